#pragma once
// A white canvas for the calibration and fit plots, drawn with OpenImageIO's ImageBufAlgo (internal).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <string>

#include "smokescan/render/image.hpp"

namespace smokescan {

using Col = std::array<float, 3>;

class Canvas {
public:
    Canvas(int w, int h) : buf_(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT))
    {
        const float white[3] = {1, 1, 1};
        OIIO::ImageBufAlgo::fill(buf_, white);
    }
    void line(int x0, int y0, int x1, int y1, const Col& c) { OIIO::ImageBufAlgo::render_line(buf_, x0, y0, x1, y1, c); }
    void box(int x0, int y0, int x1, int y1, const Col& c, bool fill)
    {
        OIIO::ImageBufAlgo::render_box(buf_, x0, y0, x1, y1, c, fill);
    }
    void text(int x, int y, const std::string& s, int size = 14, const Col& c = {0, 0, 0})
    {
        // Text needs a font; a missing font leaves the plot without labels rather than failing.
        OIIO::ImageBufAlgo::render_text(buf_, x, y, s, size, "DejaVuSans", c);
    }
    Image image() const
    {
        Image img(buf_.spec().width, buf_.spec().height, 3);
        buf_.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, img.data.data());
        for (float& v : img.data) v = std::clamp(v, 0.0f, 1.0f);
        return img;
    }

private:
    OIIO::ImageBuf buf_;
};

}  // namespace smokescan
