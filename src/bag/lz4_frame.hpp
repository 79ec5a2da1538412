#pragma once
// Internal: an LZ4 frame (liblz4's frame format, as MCAP's and ROS 1's lz4 chunks hold) unpacked
// into a buffer of the size the container states.
#include <cstdint>
#include <string>
#include <vector>

namespace smokescan::detail {

/// @brief Unpacks n bytes at p into `out`, whose size is what they must unpack to.
/// @throw Error naming `where` when they are not an LZ4 frame of that size.
void unpackLz4Frame(const uint8_t* p, size_t n, std::vector<uint8_t>& out, const std::string& where);

}  // namespace smokescan::detail
