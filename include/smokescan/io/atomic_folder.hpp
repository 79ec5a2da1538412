#pragma once
/// @file atomic_folder.hpp
/// @brief A new output folder written whole or not at all: its files go into a temporary folder
/// beside it, which replaces it on commit(); destroyed uncommitted (an error, a signal), nothing
/// is left. The target must not exist, or be an empty folder.
#include <string>

namespace smokescan {

class AtomicFolder {
public:
    /// @param dir the folder to make; @param what what it holds, for errors ("the frames folder")
    /// @param option the option that named it ("--saturation-frames"), for errors
    /// @throw Error when dir exists and is not an empty folder, or cannot be created.
    AtomicFolder(std::string dir, std::string what, const std::string& option);
    ~AtomicFolder();
    AtomicFolder(const AtomicFolder&) = delete;
    AtomicFolder& operator=(const AtomicFolder&) = delete;

    /// @brief Where to write `relative` (a file or a subfolder) until commit().
    std::string path(const std::string& relative) const { return tmp_ + "/" + relative; }
    /// @brief The path `relative` will have once committed (for messages).
    std::string finalPath(const std::string& relative) const { return dir_ + "/" + relative; }
    /// @brief Makes the subfolder `relative`.
    void makeFolder(const std::string& relative);
    /// @brief Moves the folder into place.
    void commit();

private:
    std::string dir_, what_, tmp_;
    bool done_ = false;
};

}  // namespace smokescan
