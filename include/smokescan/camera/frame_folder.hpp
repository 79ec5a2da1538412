#pragma once
/// @file frame_folder.hpp
/// @brief A folder of rendered camera frames, written whole or not at all: FOLDER/frame_NNNNNN.png
/// (what the camera delivers), FOLDER/ids/frame_NNNNNN.exr (object, material, depth) and
/// FOLDER/timestamps.csv (file, camera-clock time), the input `smokescan saturation --ids
/// --timestamps` reads. Frames go into a temporary folder that replaces FOLDER on commit().
#include <cstdint>
#include <string>

#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/image.hpp"

namespace smokescan {

class FrameFolder {
public:
    /// @throw Error when `dir` exists and is not an empty folder, or cannot be created.
    explicit FrameFolder(std::string dir);

    /// @brief Frame k, delivered at camera time camera_time_s [s], with its id image.
    void add(uint64_t k, double camera_time_s, const Image& display, const Image& ids);
    /// @brief Writes the timestamps and moves the folder into place.
    void commit();

private:
    AtomicFolder folder_;  ///< removed unless committed
    std::string times_;
};

}  // namespace smokescan
