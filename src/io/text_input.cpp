#include "smokescan/io/text_input.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "smokescan/core/error.hpp"

namespace smokescan {

std::string readTextInput(const std::string& path, const std::string& what, size_t max_bytes)
{
    return readInputBytes(path, what, max_bytes, true);
}

std::string readInputBytes(const std::string& path, const std::string& what, size_t max_bytes, bool text_only)
{
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw Error(path, "no such " + what);
    if (S_ISDIR(st.st_mode)) throw Error(path, "is a folder, not a " + what);
    if (S_ISREG(st.st_mode) && size_t(st.st_size) > max_bytes)
        throw Error(path,
                    "is " + std::to_string(st.st_size >> 20) + " MiB, over the " + std::to_string(max_bytes >> 20) +
                        " MiB a " + what + " may have");
    // A FIFO without a writer would block open(): opened without waiting, it reads as empty.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (S_ISFIFO(st.st_mode) ? O_NONBLOCK : 0));
    if (fd < 0) throw Error(path, "cannot read (" + std::string(std::strerror(errno)) + ")");
    if (S_ISFIFO(st.st_mode)) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    std::string text;
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(fd);
            throw Error(path, "cannot read (" + std::string(std::strerror(e)) + ")");
        }
        if (const void* nul = text_only ? std::memchr(buf, '\0', size_t(n)) : nullptr) {
            ::close(fd);
            const size_t at = text.size() + size_t(static_cast<const char*>(nul) - buf);
            throw Error(path, "is not text (a NUL byte at byte " + std::to_string(at) + "); expected a " + what);
        }
        if (text.size() + size_t(n) > max_bytes) {
            ::close(fd);
            throw Error(path,
                        "gives more than the " + std::to_string(max_bytes >> 20) + " MiB a " + what + " may have");
        }
        text.append(buf, size_t(n));
    }
    ::close(fd);
    return text;
}

double parseFiniteNumber(const std::string& text, const std::string& where)
{
    char* end = nullptr;
    const double x = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(x)) throw Error(where, "'" + text + "' is not a finite number");
    return x;
}

std::vector<double> parseNumberList(const std::string& text, const std::string& what)
{
    std::vector<double> v;
    std::stringstream ss(text);
    std::string tok;
    while (std::getline(ss, tok, ',')) v.push_back(parseFiniteNumber(tok, what));
    return v;
}

}  // namespace smokescan
