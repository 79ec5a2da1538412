#pragma once
/// @file mcap_reader.hpp
/// @brief Reads an MCAP file (https://mcap.dev/spec) from start to end, one record at a time: a
/// chunk is read, checked (its CRC) and decompressed (zstd, lz4 or none) on its own, so that memory
/// is bounded by the largest chunk, itself bounded (limits::kBagChunkBytes). Every length is
/// checked against what is left of the file or chunk before it is used; a truncated file, a CRC
/// that does not match, an unknown compression or a record that runs past its container is a
/// one-line error naming the file and the record's byte offset.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace smokescan {

/// A channel and its schema, as the file declares them.
struct McapChannel {
    uint16_t id = 0;
    std::string topic, message_encoding;
    std::string schema_name, schema_encoding, schema_data;  ///< empty without a schema
};

/// One message.
struct McapMessage {
    uint16_t channel = 0;
    uint32_t sequence = 0;
    uint64_t log_time_ns = 0, publish_time_ns = 0;
    std::vector<uint8_t> data;
    uint64_t offset = 0;  ///< of its record (or its chunk's) in the file, for messages
};

/// @brief Reads every record of the MCAP file at `path`, calling `on_message` for each message
/// (with its channel) in file order. @return the channels by id.
/// @throw Error "PATH: …" for a file that is not a whole, valid MCAP file.
std::map<uint16_t, McapChannel> readMcap(const std::string& path,
                                         const std::function<void(const McapChannel&, McapMessage&&)>& on_message);

/// @brief The same on bytes in memory (the fuzz target's entry); `name` names them in errors.
std::map<uint16_t, McapChannel> readMcapBytes(const std::vector<uint8_t>& bytes, const std::string& name,
                                              const std::function<void(const McapChannel&, McapMessage&&)>& on_message);

}  // namespace smokescan
