#include <OpenImageIO/imageio.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"

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
        throw Error(path,
                    "cannot write (" + (why.empty() ? std::string("directory missing or not writable") : why) + ")");
    }
    file.commit();
}

namespace {

/// OpenImageIO's messages, on one line ("a\nb" → "a; b").
std::string oneLine(std::string m)
{
    while (!m.empty() && (m.back() == '\n' || m.back() == '\r')) m.pop_back();
    for (size_t p; (p = m.find('\n')) != std::string::npos;) m.replace(p, 1, "; ");
    return m;
}

/// Silences stderr while a reader runs: libpng prints its errors there itself, and OpenImageIO
/// also returns them, so they reach the user once, in the one-line error.
class QuietStderr {
public:
    QuietStderr() : saved_(::dup(2))
    {
        const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
        if (null >= 0) ::close(null);
    }
    ~QuietStderr()
    {
        if (saved_ < 0) return;
        ::dup2(saved_, 2);
        ::close(saved_);
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    int saved_;
};

}  // namespace

Image readImage(const std::string& path)
{
    if (!fs::exists(path)) throw Error(path, "no such file");
    if (fs::is_directory(path)) throw Error(path, "is a folder, not an image");
    QuietStderr quiet;
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error(path, "cannot read as an image (" + oneLine(OIIO::geterror()) + ")");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.nchannels > 64 ||
        spec.width > limits::kFrameSide || spec.height > limits::kFrameSide ||
        int64_t(spec.width) * spec.height > limits::kFramePixels)
        throw Error(path,
                    "is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + " with " +
                        std::to_string(spec.nchannels) + " channels, beyond what smokescan reads (docs/limits.md)");
    Image img(spec.width, spec.height, spec.nchannels);
    img.channel_names = spec.channelnames;
    const bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.data.data());
    const std::string why = oneLine(in->geterror());
    in->close();
    if (!ok) throw Error(path, "cannot read pixels (" + why + ")");
    return img;
}

}  // namespace smokescan
