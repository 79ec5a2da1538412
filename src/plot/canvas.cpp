#include "smokescan/plot/canvas.hpp"

#include <algorithm>

#include "smokescan/io/oiio_module.hpp"

namespace smokescan {

struct Canvas::Impl {
    Image img;
    const detail::OiioApi& oiio = detail::oiio();  // loaded when the first canvas is made
};

Canvas::Canvas(int w, int h) : impl_(std::make_unique<Impl>())
{
    impl_->img = Image(w, h, 3);
    std::fill(impl_->img.data.begin(), impl_->img.data.end(), 1.0f);  // white
}

Canvas::~Canvas() = default;

void Canvas::line(int x0, int y0, int x1, int y1, const Col& c)
{
    impl_->oiio.line(impl_->img, x0, y0, x1, y1, c.data());
}

void Canvas::box(int x0, int y0, int x1, int y1, const Col& c, bool fill)
{
    impl_->oiio.box(impl_->img, x0, y0, x1, y1, c.data(), fill);
}

void Canvas::text(int x, int y, const std::string& s, int size, const Col& c)
{
    // OpenImageIO asserts on text drawn past the image's edge (a long legend, a crowded key):
    // text that does not fit whole is left out, so that a plot never aborts a run.
    if (s.empty()) return;
    int ext[4];  // x begin, x end, y begin, y end
    if (!impl_->oiio.textSize(s, size, ext)) return;  // no glyphs (or no font)
    const long long x0 = (long long)x + ext[0], x1 = (long long)x + ext[1];
    const long long y0 = (long long)y + ext[2], y1 = (long long)y + ext[3];
    if (x0 < 0 || y0 < 0 || x1 > impl_->img.width || y1 > impl_->img.height) return;
    impl_->oiio.text(impl_->img, x, y, s, size, c.data());
}

Image Canvas::image() const
{
    Image img = impl_->img;
    for (float& v : img.data) v = std::clamp(v, 0.0f, 1.0f);
    return img;
}

}  // namespace smokescan
