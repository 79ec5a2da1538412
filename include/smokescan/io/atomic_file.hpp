#pragma once
/// @file atomic_file.hpp
/// @brief An output file that appears only when complete: written to "PATH.tmp.PID", renamed on
/// commit(), removed if destroyed uncommitted (an error midway leaves no partial output).
#include <fstream>
#include <string>

namespace smokescan {

class AtomicFile {
public:
    /// @throw Error naming `path` when the temporary cannot be created.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::ostream& stream() { return out_; }
    /// @throw Error when writing or renaming failed.
    void commit();

private:
    std::string path_, tmp_;
    std::ofstream out_;
    bool done_ = false;
};

}  // namespace smokescan
