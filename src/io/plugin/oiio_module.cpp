// libsmokescan_oiio.so: smokescan's calls into OpenImageIO, opened on first use
// (include/smokescan/io/oiio_module.hpp says why). Nothing here throws: each function says why it failed.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "smokescan/io/oiio_module.hpp"

namespace smokescan::detail {
namespace {

bool writeImageFile(const std::string& path, const Image& img, bool as_float, std::string& why)
{
    try {
        OIIO::ImageSpec spec(img.width, img.height, img.channels,
                             as_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        if (!img.channel_names.empty()) spec.channelnames = img.channel_names;
        if (!as_float) spec.attribute("oiio:ColorSpace", "sRGB");
        auto out = OIIO::ImageOutput::create(path);
        if (!out) {
            why = "no image writer for this format (" + OIIO::geterror() + ")";
            return false;
        }
        bool ok = out->open(path, spec);
        if (ok) {
            if (as_float) {
                ok = out->write_image(OIIO::TypeDesc::FLOAT, img.data.data());
            } else {
                std::vector<unsigned char> q(img.data.size());
                for (size_t i = 0; i < q.size(); ++i) {
                    const float v = std::isfinite(img.data[i]) ? std::clamp(img.data[i], 0.0f, 1.0f) : 0.0f;
                    q[i] = (unsigned char)std::lround(v * 255.0f);
                }
                ok = out->write_image(OIIO::TypeDesc::UINT8, q.data());
            }
            ok = out->close() && ok;
        }
        if (!ok) {
            const std::string w = out->geterror();
            why = "cannot write (" + (w.empty() ? std::string("directory missing or not writable") : w) + ")";
        }
        return ok;
    } catch (const std::exception& e) {
        why = std::string("cannot write (") + e.what() + ")";
        return false;
    }
}

bool readImageFile(const std::string& path, Image& img, bool (*admit)(const Image&, std::string&), std::string& why)
{
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) {
            why = "cannot read as an image (" + OIIO::geterror() + ")";
            return false;
        }
        const OIIO::ImageSpec& spec = in->spec();
        if (spec.depth != 1 || spec.deep) {
            why = spec.deep ? "is a deep image, not a picture"
                            : "is a " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" +
                    std::to_string(spec.depth) + " volume, not a picture";
            return false;
        }
        img.width = spec.width;
        img.height = spec.height;
        img.channels = spec.nchannels;
        img.channel_names = spec.channelnames;
        if (!admit(img, why)) return false;
        img.data.assign(size_t(img.width) * size_t(img.height) * size_t(img.channels), 0.0f);
        const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.data.data());
        if (!ok) why = "cannot read pixels (" + in->geterror() + ")";
        in->close();
        return ok;
    } catch (const std::exception& e) {
        why = std::string("cannot read as an image (") + e.what() + ")";
        return false;
    }
}

/// The image's floats as an ImageBuf (drawn on in place).
OIIO::ImageBuf wrap(Image& img)
{
    return OIIO::ImageBuf(OIIO::ImageSpec(img.width, img.height, img.channels, OIIO::TypeDesc::FLOAT), img.data.data());
}

// Drawing is best effort: a plot missing a stroke is better than a run that ends (nothing is thrown).
void drawLine(Image& img, int x0, int y0, int x1, int y1, const float* rgb)
{
    try {
        OIIO::ImageBuf b = wrap(img);
        OIIO::ImageBufAlgo::render_line(b, x0, y0, x1, y1, {rgb, 3});
    } catch (...) {
    }
}

void drawBox(Image& img, int x0, int y0, int x1, int y1, const float* rgb, bool fill)
{
    try {
        OIIO::ImageBuf b = wrap(img);
        OIIO::ImageBufAlgo::render_box(b, x0, y0, x1, y1, {rgb, 3}, fill);
    } catch (...) {
    }
}

bool textExtent(const std::string& s, int size, int extent[4])
{
    try {
        const OIIO::ROI ext = OIIO::ImageBufAlgo::text_size(s, size, "DejaVuSans");
        if (!ext.defined() || ext.xend <= ext.xbegin || ext.yend <= ext.ybegin) return false;
        extent[0] = ext.xbegin;
        extent[1] = ext.xend;
        extent[2] = ext.ybegin;
        extent[3] = ext.yend;
        return true;
    } catch (...) {
        return false;
    }
}

void drawText(Image& img, int x, int y, const std::string& s, int size, const float* rgb)
{
    try {
        OIIO::ImageBuf b = wrap(img);
        OIIO::ImageBufAlgo::render_text(b, x, y, s, size, "DejaVuSans", {rgb, 3});
    } catch (...) {
    }
}

const OiioApi kApi{kOiioApiVersion, writeImageFile, readImageFile, drawLine, drawBox, textExtent, drawText};

}  // namespace
}  // namespace smokescan::detail

extern "C" __attribute__((visibility("default"))) const smokescan::detail::OiioApi* smokescan_oiio_api()
{
    return &smokescan::detail::kApi;
}
