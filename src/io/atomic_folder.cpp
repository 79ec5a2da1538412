#include "smokescan/io/atomic_folder.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"

namespace smokescan {

namespace fs = std::filesystem;

AtomicFolder::AtomicFolder(std::string dir, std::string what, const std::string& option)
    : dir_(std::move(dir)), what_(std::move(what))
{
    if (dir_.empty()) throw Error(option, "names no folder");
    while (dir_.size() > 1 && dir_.back() == '/') dir_.pop_back();  // "diag/" is the folder diag
    const std::string name = fs::path(dir_).filename().string();
    if (name == "." || name == "..")
        throw Error(dir_, "names its folder by '" + name + "'; give the folder's own name (" + option + ")");
    if (name.size() > 255) throw Error(dir_, "has a name of " + std::to_string(name.size()) + " bytes (at most 255)");
    struct stat st {};
    if (::lstat(dir_.c_str(), &st) == 0) {
        if (S_ISLNK(st.st_mode)) throw Error(dir_, "is a symbolic link (" + option + " writes a new folder)");
        if (!S_ISDIR(st.st_mode)) throw Error(dir_, "exists and is not a folder (" + option + " writes a new one)");
        if (!fs::is_empty(dir_))
            throw Error(dir_, "exists and is not an empty folder (" + option + " writes a new one)");
    }
    const fs::path parent = fs::path(dir_).parent_path();
    if (!parent.empty() && !fs::is_directory(parent)) throw Error(dir_, "cannot write (no such directory)");
    // The temporary's name: the target's, cut so that its suffix still fits in 255 bytes.
    std::string base = fs::path(dir_).filename().string();
    if (base.size() > 245) base.resize(245);
    std::string tmpl = (parent.empty() ? fs::path(base) : parent / base).string() + ".tmpXXXXXX";
    if (!::mkdtemp(tmpl.data())) throw Error(dir_, "cannot create " + what_ + ": " + std::string(std::strerror(errno)));
    tmp_ = tmpl;
    registerTemporary(tmp_);
    // mkdtemp makes it 0700; the folder gets the mode a new folder would (0777 less the umask).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::chmod(tmp_.c_str(), 0777 & ~mask);
}

AtomicFolder::~AtomicFolder()
{
    if (done_) return;
    std::error_code ec;
    fs::remove_all(tmp_, ec);
    releaseTemporary(tmp_);
}

void AtomicFolder::makeFolder(const std::string& relative)
{
    std::error_code ec;
    fs::create_directory(fs::path(tmp_) / relative, ec);
    if (ec) throw Error(dir_, "cannot create " + what_ + ": " + ec.message());
}

void AtomicFolder::commit()
{
    // What appeared at the target during the run is refused as at the start, never removed:
    // only an empty folder is replaced (rmdir removes nothing else).
    struct stat st {};
    if (::lstat(dir_.c_str(), &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            throw Error(dir_, "appeared during the run and is not an empty folder; not replacing it");
        if (::rmdir(dir_.c_str()) != 0) {
            const int e = errno;
            if (e == ENOTEMPTY || e == EEXIST)
                throw Error(dir_, "appeared during the run and is not an empty folder; not replacing it");
            throw Error(dir_, "cannot replace the empty folder (" + std::string(std::strerror(e)) + ")");
        }
    }
    std::error_code ec;
    fs::rename(tmp_, dir_, ec);
    if (ec) throw Error(dir_, "cannot move " + what_ + " into place: " + ec.message());
    releaseTemporary(tmp_);
    done_ = true;
}

}  // namespace smokescan
