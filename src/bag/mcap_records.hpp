#pragma once
// Internal: MCAP's record opcodes and its little-endian field encoding (mcap.dev/spec,
// "Serialization"), shared by the writer and the reader.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace smokescan::mcap {

inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum Op : uint8_t {
    kHeader = 0x01,
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kMessageIndex = 0x07,
    kChunkIndex = 0x08,
    kAttachment = 0x09,
    kAttachmentIndex = 0x0A,
    kStatistics = 0x0B,
    kMetadata = 0x0C,
    kMetadataIndex = 0x0D,
    kSummaryOffset = 0x0E,
    kDataEnd = 0x0F
};

/// A record's content, built field by field.
class Fields {
public:
    template <class T>
    Fields& num(T v)  // uint8/16/32/64, little-endian (this build's order: checked in CMake)
    {
        const size_t at = b_.size();
        b_.resize(at + sizeof v);
        std::memcpy(b_.data() + at, &v, sizeof v);
        return *this;
    }
    Fields& str(const std::string& s)
    {
        num(uint32_t(s.size()));
        b_.insert(b_.end(), s.begin(), s.end());
        return *this;
    }
    Fields& bytes(const void* p, size_t n)
    {
        const auto* c = static_cast<const uint8_t*>(p);
        b_.insert(b_.end(), c, c + n);
        return *this;
    }
    /// The opcode, the content's length, the content.
    std::vector<uint8_t> record(uint8_t op) const
    {
        const uint64_t n = b_.size();
        std::vector<uint8_t> r(9 + n);
        r[0] = op;
        std::memcpy(r.data() + 1, &n, 8);
        if (n > 0) std::memcpy(r.data() + 9, b_.data(), n);
        return r;
    }
    const std::vector<uint8_t>& content() const { return b_; }

private:
    std::vector<uint8_t> b_;
};

/// @brief CRC-32 (IEEE 802.3, zlib's) of `n` bytes continuing `crc` (0 to start).
uint32_t crc32(uint32_t crc, const void* p, size_t n);

}  // namespace smokescan::mcap
