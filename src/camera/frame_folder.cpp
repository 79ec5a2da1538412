#include "smokescan/camera/frame_folder.hpp"

#include <cstdio>

#include "smokescan/io/atomic_file.hpp"

namespace smokescan {

FrameFolder::FrameFolder(std::string dir) : folder_(std::move(dir), "the frames folder", "--saturation-frames")
{
    folder_.makeFolder("ids");
}

void FrameFolder::add(uint64_t k, double camera_time_s, const Image& display, const Image& ids)
{
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06llu", (unsigned long long)k);
    writeImage(folder_.path(std::string(name) + ".png"), display);
    writeImage(folder_.path(std::string("ids/") + name + ".exr"), ids);
    char line[96];
    std::snprintf(line, sizeof line, "%s.png,%.9g\n", name, camera_time_s);
    times_ += line;
}

void FrameFolder::commit()
{
    AtomicFile f(folder_.path("timestamps.csv"));
    f.stream() << "file,time_s\n" << times_;
    f.commit();
    folder_.commit();
}

}  // namespace smokescan
