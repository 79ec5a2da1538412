#include "ros1_structure.hpp"

#include <bzlib.h>

#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "lz4_frame.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"

namespace smokescan::detail {
namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr size_t kMagicBytes = sizeof kMagic - 1;
constexpr uint32_t kMaxHeader = 1u << 20;

using Fields = std::map<std::string, std::string>;

/// A record header's fields: each a uint32 length then name=value, within the header.
Fields parseFields(const uint8_t* h, size_t n, const std::string& where)
{
    Fields f;
    size_t at = 0;
    while (at < n) {
        if (n - at < 4) throw Error(where, "ends inside a header field's length");
        uint32_t len;
        std::memcpy(&len, h + at, 4);
        at += 4;
        if (len > n - at) throw Error(where, "has a header field of " + std::to_string(len) + " bytes past its header");
        const std::string field(reinterpret_cast<const char*>(h + at), len);
        at += len;
        const size_t eq = field.find('=');
        if (eq == std::string::npos) throw Error(where, "has a header field without '='");
        f[field.substr(0, eq)] = field.substr(eq + 1);
    }
    return f;
}

template <class T>
T fieldOf(const Fields& f, const char* name, const std::string& where)
{
    const auto v = f.find(name);
    if (v == f.end() || v->second.size() != sizeof(T))
        throw Error(where, std::string("has no ") + std::to_string(sizeof(T)) + "-byte field " + name);
    T x;
    std::memcpy(&x, v->second.data(), sizeof x);
    return x;
}

uint8_t opOf(const Fields& f, const std::string& where) { return fieldOf<uint8_t>(f, "op", where); }

/// One record's header length, header, data length and data at `at` of [p, p + n).
struct Record {
    Fields fields;
    const uint8_t* data;
    uint32_t data_len;
    size_t size;  ///< all of it
};

Record recordAt(const uint8_t* p, size_t n, size_t at, const std::string& where)
{
    if (n - at < 4) throw Error(where, "ends inside its header's length");
    uint32_t hn;
    std::memcpy(&hn, p + at, 4);
    if (hn > kMaxHeader || hn > n - at - 4) throw Error(where, "claims a header of " + std::to_string(hn) + " bytes");
    Record r;
    r.fields = parseFields(p + at + 4, hn, where);
    if (n - at - 4 - hn < 4) throw Error(where, "ends inside its data's length");
    std::memcpy(&r.data_len, p + at + 4 + hn, 4);
    if (r.data_len > n - at - 8 - hn)
        throw Error(where, "claims " + std::to_string(r.data_len) + " bytes of data past its end");
    r.data = p + at + 8 + hn;
    r.size = 8 + size_t(hn) + r.data_len;
    return r;
}

std::vector<uint8_t> unpack(const std::string& compression, const uint8_t* p, uint32_t n, uint32_t size,
                            const std::string& where)
{
    if (size > limits::kBagChunkBytes) throw Error(where, "is a chunk over the limit unpacked");
    std::vector<uint8_t> out(size);
    if (compression == "none") {
        if (n != size)
            throw Error(where, "is a chunk of " + std::to_string(n) + " bytes, not its size " + std::to_string(size));
        if (n) std::memcpy(out.data(), p, n);
    } else if (compression == "bz2") {
        unsigned int got = size;
        const int r = BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &got,
                                                 const_cast<char*>(reinterpret_cast<const char*>(p)), n, 0, 0);
        if (r != BZ_OK || got != size) throw Error(where, "is a bz2 chunk that does not unpack to its size");
    } else if (compression == "lz4") {
        detail::unpackLz4Frame(p, n, out, where);
    } else {
        throw Error(where, "is a chunk of the compression '" + compression + "' (none, bz2, lz4)");
    }
    return out;
}

}  // namespace

bool isRos1Bag(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    char magic[kMagicBytes];
    return in.read(magic, kMagicBytes) && std::memcmp(magic, kMagic, kMagicBytes) == 0;
}

void checkRos1Structure(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot be opened");
    in.seekg(0, std::ios::end);
    const uint64_t size = uint64_t(in.tellg());
    in.seekg(0);
    char magic[kMagicBytes];
    if (size < kMagicBytes || !in.read(magic, kMagicBytes) || std::memcmp(magic, kMagic, kMagicBytes) != 0)
        throw Error(path, "is not a ROS 1 bag (format 2.0)");
    if (size == kMagicBytes) throw Error(path, "holds a ROS 1 bag's first line and nothing after it (no bag header)");
    std::set<uint64_t> starts, chunks;  // record starts; chunk starts
    std::set<uint32_t> message_offsets;  // the last chunk's message records, by offset in it
    std::set<uint32_t> unindexed;  // those no index entry has pointed at yet
    uint64_t last_chunk = 0;
    bool after_chunk = false;
    // librosbag reads a chunk's messages through its index entries: one they miss is skipped.
    auto closeChunk = [&] {
        if (!unindexed.empty())
            throw Error(path + ": record at byte " + std::to_string(last_chunk),
                        "is a chunk whose message at byte " + std::to_string(*unindexed.begin()) +
                            " no index entry points to (librosbag would skip it)");
    };
    uint64_t index_pos = 0, pos = kMagicBytes, records = 0;
    std::vector<uint8_t> buf;
    std::vector<std::pair<uint64_t, uint64_t>> chunk_infos;  // (record, chunk_pos)
    while (pos < size) {
        const std::string where = path + ": record at byte " + std::to_string(pos);
        // The record's lengths first, then the record, read whole (bounded).
        uint8_t len[4];
        if (size - pos < 8) throw Error(where, "ends inside its lengths (truncated?)");
        in.seekg(std::streamoff(pos));
        in.read(reinterpret_cast<char*>(len), 4);
        uint32_t hn;
        std::memcpy(&hn, len, 4);
        if (hn > kMaxHeader || hn > size - pos - 8)
            throw Error(where, "claims a header of " + std::to_string(hn) + " bytes");
        in.seekg(std::streamoff(pos + 4 + hn));
        in.read(reinterpret_cast<char*>(len), 4);
        uint32_t dn;
        std::memcpy(&dn, len, 4);
        if (dn > size - pos - 8 - hn)
            throw Error(where, "claims " + std::to_string(dn) + " bytes past the file's end (truncated?)");
        if (uint64_t(dn) > limits::kBagChunkBytes) throw Error(where, "is over the limit");
        buf.resize(8 + size_t(hn) + dn);
        in.seekg(std::streamoff(pos));
        in.read(reinterpret_cast<char*>(buf.data()), std::streamsize(buf.size()));
        if (!in) throw Error(where, "could not be read");
        const Record r = recordAt(buf.data(), buf.size(), 0, where);
        const uint8_t op = opOf(r.fields, where);
        if (records == 0 && op != 0x03) throw Error(where, "should be the bag header");
        starts.insert(pos);
        switch (op) {
        case 0x03:
            index_pos = fieldOf<uint64_t>(r.fields, "index_pos", where);
            if (fieldOf<uint32_t>(r.fields, "conn_count", where) > 100000 ||
                fieldOf<uint32_t>(r.fields, "chunk_count", where) > 10000000)
                throw Error(where, "counts too many connections or chunks");
            break;
        case 0x05: {
            const auto c = r.fields.find("compression");
            if (c == r.fields.end()) throw Error(where, "is a chunk without its compression");
            const std::vector<uint8_t> inner =
                unpack(c->second, r.data, r.data_len, fieldOf<uint32_t>(r.fields, "size", where), where);
            closeChunk();
            message_offsets.clear();
            for (size_t at = 0; at < inner.size();) {
                const std::string w = where + " (its record at byte " + std::to_string(at) + ")";
                const Record ir = recordAt(inner.data(), inner.size(), at, w);
                const uint8_t iop = opOf(ir.fields, w);
                if (iop == 0x02) {
                    (void)fieldOf<uint32_t>(ir.fields, "conn", w);
                    // Time 0 is ROS 1's "no time": librosbag drops such a message from its index
                    // with a note on stderr, and the bag would be read short by one.
                    if (fieldOf<uint64_t>(ir.fields, "time", w) == 0)
                        throw Error(w, "is a message stamped at time 0 (ROS 1's 'no time': librosbag drops it)");
                    message_offsets.insert(uint32_t(at));
                } else if (iop == 0x07) {
                    (void)fieldOf<uint32_t>(ir.fields, "conn", w);
                    (void)parseFields(ir.data, ir.data_len, w);
                } else {
                    throw Error(w, "is not a message or connection record inside a chunk");
                }
                at += ir.size;
            }
            chunks.insert(pos);
            unindexed = message_offsets;
            last_chunk = pos;
            after_chunk = true;
            break;
        }
        case 0x04: {
            if (!after_chunk) throw Error(where, "is an index record that follows no chunk");
            (void)fieldOf<uint32_t>(r.fields, "conn", where);
            const uint32_t n = fieldOf<uint32_t>(r.fields, "count", where);
            if (fieldOf<uint32_t>(r.fields, "ver", where) != 1 || uint64_t(n) * 12 != r.data_len)
                throw Error(where, "is an index record of another version or length");
            for (uint32_t i = 0; i < n; ++i) {
                uint64_t time;
                uint32_t offset;
                std::memcpy(&time, r.data + 12 * size_t(i), 8);
                std::memcpy(&offset, r.data + 12 * size_t(i) + 8, 4);
                if (!message_offsets.count(offset))
                    throw Error(
                        where,
                        "indexes a message at byte " + std::to_string(offset) + " of its chunk, where none starts");
                if (time == 0)  // ROS 1's "no time": librosbag drops the entry, and with it the message
                    throw Error(where,
                                "indexes the message at byte " + std::to_string(offset) +
                                    " of its chunk at time 0 (ROS 1's 'no time': librosbag drops it)");
                unindexed.erase(offset);
            }
            break;
        }
        case 0x07:
            (void)fieldOf<uint32_t>(r.fields, "conn", where);
            (void)parseFields(r.data, r.data_len, where);
            after_chunk = false;
            break;
        case 0x06: {
            if (fieldOf<uint32_t>(r.fields, "ver", where) != 1 ||
                uint64_t(fieldOf<uint32_t>(r.fields, "count", where)) * 8 != r.data_len)
                throw Error(where, "is a chunk info of another version or length");
            chunk_infos.push_back({pos, fieldOf<uint64_t>(r.fields, "chunk_pos", where)});
            after_chunk = false;
            break;
        }
        default:
            throw Error(where, "has an unknown op " + std::to_string(int(op)));
        }
        if (++records > uint64_t(limits::kBagMessages)) throw Error(path, "has too many records");
        pos += buf.size();
    }
    closeChunk();
    if (index_pos != 0 && index_pos != size && !starts.count(index_pos))
        throw Error(path, "has its index at byte " + std::to_string(index_pos) + ", where no record starts");
    for (const auto& [at, chunk] : chunk_infos)
        if (!chunks.count(chunk))
            throw Error(path + ": record at byte " + std::to_string(at),
                        "points at a chunk at byte " + std::to_string(chunk) + ", where none starts");
}

}  // namespace smokescan::detail
