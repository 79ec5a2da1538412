#include "smokescan/io/atomic_file.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "smokescan/core/error.hpp"

namespace smokescan {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path))
{
    tmp_ = path_ + ".tmp." + std::to_string(::getpid());
    if (std::filesystem::is_directory(path_)) throw Error(path_, "is a directory");
    out_.open(tmp_, std::ios::out | std::ios::trunc);
    if (!out_) throw Error(path_, "cannot write (directory missing or not writable)");
}

AtomicFile::~AtomicFile()
{
    if (!done_) {
        out_.close();
        std::remove(tmp_.c_str());
    }
}

void AtomicFile::commit()
{
    out_.flush();
    const bool ok = bool(out_);
    out_.close();
    if (!ok) throw Error(path_, "write failed");
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) throw Error(path_, "cannot write (" + ec.message() + ")");
    done_ = true;
}

}  // namespace smokescan
