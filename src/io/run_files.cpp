#include "smokescan/io/run_files.hpp"

#include <sys/stat.h>

#include <filesystem>

#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"

namespace smokescan {
namespace {
namespace fs = std::filesystem;

/// A file's identity: (device, inode) of the file, or for a file not yet made, of its folder
/// plus its name.
struct FileId {
    dev_t dev = 0;
    ino_t ino = 0;
    std::string name;  ///< "" for an existing file
    bool device = false;
    bool operator==(const FileId& o) const { return dev == o.dev && ino == o.ino && name == o.name; }
};

bool identify(const std::string& path, FileId& id)
{
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) {
        id = {st.st_dev, st.st_ino, "", S_ISCHR(st.st_mode)};
        return true;
    }
    const fs::path p(path);
    const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
    if (::stat(dir.c_str(), &st) != 0) return false;
    id = {st.st_dev, st.st_ino, p.filename().string(), false};
    return true;
}

}  // namespace

RunFiles::RunFiles() = default;
RunFiles::~RunFiles() = default;  // uncommitted AtomicFiles remove their temporaries

void RunFiles::input(const std::string& path, const std::string& option)
{
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0) return;
    inputs_.emplace_back(path, option);
}

void RunFiles::output(const std::string& path, const std::string& option)
{
    if (path.empty()) return;
    checkOutputPath(path);
    record(path, option);
}

void RunFiles::outputFolder(const std::string& path, const std::string& option)
{
    std::string p = path;
    while (p.size() > 1 && p.back() == '/') p.pop_back();  // "diag/" is the folder diag
    if (!p.empty()) record(p, option);
}

void RunFiles::record(const std::string& path, const std::string& option)
{
    FileId me;
    if (!identify(path, me)) throw Error(path, "cannot write (no such directory)");
    for (const auto& [p, opt] : inputs_) {
        FileId other;
        if (identify(p, other) && other == me)
            throw Error(path, "is the input of " + opt + " (" + p + "); " + option + " would destroy it");
    }
    if (!me.device) {
        const auto [it, fresh] =
            output_ids_.emplace(std::make_tuple(uint64_t(me.dev), uint64_t(me.ino), me.name), option);
        if (!fresh)
            throw Error(path, "is named by both " + it->second + " and " + option + "; give each output its own file");
    }
    outputs_.emplace_back(path, option);
}

std::string RunFiles::stage(const std::string& path)
{
    staged_.push_back(std::make_unique<AtomicFile>(path));
    return staged_.back()->tempPath();
}

void RunFiles::commit()
{
    // Devices and pipes first: a write into one can fail (/dev/full) and cannot be taken back, so
    // the files are renamed into place only once every device took its content.
    for (auto& f : staged_)
        if (f->isDevice()) f->commit();
    for (auto& f : staged_)
        if (!f->isDevice()) f->commit();
}

}  // namespace smokescan
