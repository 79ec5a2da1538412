#include "smokescan/camera/frame_folder.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"

namespace smokescan {

FrameFolder::FrameFolder(std::string dir) : dir_(std::move(dir))
{
    namespace fs = std::filesystem;
    struct stat st {};
    if (::lstat(dir_.c_str(), &st) == 0 && !(S_ISDIR(st.st_mode) && fs::is_empty(dir_)))
        throw Error(dir_, "exists and is not an empty folder (--saturation-frames writes a new one)");
    const fs::path parent = fs::path(dir_).parent_path();
    if (!parent.empty() && !fs::is_directory(parent)) throw Error(dir_, "cannot write (no such directory)");
    std::string tmpl = dir_ + ".tmpXXXXXX";
    if (!::mkdtemp(tmpl.data()))
        throw Error(dir_, "cannot create the frames folder: " + std::string(std::strerror(errno)));
    tmp_ = tmpl;
    registerTemporary(tmp_);
    std::error_code ec;
    fs::create_directory(fs::path(tmp_) / "ids", ec);
    if (ec) throw Error(dir_, "cannot create the frames folder: " + ec.message());
}

FrameFolder::~FrameFolder()
{
    if (done_) return;
    std::error_code ec;
    std::filesystem::remove_all(tmp_, ec);
    releaseTemporary(tmp_);
}

void FrameFolder::add(uint64_t k, double camera_time_s, const Image& display, const Image& ids)
{
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu", (unsigned long long)k);
    writeImage(tmp_ + "/" + name + ".png", display);
    writeImage(tmp_ + "/ids/" + name + ".exr", ids);
    char line[96];
    std::snprintf(line, sizeof line, "%s.png,%.9g\n", name, camera_time_s);
    times_ += line;
}
void FrameFolder::commit()
{
    AtomicFile f(tmp_ + "/timestamps.csv");
    f.stream() << "file,time_s\n" << times_;
    f.commit();
    std::error_code ec;
    std::filesystem::remove(dir_, ec);  // an empty folder given as the target
    std::filesystem::rename(tmp_, dir_, ec);
    if (ec) throw Error(dir_, "cannot move the frames into place: " + ec.message());
    releaseTemporary(tmp_);
    done_ = true;
}

}  // namespace smokescan
