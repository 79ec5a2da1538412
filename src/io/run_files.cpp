#include "smokescan/io/run_files.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

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
    const int own = ownStreamFd(path);  // /dev/stdout: the file behind the stream, wherever it went
    if (own >= 0 ? ::fstat(own, &st) == 0 : ::stat(path.c_str(), &st) == 0) {
        id = {st.st_dev, st.st_ino, "", S_ISCHR(st.st_mode)};
        return true;
    }
    const fs::path p(path);
    const std::string dir = p.parent_path().empty() ? "." : p.parent_path().string();
    if (::stat(dir.c_str(), &st) != 0) return false;
    id = {st.st_dev, st.st_ino, p.filename().string(), false};
    return true;
}

using Named = std::vector<std::pair<std::string, std::string>>;  // (path, the option that named it)

/// The entry of `files` that is the file `me`, or null.
const std::pair<std::string, std::string>* sameFile(const FileId& me, const Named& files)
{
    for (const auto& f : files) {
        FileId other;
        if (identify(f.first, other) && other == me) return &f;
    }
    return nullptr;
}

/// The error of an output that is an input.
Error destroys(const std::string& out, const std::string& out_option, const std::string& in,
               const std::string& in_option)
{
    return Error(out, "is the input of " + in_option + " (" + in + "); " + out_option + " would destroy it");
}

/// A second name for `path`'s file in its folder (".smokescan-keep-PID-N"), removed on a signal
/// until released; "" where the file system makes no hard links (the file is then replaced
/// without a way back, as before).
std::string keepLink(const std::string& path)
{
    const fs::path dir = fs::path(path).parent_path();
    for (int n = 0; n < 1000; ++n) {
        const std::string keep =
            (dir / (".smokescan-keep-" + std::to_string(::getpid()) + "-" + std::to_string(n))).string();
        if (::link(path.c_str(), keep.c_str()) == 0) {
            registerTemporary(keep);
            return keep;
        }
        if (errno != EEXIST) break;
    }
    return "";
}

}  // namespace

RunFiles::RunFiles() = default;
RunFiles::~RunFiles() = default;  // uncommitted AtomicFiles remove their temporaries

void RunFiles::input(const std::string& path, const std::string& option)
{
    struct stat st {};
    if (path.empty() || ::stat(path.c_str(), &st) != 0) return;
    // An input learned after the outputs (the files a scene reads, known once it is loaded) is
    // checked against them as an output is checked against the inputs.
    FileId me;
    if (identify(path, me) && !me.device)
        if (const auto* out = sameFile(me, outputs_)) throw destroys(out->first, out->second, path, option);
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
    if (const auto* in = sameFile(me, inputs_)) throw destroys(path, option, in->first, in->second);
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

void RunFiles::commit(const std::function<void()>& last)
{
    // Devices and pipes first: a write into one can fail (/dev/full) and cannot be taken back, so
    // the files are renamed into place only once every device took its content.
    for (auto& f : staged_)
        if (f->isDevice()) f->commit();
    // Every file's target is checked again before the first rename (a folder or link may have
    // appeared during the run) ...
    for (auto& f : staged_)
        if (!f->isDevice()) checkOutputPath(f->path());
    // ... and each file it replaces is kept (a hard link beside it) until all are in place, so
    // that a rename that still fails puts back what the earlier ones replaced.
    Named kept;  // (target, its old content's link)
    std::vector<std::string> placed;
    auto releaseKept = [&] {
        for (const auto& [target, keep] : kept) {
            std::remove(keep.c_str());
            releaseTemporary(keep);
        }
    };
    try {
        for (auto& f : staged_) {
            if (f->isDevice()) continue;
            struct stat st {};
            if (::lstat(f->path().c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
                const std::string keep = keepLink(f->path());
                if (!keep.empty()) kept.emplace_back(f->path(), keep);
            }
            f->commit();
            placed.push_back(f->path());
        }
        if (last) last();
    } catch (...) {
        for (const std::string& p : placed) {
            const auto k = std::find_if(kept.begin(), kept.end(), [&](const auto& x) { return x.first == p; });
            if (k != kept.end())
                std::rename(k->second.c_str(), p.c_str());
            else
                std::remove(p.c_str());
        }
        releaseKept();
        throw;
    }
    releaseKept();
}

}  // namespace smokescan
