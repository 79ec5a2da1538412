#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/render/image.hpp"

namespace smokescan {
namespace fs = std::filesystem;

namespace {
std::string lowerExt(const std::string& path)
{
    std::string e = fs::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}
}  // namespace

bool isImageExtension(const std::string& path)
{
    const std::string e = lowerExt(path);
    return e == ".exr" || e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".tif" || e == ".tiff";
}

void writeImage(const std::string& path, const Image& img)
{
    if (!isImageExtension(path))
        throw Error(path, "unknown image format '" + lowerExt(path) + "' (exr, png, jpg, tif)");
    if (img.width <= 0 || img.height <= 0 || img.channels <= 0) throw Error(path, "empty image");
    AtomicFile file(path);  // the temporary keeps the extension: OpenImageIO picks the writer by it
    const std::string& tmp = file.tempPath();
    const bool is_float = lowerExt(path) == ".exr";
    OIIO::ImageSpec spec(img.width, img.height, img.channels, is_float ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!img.channel_names.empty()) spec.channelnames = img.channel_names;
    if (!is_float) spec.attribute("oiio:ColorSpace", "sRGB");
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out) throw Error(path, "no image writer for this format (" + OIIO::geterror() + ")");
    bool ok = out->open(tmp, spec);
    if (ok) {
        if (is_float) {
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
        const std::string why = out->geterror();
        throw Error(path, "cannot write (" + (why.empty() ? std::string("directory missing or not writable") : why) + ")");
    }
    file.commit();
}

Image readImage(const std::string& path)
{
    if (!fs::exists(path)) throw Error(path, "no such file");
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(path, "cannot read as an image (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = in->spec();
    Image img(spec.width, spec.height, spec.nchannels);
    img.channel_names = spec.channelnames;
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.data.data());
    const std::string why = in->geterror();
    in->close();
    if (!ok) throw Error(path, "cannot read pixels (" + why + ")");
    return img;
}

}  // namespace smokescan
