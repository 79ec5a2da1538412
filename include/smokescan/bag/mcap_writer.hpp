#pragma once
/// @file mcap_writer.hpp
/// @brief An MCAP file writer (https://mcap.dev/spec, major version 0), written to the published
/// specification and read back in the tests by an independent reader (@mcap/core): messages in
/// zstd-compressed chunks with their CRC, each chunk followed by its message indexes; a Data End
/// record with the data section's CRC; a summary (schemas, channels, statistics, chunk indexes)
/// with summary offsets, so that readers can seek; the footer with the summary's CRC.
///
/// | setting     | default | unit  | meaning                                                  |
/// |-------------|---------|-------|----------------------------------------------------------|
/// | chunk_bytes | 1 MiB   | bytes | a chunk is closed once its records reach this size        |
/// | zstd_level  | 3       | –     | zstd's compression level (1 fast … 19 small)              |
/// | profile     | "ros2"  | –     | the Header's profile                                      |
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace smokescan {

struct McapWriterConfig {
    size_t chunk_bytes = 1 << 20;
    int zstd_level = 3;
    std::string profile = "ros2";
};

/// What a finished file holds.
struct McapWriteResult {
    uint64_t messages = 0, chunks = 0, bytes = 0;
    uint64_t start_ns = 0, end_ns = 0;  ///< the earliest and latest log time (0 without messages)
    std::map<std::string, uint64_t> per_topic;  ///< messages by topic
};

/// Writes one MCAP file to a stream the caller owns (and commits: io/atomic_file.hpp).
class McapWriter {
public:
    McapWriter(std::ostream& out, McapWriterConfig cfg = {});  ///< writes the magic and the Header
    McapWriter(const McapWriter&) = delete;
    McapWriter& operator=(const McapWriter&) = delete;
    ~McapWriter();
    /// @brief A schema (encoding "ros2msg" for ROS 2 messages); returns its id (from 1).
    uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
    /// @brief A channel on `topic` with messages of `schema` in `message_encoding` ("cdr").
    uint16_t addChannel(uint16_t schema, const std::string& topic, const std::string& message_encoding,
                        const std::map<std::string, std::string>& metadata = {});
    /// @brief One message; its sequence number counts the channel's messages from 0.
    /// @param log_time_ns, publish_time_ns nanoseconds on the recording's clock
    void write(uint16_t channel, uint64_t log_time_ns, uint64_t publish_time_ns, const std::vector<uint8_t>& data);
    /// @brief Closes the last chunk and writes the summary, footer and closing magic.
    /// @throw Error when the stream fails.
    McapWriteResult finish();

private:
    struct Impl;
    Impl* impl_;
};

}  // namespace smokescan
