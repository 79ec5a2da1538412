#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/oiio_module.hpp"

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
    const detail::OiioApi& oiio = detail::oiio();
    AtomicFile file(path);  // the temporary keeps the extension: OpenImageIO picks the writer by it
    std::string why;
    if (!oiio.write(file.tempPath(), img, lowerExt(path) == ".exr", why)) throw Error(path, why);
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
/// also returns them, so they reach the user once, in the one-line error. Readers on several
/// threads share one silence: the first in saves fd 2, the last out restores it.
class QuietStderr {
public:
    QuietStderr()
    {
        const std::lock_guard<std::mutex> lock(mutex());
        if (users()++ > 0) return;
        saved() = ::fcntl(2, F_DUPFD_CLOEXEC, 0);  // not inherited by a child started meanwhile
        const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (saved() >= 0 && null >= 0) ::dup2(null, 2);
        if (null >= 0) ::close(null);
    }
    ~QuietStderr()
    {
        const std::lock_guard<std::mutex> lock(mutex());
        if (--users() > 0 || saved() < 0) return;
        ::dup2(saved(), 2);
        ::close(saved());
        saved() = -1;
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    static std::mutex& mutex()
    {
        static std::mutex m;
        return m;
    }
    static int& users()
    {
        static int n = 0;
        return n;
    }
    static int& saved()
    {
        static int fd = -1;
        return fd;
    }
};

/// Whether smokescan reads an image of this size (docs/limits.md).
bool admitFrame(const Image& h, std::string& why)
{
    if (h.width > 0 && h.height > 0 && h.channels > 0 && h.channels <= 64 && h.width <= limits::kFrameSide &&
        h.height <= limits::kFrameSide && int64_t(h.width) * h.height <= limits::kFramePixels)
        return true;
    why = "is " + std::to_string(h.width) + "x" + std::to_string(h.height) + " with " + std::to_string(h.channels) +
        " channels, beyond what smokescan reads (docs/limits.md)";
    return false;
}

}  // namespace

Image readImage(const std::string& path)
{
    if (!fs::exists(path)) throw Error(path, "no such file");
    if (fs::is_directory(path)) throw Error(path, "is a folder, not an image");
    const detail::OiioApi& oiio = detail::oiio();
    QuietStderr quiet;
    Image img;
    std::string why;
    if (!oiio.read(path, img, admitFrame, why)) throw Error(path, oneLine(why));
    return img;
}

}  // namespace smokescan
