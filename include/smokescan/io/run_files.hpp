#pragma once
/// @file run_files.hpp
/// @brief The files one command reads and writes, checked before any work and written all or
/// nothing.
///
/// Before work starts, each output is checked (checkOutputPath) and compared by file identity
/// (device and inode, not by name: `./a.log`, a hard link and `a.log` are one file) with every
/// input and every other output; a clash is a one-line error naming both options. Writers then
/// write to stage(path), a fresh temporary beside each output, and commit() moves them all into
/// place at the end, so a run that fails midway leaves none of its outputs (and no temporaries:
/// they are removed on destruction and on SIGINT/SIGTERM/SIGHUP).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace smokescan {

class AtomicFile;

class RunFiles {
public:
    RunFiles();
    ~RunFiles();
    RunFiles(const RunFiles&) = delete;
    RunFiles& operator=(const RunFiles&) = delete;

    /// @brief Records an input file. Names that are not files (built-in scenes, "") are ignored.
    /// Inputs and outputs may be recorded in any order (a scene's files are known once it is
    /// loaded): either way a clash is refused before anything is written.
    /// @param option the option or argument that named it, for errors
    /// @throw Error when it is an output already recorded
    void input(const std::string& path, const std::string& option);
    /// @brief Records an output; "" is ignored.
    /// @throw Error when it may not be written, or is an input or another output of this run
    /// (two outputs may share a character device such as /dev/null).
    void output(const std::string& path, const std::string& option);
    /// @brief Records an output folder (made new, or an empty one replaced, by its writer):
    /// compared with the inputs and outputs as output() does; "" is ignored.
    void outputFolder(const std::string& path, const std::string& option);
    /// @brief A new temporary to write `path`'s content to (path must have been recorded).
    /// @return the temporary's name (same folder and extension as `path`)
    std::string stage(const std::string& path);
    /// @brief Moves every staged output into place, in the order staged, then runs `last` (an
    /// output folder's own commit): when `last` fails, the files are taken back (what they
    /// replaced restored) before its error goes on, so that the run changes all or nothing.
    void commit(const std::function<void()>& last = {});

private:
    void record(const std::string& path, const std::string& option);

    std::vector<std::pair<std::string, std::string>> inputs_, outputs_;  // (path, option)
    std::map<std::tuple<uint64_t, uint64_t, std::string>, std::string> output_ids_;  // identity → option
    std::vector<std::unique_ptr<AtomicFile>> staged_;
};

}  // namespace smokescan
