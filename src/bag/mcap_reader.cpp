#include "smokescan/bag/mcap_reader.hpp"

#include <zstd.h>

#include <cstring>
#include <fstream>
#include <memory>

#include "lz4_frame.hpp"
#include "mcap_records.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan {
namespace {

/// Where the bytes come from: a file read piece by piece, or memory.
class Source {
public:
    virtual ~Source() = default;
    virtual uint64_t size() const = 0;
    virtual void read(uint64_t offset, void* p, size_t n) = 0;
};

class FileSource : public Source {
public:
    explicit FileSource(const std::string& path) : in_(path, std::ios::binary)
    {
        if (!in_) throw Error(path, "cannot be opened");
        in_.seekg(0, std::ios::end);
        size_ = uint64_t(in_.tellg());
        path_ = path;
    }
    uint64_t size() const override { return size_; }
    void read(uint64_t offset, void* p, size_t n) override
    {
        in_.seekg(std::streamoff(offset));
        in_.read(static_cast<char*>(p), std::streamsize(n));
        if (!in_) throw Error(path_, "could not be read at byte " + std::to_string(offset));
    }

private:
    std::ifstream in_;
    uint64_t size_ = 0;
    std::string path_;
};

class MemorySource : public Source {
public:
    explicit MemorySource(const std::vector<uint8_t>& b) : b_(b) {}
    uint64_t size() const override { return b_.size(); }
    void read(uint64_t offset, void* p, size_t n) override { std::memcpy(p, b_.data() + offset, n); }

private:
    const std::vector<uint8_t>& b_;
};

/// A record's fields, each read within the record's bounds.
class Cursor {
public:
    Cursor(const uint8_t* p, uint64_t n, std::string where) : p_(p), n_(n), where_(std::move(where)) {}
    template <class T>
    T num()
    {
        need(sizeof(T));
        T v;
        std::memcpy(&v, p_ + at_, sizeof v);
        at_ += sizeof v;
        return v;
    }
    std::string str()
    {
        const uint32_t n = num<uint32_t>();
        need(n);
        std::string s(reinterpret_cast<const char*>(p_ + at_), n);
        at_ += n;
        return s;
    }
    const uint8_t* take(uint64_t n)
    {
        need(n);
        const uint8_t* q = p_ + at_;
        at_ += n;
        return q;
    }
    uint64_t left() const { return n_ - at_; }

private:
    void need(uint64_t n) const
    {
        if (n > n_ - at_)
            throw Error(where_,
                        "runs past its end (a field of " + std::to_string(n) + " bytes with " +
                            std::to_string(n_ - at_) + " left)");
    }
    const uint8_t* p_;
    uint64_t n_, at_ = 0;
    std::string where_;
};

std::string opName(uint8_t op) { return fmt("opcode 0x%02x", unsigned(op)); }

struct Reader {
    std::string name;
    const std::function<void(const McapChannel&, McapMessage&&)>& on_message;
    std::map<uint16_t, McapChannel> channels;
    std::map<uint16_t, McapChannel> schemas;  ///< schema fields only

    std::string where(uint64_t offset, uint8_t op, const char* in = "") const
    {
        return name + ": record at byte " + std::to_string(offset) + in + " (" + opName(op) + ")";
    }

    /// One record inside or outside a chunk; returns false at a Data End or Footer.
    bool record(uint8_t op, const uint8_t* p, uint64_t n, uint64_t offset, bool in_chunk)
    {
        const std::string w = where(offset, op, in_chunk ? " of a chunk" : "");
        Cursor c(p, n, w);
        switch (op) {
        case mcap::kSchema: {
            const auto id = c.num<uint16_t>();
            McapChannel s;
            s.schema_name = c.str();
            s.schema_encoding = c.str();
            const uint32_t len = c.num<uint32_t>();
            s.schema_data.assign(reinterpret_cast<const char*>(c.take(len)), len);
            if (id != 0) schemas[id] = s;  // id 0 is invalid and ignored (the specification)
            return true;
        }
        case mcap::kChannel: {
            McapChannel ch;
            ch.id = c.num<uint16_t>();
            const auto schema = c.num<uint16_t>();
            ch.topic = c.str();
            ch.message_encoding = c.str();
            (void)c.take(c.num<uint32_t>());  // metadata
            if (schema != 0) {
                const auto s = schemas.find(schema);
                if (s == schemas.end())
                    throw Error(w, "names schema " + std::to_string(schema) + ", not declared before it");
                ch.schema_name = s->second.schema_name;
                ch.schema_encoding = s->second.schema_encoding;
                ch.schema_data = s->second.schema_data;
            }
            channels[ch.id] = ch;
            return true;
        }
        case mcap::kMessage: {
            McapMessage m;
            m.channel = c.num<uint16_t>();
            m.sequence = c.num<uint32_t>();
            m.log_time_ns = c.num<uint64_t>();
            m.publish_time_ns = c.num<uint64_t>();
            const uint64_t len = c.left();
            const uint8_t* d = c.take(len);
            m.data.assign(d, d + len);
            m.offset = offset;
            const auto ch = channels.find(m.channel);
            if (ch == channels.end())
                throw Error(w, "is a message on channel " + std::to_string(m.channel) + ", not declared before it");
            on_message(ch->second, std::move(m));
            return true;
        }
        case mcap::kDataEnd:
        case mcap::kFooter:
            if (in_chunk) throw Error(w, "cannot be inside a chunk");
            return false;
        default:
            if (in_chunk && op < 0x80) throw Error(w, "cannot be inside a chunk");
            return true;  // indexes, attachments, metadata, statistics: not needed to read messages
        }
    }

    std::vector<uint8_t> decompress(const std::string& compression, const uint8_t* p, uint64_t n, uint64_t size,
                                    const std::string& w) const
    {
        std::vector<uint8_t> out(size);
        if (compression.empty()) {
            if (n != size)
                throw Error(w,
                            "holds " + std::to_string(n) + " bytes, not its uncompressed size " + std::to_string(size));
            if (n) std::memcpy(out.data(), p, n);
        } else if (compression == "zstd") {
            const size_t r = ZSTD_decompress(out.data(), out.size(), p, n);
            if (ZSTD_isError(r))
                throw Error(w, std::string("could not be decompressed (zstd: ") + ZSTD_getErrorName(r) + ")");
            if (r != size)
                throw Error(w, "decompresses to " + std::to_string(r) + " bytes, not " + std::to_string(size));
        } else if (compression == "lz4") {
            detail::unpackLz4Frame(p, n, out, w);
        } else {
            throw Error(w,
                        "uses the compression '" + compression + "', which smokescan does not read (zstd, lz4, none)");
        }
        return out;
    }

    void chunk(const uint8_t* p, uint64_t n, uint64_t offset)
    {
        const std::string w = where(offset, mcap::kChunk);
        Cursor c(p, n, w);
        (void)c.num<uint64_t>();
        (void)c.num<uint64_t>();
        const auto size = c.num<uint64_t>();
        const auto crc = c.num<uint32_t>();
        const std::string compression = c.str();
        const auto len = c.num<uint64_t>();
        const uint8_t* packed = c.take(len);
        if (size > limits::kBagChunkBytes)
            throw Error(w,
                        "unpacks to " + std::to_string(size) + " bytes, over the limit of " +
                            std::to_string(limits::kBagChunkBytes));
        const std::vector<uint8_t> records = decompress(compression, packed, len, size, w);
        if (crc != 0 && mcap::crc32(0, records.data(), records.size()) != crc)
            throw Error(w, "fails its CRC (the chunk is damaged)");
        uint64_t at = 0;
        while (at < records.size()) {
            if (records.size() - at < 9) throw Error(w, "ends inside a record's header at byte " + std::to_string(at));
            const uint8_t op = records[at];
            uint64_t rn;
            std::memcpy(&rn, records.data() + at + 1, 8);
            if (rn > records.size() - at - 9)
                throw Error(w,
                            "holds a record at byte " + std::to_string(at) + " (" + opName(op) + ") of " +
                                std::to_string(rn) + " bytes, past the chunk's end");
            record(op, records.data() + at + 9, rn, at, true);
            at += 9 + rn;
        }
    }
};

std::map<uint16_t, McapChannel> readFrom(Source& src, const std::string& name,
                                         const std::function<void(const McapChannel&, McapMessage&&)>& on_message)
{
    const uint64_t size = src.size();
    uint8_t magic[8];
    if (size < 16) throw Error(name, "is too short to be an MCAP file (" + std::to_string(size) + " bytes)");
    src.read(0, magic, 8);
    if (std::memcmp(magic, mcap::kMagic, 8) != 0) throw Error(name, "is not an MCAP file (no magic at its start)");
    src.read(size - 8, magic, 8);
    if (std::memcmp(magic, mcap::kMagic, 8) != 0)
        throw Error(name, "does not end with MCAP's magic (truncated, or still being written?)");
    Reader r{name, on_message, {}, {}};
    uint32_t crc = mcap::crc32(0, mcap::kMagic, 8);
    const uint64_t end = size - 8;
    uint64_t pos = 8;
    bool first = true;
    std::vector<uint8_t> content;
    while (true) {
        if (end - pos < 9)
            throw Error(name, "ends at byte " + std::to_string(end) + " inside a record's header (truncated?)");
        uint8_t head[9];
        src.read(pos, head, 9);
        const uint8_t op = head[0];
        uint64_t n;
        std::memcpy(&n, head + 1, 8);
        const std::string w = r.where(pos, op);
        if (first && op != mcap::kHeader) throw Error(w, "should be the Header");
        first = false;
        if (n > end - pos - 9)
            throw Error(w,
                        "claims " + std::to_string(n) + " bytes, past the file's end at byte " + std::to_string(end) +
                            " (truncated?)");
        if (n > limits::kBagChunkBytes)
            throw Error(
                w, "is " + std::to_string(n) + " bytes, over the limit of " + std::to_string(limits::kBagChunkBytes));
        content.resize(n);
        if (n) src.read(pos + 9, content.data(), n);
        if (op == mcap::kDataEnd) {
            Cursor c(content.data(), n, w);
            const auto expected = c.num<uint32_t>();
            if (expected != 0 && expected != crc)
                throw Error(w, "finds the data section's CRC wrong (the file is damaged)");
            return r.channels;
        }
        if (op == mcap::kFooter) return r.channels;
        crc = mcap::crc32(crc, head, 9);
        crc = mcap::crc32(crc, content.data(), n);
        if (op == mcap::kChunk)
            r.chunk(content.data(), n, pos);
        else
            r.record(op, content.data(), n, pos, false);
        pos += 9 + n;
    }
}

}  // namespace

std::map<uint16_t, McapChannel> readMcap(const std::string& path,
                                         const std::function<void(const McapChannel&, McapMessage&&)>& on_message)
{
    FileSource src(path);
    return readFrom(src, path, on_message);
}

std::map<uint16_t, McapChannel> readMcapBytes(const std::vector<uint8_t>& bytes, const std::string& name,
                                              const std::function<void(const McapChannel&, McapMessage&&)>& on_message)
{
    MemorySource src(bytes);
    return readFrom(src, name, on_message);
}

}  // namespace smokescan
