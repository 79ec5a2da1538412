#include "smokescan/io/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <vector>

#include "smokescan/core/error.hpp"

namespace smokescan {
namespace fs = std::filesystem;
namespace {

// ---- temporaries removed on a signal ----

constexpr size_t kSlots = 8192;
std::atomic<char*> g_temps[kSlots];
std::mutex g_temps_mutex;

/// Removes a file, or a folder and what is below it (the frames folder is two levels deep).
/// Runs in a signal handler that ends the process: plain system calls only, no allocation.
void removeTree(const char* path, int depth)
{
    if (::unlink(path) == 0 || errno != EISDIR) return;
    if (DIR* d = depth > 0 ? ::opendir(path) : nullptr) {
        char child[4096];
        while (const dirent* e = ::readdir(d)) {
            if (!std::strcmp(e->d_name, ".") || !std::strcmp(e->d_name, "..")) continue;
            if (std::snprintf(child, sizeof child, "%s/%s", path, e->d_name) < int(sizeof child))
                removeTree(child, depth - 1);
        }
        ::closedir(d);
    }
    ::rmdir(path);
}

extern "C" void removeTemporariesAndDie(int sig)
{
    for (auto& slot : g_temps)
        if (char* p = slot.load()) removeTree(p, 3);
    ::signal(sig, SIG_DFL);
    ::raise(sig);
}

std::atomic<bool> g_host_signals{false};

void installHandlers()
{
    if (g_host_signals.load()) return;
    static std::once_flag once;
    std::call_once(once, [] {
        struct sigaction sa {};
        sa.sa_handler = removeTemporariesAndDie;
        sigemptyset(&sa.sa_mask);
        // SIGPIPE too: a reader that closes early (`smokescan ... | head -c 1`) ends the run
        // as it would have, but without a temporary left behind; SIGQUIT (Ctrl-\) and SIGXFSZ
        // (a file-size limit) likewise, before their core dump.
        for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT, SIGXFSZ}) {
            struct sigaction old {};
            ::sigaction(sig, nullptr, &old);
            if (old.sa_handler != SIG_IGN) ::sigaction(sig, &sa, nullptr);  // keep nohup's choice
        }
    });
}

/// The process's umask, read once (the temporaries get the mode a new file would have had).
mode_t processUmask()
{
    static const mode_t m = [] {
        const mode_t u = ::umask(0);
        ::umask(u);
        return u;
    }();
    return m;
}

/// A new, exclusively created file "DIR/STEM.tmpXXXXXX.EXT"; returns its name.
std::string makeTemporary(const fs::path& dir, const fs::path& target)
{
    const std::string ext = target.extension().string();
    // The stem is shortened so that a name near the file system's limit (255 bytes) still has
    // room for the temporary's suffix; an extension that leaves none is refused as the target's.
    std::string stem = target.stem().string();
    const size_t room = 255 > ext.size() + 10 ? 255 - ext.size() - 10 : 0;
    if (room == 0) throw Error(target.string(), "cannot write (file name too long)");
    if (stem.size() > room) stem.resize(room);
    std::string name = (dir / (stem + ".tmpXXXXXX" + ext)).string();
    std::vector<char> buf(name.begin(), name.end());
    buf.push_back('\0');
    const int fd = ::mkostemps(buf.data(), int(ext.size()), O_CLOEXEC);
    if (fd < 0) throw Error(target.string(), std::string("cannot write (") + std::strerror(errno) + ")");
    ::fchmod(fd, 0666 & ~processUmask());
    ::close(fd);
    name.assign(buf.data());
    registerTemporary(name);
    return name;
}

/// Copies the file `from` into the open descriptor `fd`, checking every write.
void copyInto(const std::string& from, int fd, const std::string& target)
{
    const int in = ::open(from.c_str(), O_RDONLY | O_CLOEXEC);
    if (in < 0) throw Error(target, std::string("write failed (") + std::strerror(errno) + ")");
    std::vector<char> buf(1 << 16);
    for (;;) {
        const ssize_t n = ::read(in, buf.data(), buf.size());
        if (n == 0) break;
        if (n < 0) {
            if (errno == EINTR) continue;
            const int e = errno;
            ::close(in);
            throw Error(target, std::string("write failed (") + std::strerror(e) + ")");
        }
        for (ssize_t done = 0; done < n;) {
            const ssize_t w = ::write(fd, buf.data() + done, size_t(n - done));
            if (w < 0 && errno == EINTR) continue;
            if (w <= 0) {
                const int e = w < 0 ? errno : EIO;
                ::close(in);
                throw Error(target, std::string("write failed (") + std::strerror(e) + ")");
            }
            done += w;
        }
    }
    ::close(in);
}

/// Where the outputs naming the process's standard output write, once divertStdout() moved it.
std::atomic<int> g_stdout_fd{1};

/// The descriptor number a path of the process's own streams names, or −1.
int streamNumber(const std::string& path)
{
    if (path == "/dev/stdout") return 1;
    if (path == "/dev/stderr") return 2;
    for (const char* prefix : {"/dev/fd/", "/proc/self/fd/"})
        if (path.rfind(prefix, 0) == 0) {
            const std::string n = path.substr(std::strlen(prefix));
            if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos) return -1;
            return std::atoi(n.c_str());
        }
    return -1;
}
bool isOwnStream(const std::string& path) { return ownStreamFd(path) >= 0; }

}  // namespace

int ownStreamFd(const std::string& path)
{
    const int n = streamNumber(path);
    return n == 1 ? g_stdout_fd.load() : n;
}

bool divertStdout()
{
    std::fflush(stdout);
    const int kept = ::fcntl(1, F_DUPFD_CLOEXEC, 3);
    if (kept < 0) return false;
    if (::dup2(2, 1) < 0) {
        ::close(kept);
        return false;
    }
    g_stdout_fd = kept;
    return true;
}

void leaveSignalsToHost() { g_host_signals.store(true); }

void registerTemporary(const std::string& path)
{
    installHandlers();
    char* copy = new char[path.size() + 1];
    std::memcpy(copy, path.c_str(), path.size() + 1);
    std::lock_guard<std::mutex> lock(g_temps_mutex);
    for (auto& slot : g_temps)
        if (!slot.load()) {
            slot.store(copy);
            return;
        }
    delete[] copy;  // all slots taken: this one is still removed by its owner, only not on a signal
}

void releaseTemporary(const std::string& path)
{
    std::lock_guard<std::mutex> lock(g_temps_mutex);
    for (auto& slot : g_temps)
        if (char* p = slot.load(); p && path == p) {
            slot.store(nullptr);
            delete[] p;
            return;
        }
}

bool checkOutputPath(const std::string& path)
{
    if (path.empty()) throw Error("output", "empty file name");
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode)) {
            // A link to a device or pipe is written into, like the device; so is whatever one of
            // the process's own streams leads to (/dev/stdout > FILE: appended to).
            struct stat to {};
            if (isOwnStream(path)) {
                if (::fstat(ownStreamFd(path), &to) != 0)
                    throw Error(path, "is not open (the program's stream was closed)");
                if (S_ISDIR(to.st_mode)) throw Error(path, "leads to a directory");
                return true;
            }
            if (::stat(path.c_str(), &to) == 0 && (S_ISCHR(to.st_mode) || S_ISFIFO(to.st_mode))) return true;
            throw Error(path, "is a symbolic link; smokescan does not replace links (name the file it points to)");
        }
        if (S_ISDIR(st.st_mode)) throw Error(path, "is a directory");
        if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return true;
        if (!S_ISREG(st.st_mode))
            throw Error(path, "is not a regular file, character device or FIFO; not replacing it");
        return false;
    }
    const fs::path dir = fs::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec)) throw Error(path, "cannot write (no such directory)");
    return false;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path))
{
    device_ = checkOutputPath(path_);
    const fs::path target(path_);
    std::error_code ec;
    const fs::path dir = device_ ? fs::temp_directory_path(ec) : target.parent_path();
    tmp_ = makeTemporary(dir.empty() ? fs::path(".") : dir, target);
}

AtomicFile::~AtomicFile()
{
    if (done_) return;
    if (out_.is_open()) out_.close();
    std::remove(tmp_.c_str());
    releaseTemporary(tmp_);
}

std::ostream& AtomicFile::stream()
{
    if (!out_.is_open()) {
        out_.open(tmp_, std::ios::out | std::ios::trunc | std::ios::binary);
        if (!out_) throw Error(path_, "cannot write (" + std::string(std::strerror(errno)) + ")");
    }
    return out_;
}

void AtomicFile::commit()
{
    if (done_) return;
    if (out_.is_open()) {
        out_.flush();
        const bool ok = bool(out_);
        const int e = errno;
        out_.close();
        if (!ok || out_.fail())
            throw Error(path_, std::string("write failed (") + (ok ? "close" : std::strerror(e)) + ")");
    }
    if (device_) {
        // One of the process's own streams is written through its descriptor, so that what the
        // program printed before and prints after stays in order (a file behind `> FILE` has one
        // offset for all); any other device or pipe is opened.
        const int own = ownStreamFd(path_);
        if (own >= 0) {
            std::fflush(nullptr);
            copyInto(tmp_, own, path_);
            std::remove(tmp_.c_str());
            releaseTemporary(tmp_);
            done_ = true;
            return;
        }
        const int fd = ::open(path_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
        if (fd < 0) throw Error(path_, std::string("cannot write (") + std::strerror(errno) + ")");
        try {
            copyInto(tmp_, fd, path_);
        } catch (...) {
            ::close(fd);
            throw;
        }
        if (::close(fd) != 0 && errno != EINTR)
            throw Error(path_, std::string("write failed (") + std::strerror(errno) + ")");
        std::remove(tmp_.c_str());
    } else {
        // The target may have become a link or folder since the check: refuse rather than replace.
        checkOutputPath(path_);
        if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
            throw Error(path_, std::string("cannot write (") + std::strerror(errno) + ")");
    }
    releaseTemporary(tmp_);
    done_ = true;
}

}  // namespace smokescan
