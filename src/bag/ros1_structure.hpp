#pragma once
// Internal: the record structure of a ROS 1 bag (format 2.0, wiki.ros.org/Bags/Format/2.0),
// checked before librosbag_storage reads the file: that library trusts the lengths and offsets
// it finds (a fuzzed bag made it read past a buffer), so every one it will follow is checked here.
#include <string>

namespace smokescan::detail {

/// @brief Whether the file's first bytes name a ROS 1 bag (format 2.0).
bool isRos1Bag(const std::string& path);

/// @brief Walks every record, and every record inside each chunk (decompressed: none, bz2, lz4):
/// each length within its container, each header field within its header, a chunk's unpacked
/// size bounded (limits::kBagChunkBytes) and true; each index entry at a message record of the
/// chunk before it; each chunk info at a chunk; the bag header's index position at a record.
/// @throw Error "PATH: record at byte N: …" at the first problem.
void checkRos1Structure(const std::string& path);

}  // namespace smokescan::detail
