#pragma once
/// @file atomic_file.hpp
/// @brief An output file that appears only when complete, and never at the cost of another file.
///
/// The content goes to a temporary created exclusively (O_EXCL, random name) beside the target,
/// with the target's extension so that writers choosing a format by extension (OpenImageIO) work,
/// and commit() renames it into place. A target that exists must be a regular file, a character
/// device or a FIFO, or a link to a device or FIFO, or one of the process's own streams
/// (`/dev/stdout`, `/dev/fd/N`, whatever they lead to): any other link, a folder or anything else
/// is refused, never replaced. A
/// device, FIFO or stream (`/dev/null`, `/dev/stdout`, a pipe) is appended to at commit, from a
/// temporary in the temp folder. Every write and the close are checked ("No space left on
/// device" is an error, not a short file). An uncommitted temporary is removed when the object is
/// destroyed, and also on SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT and SIGXFSZ.
#include <fstream>
#include <memory>
#include <string>

namespace smokescan {

class AtomicFile {
public:
    /// @param path the file to write
    /// @throw Error naming `path` when it may not be replaced or the temporary cannot be created.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// The stream onto the temporary (opened on first use).
    std::ostream& stream();
    /// The temporary's name, for writers that open files by name (OpenVDB, OpenImageIO).
    const std::string& tempPath() const { return tmp_; }
    const std::string& path() const { return path_; }
    /// True when the target is a character device or FIFO (written into at commit).
    bool isDevice() const { return device_; }
    /// Checks every write, then moves the content into place.
    /// @throw Error when writing, closing or renaming failed (the target is then untouched).
    void commit();

private:
    std::string path_, tmp_;
    std::ofstream out_;
    bool device_ = false, done_ = false;
};

/// @brief Refuses (Error naming `path`) an output that may not be written: a folder, a symbolic
/// link, a socket or block device, or a file in a folder that does not exist.
/// @return true when `path` is a character device or FIFO (written into, not replaced)
bool checkOutputPath(const std::string& path);

/// @brief The descriptor an output path of the process's own streams writes to (/dev/stdout,
/// /dev/stderr, /dev/fd/N, /proc/self/fd/N; after divertStdout() /dev/stdout is the kept
/// standard output), or −1 for any other path.
int ownStreamFd(const std::string& path);
/// @brief For a program whose output file is its own standard output: keeps that stream for the
/// outputs that name it and points descriptor 1 at standard error, so that what the program
/// prints (summaries, "wrote ...") does not mix into the file. Call before anything is printed.
/// @return false when the streams could not be moved (nothing changed)
bool divertStdout();

/// @brief Removes `path` (a file or a folder tree) on SIGINT, SIGTERM, SIGHUP or SIGPIPE until it is
/// released; for temporaries. Installs the signal handlers on first use.
void registerTemporary(const std::string& path);
void releaseTemporary(const std::string& path);
/// @brief For a host process that handles its own signals (the Python module, whose Ctrl-C is a
/// KeyboardInterrupt): the library then never installs its handlers. Call before any output is
/// written. Temporaries are still removed by their owners on an error or a cancel, not on a
/// signal that ends the process.
void leaveSignalsToHost();

}  // namespace smokescan
