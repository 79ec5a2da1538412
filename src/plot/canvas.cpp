#include "smokescan/plot/canvas.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>

namespace smokescan {

struct Canvas::Impl {
    OIIO::ImageBuf buf;
};

Canvas::Canvas(int w, int h) : impl_(std::make_unique<Impl>())
{
    impl_->buf.reset(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT));
    const float white[3] = {1, 1, 1};
    OIIO::ImageBufAlgo::fill(impl_->buf, white);
}

Canvas::~Canvas() = default;

void Canvas::line(int x0, int y0, int x1, int y1, const Col& c)
{
    OIIO::ImageBufAlgo::render_line(impl_->buf, x0, y0, x1, y1, c);
}

void Canvas::box(int x0, int y0, int x1, int y1, const Col& c, bool fill)
{
    OIIO::ImageBufAlgo::render_box(impl_->buf, x0, y0, x1, y1, c, fill);
}

void Canvas::text(int x, int y, const std::string& s, int size, const Col& c)
{
    // OpenImageIO asserts on text drawn past the image's edge (a long legend, a crowded key):
    // text that does not fit whole is left out, so that a plot never aborts a run.
    if (s.empty()) return;
    const OIIO::ROI ext = OIIO::ImageBufAlgo::text_size(s, size, "DejaVuSans");
    if (!ext.defined() || ext.xend <= ext.xbegin || ext.yend <= ext.ybegin) return;  // no glyphs (or no font)
    const OIIO::ImageSpec& sp = impl_->buf.spec();
    const long long x0 = (long long)x + ext.xbegin, x1 = (long long)x + ext.xend;
    const long long y0 = (long long)y + ext.ybegin, y1 = (long long)y + ext.yend;
    if (x0 < 0 || y0 < 0 || x1 > sp.width || y1 > sp.height) return;
    OIIO::ImageBufAlgo::render_text(impl_->buf, x, y, s, size, "DejaVuSans", c);
}

Image Canvas::image() const
{
    const OIIO::ImageBuf& b = impl_->buf;
    Image img(b.spec().width, b.spec().height, 3);
    b.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, img.data.data());
    for (float& v : img.data) v = std::clamp(v, 0.0f, 1.0f);
    return img;
}

}  // namespace smokescan
