#include "vdb_header.hpp"

#include <cctype>
#include <cstring>
#include <map>

#include "smokescan/core/error.hpp"

namespace smokescan::detail {
namespace {

constexpr uint32_t kMinVersion = 211, kMaxVersion = 224;
constexpr uint64_t kMaxNameBytes = 1 << 16;  // a grid, type or metadata name

/// Sizes OpenVDB reads for its fixed-size metadata types, whatever size the file states.
const std::map<std::string, uint32_t>& fixedMetaSizes()
{
    static const std::map<std::string, uint32_t> m = {{"bool", 1},   {"int32", 4},  {"int64", 8},  {"float", 4},
                                                      {"double", 8}, {"vec2i", 8},  {"vec2s", 8},  {"vec2d", 16},
                                                      {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
                                                      {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}};
    return m;
}

bool knownGridType(const std::string& value_type)
{
    for (const char* t :
         {"bool", "double", "float", "int32", "int64", "mask", "vec3d", "vec3i", "vec3s", "ptdataidx32", "ptidx32"})
        if (value_type == t) return true;
    return false;
}

/// Reads little-endian fields within [pos, limit), refusing anything that would run past it.
class Cursor {
public:
    Cursor(std::istream& in, uint64_t size, const std::string& path) : in_(in), size_(size), path_(path) {}

    [[noreturn]] void fail(const std::string& what) const
    {
        throw Error(path_,
                    "is not a valid VDB file: " + what + " (at byte " + std::to_string(pos_) + " of " +
                        std::to_string(size_) + ")");
    }
    uint64_t pos() const { return pos_; }
    uint64_t left() const { return limit_ - pos_; }
    void seek(uint64_t p, uint64_t limit)
    {
        if (p > size_ || limit > size_ || p > limit) fail("an offset beyond the file");
        pos_ = p;
        limit_ = limit;
    }
    void bytes(void* out, uint64_t n, const char* what)
    {
        if (n > left()) fail(std::string("the file ends inside ") + what);
        in_.clear();
        in_.seekg(std::streamoff(pos_));
        in_.read(static_cast<char*>(out), std::streamsize(n));
        if (uint64_t(in_.gcount()) != n) fail(std::string("cannot read ") + what);
        pos_ += n;
    }
    template <class T>
    T num(const char* what)
    {
        T v{};
        bytes(&v, sizeof v, what);
        return v;
    }
    std::string str(const char* what, uint64_t max = kMaxNameBytes)
    {
        const uint32_t n = num<uint32_t>(what);
        if (n > left() || n > max) fail(std::string(what) + " of " + std::to_string(n) + " bytes");
        std::string s(n, '\0');
        bytes(s.data(), n, what);
        return s;
    }
    void skip(uint64_t n, const char* what)
    {
        if (n > left()) fail(std::string("the file ends inside ") + what);
        pos_ += n;
    }

private:
    std::istream& in_;
    uint64_t size_, pos_ = 0, limit_ = 0;
    std::string path_;
};

/// A MetaMap (MetaMap::readMeta); the int64 values of the named entries are returned.
std::map<std::string, int64_t> readMeta(Cursor& c, const char* what)
{
    std::map<std::string, int64_t> ints;
    const uint32_t count = c.num<uint32_t>(what);
    if (count > c.left() / 12) c.fail(std::string(what) + ": " + std::to_string(count) + " entries cannot fit");
    for (uint32_t i = 0; i < count; ++i) {
        const std::string name = c.str("a metadata name");
        const std::string type = c.str("a metadata type");
        const uint32_t n = c.num<uint32_t>("a metadata size");
        const auto fixed = fixedMetaSizes().find(type);
        if (fixed != fixedMetaSizes().end() && n != fixed->second)
            c.fail("metadata '" + name + "' of type " + type + " states " + std::to_string(n) + " bytes, not " +
                   std::to_string(fixed->second));
        if (type == "int64" && n == 8)
            ints[name] = c.num<int64_t>("a metadata value");
        else
            c.skip(n, "a metadata value");
    }
    return ints;
}

/// "name\x1eN" → "name[N]", as OpenVDB shows repeated names.
std::string displayName(const std::string& unique)
{
    const auto sep = unique.find('\x1e');
    return sep == std::string::npos ? unique : unique.substr(0, sep) + "[" + unique.substr(sep + 1) + "]";
}

}  // namespace

std::vector<VdbGridEntry> checkVdbHeader(std::istream& in, uint64_t size, const std::string& path)
{
    Cursor c(in, size, path);
    c.seek(0, size);
    if (size < 8 || c.num<int64_t>("the magic number") != 0x56444220) c.fail("no VDB magic number");
    const uint32_t version = c.num<uint32_t>("the file version");
    if (version < kMinVersion || version > kMaxVersion)
        c.fail("file version " + std::to_string(version) + " (this reader takes " + std::to_string(kMinVersion) + "–" +
               std::to_string(kMaxVersion) + ")");
    c.skip(8, "the library version");
    if (version >= 212 && c.num<char>("the grid-offsets flag") != 1)
        c.fail("written as a stream without grid offsets (write it with a file writer)");
    if (version >= 220 && version < 222) c.skip(1, "the compression flag");
    if (version >= 218) {
        char uuid[36];
        c.bytes(uuid, sizeof uuid, "the UUID");
        for (int i = 0; i < 36; ++i) {
            const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
            if (dash ? uuid[i] != '-' : !std::isxdigit(static_cast<unsigned char>(uuid[i]))) c.fail("a malformed UUID");
        }
    } else {
        c.skip(16, "the UUID");
    }
    readMeta(c, "the file's metadata");
    const int32_t count = c.num<int32_t>("the grid count");
    if (count < 0 || uint64_t(count) > c.left() / 32) c.fail("a grid count of " + std::to_string(count));
    std::vector<VdbGridEntry> grids;
    for (int32_t g = 0; g < count; ++g) {
        VdbGridEntry e;
        e.name = displayName(c.str("a grid name"));
        std::string type = c.str("a grid type");
        const std::string half = "_HalfFloat";
        if (type.size() > half.size() && type.compare(type.size() - half.size(), half.size(), half) == 0) {
            e.half = true;
            type.resize(type.size() - half.size());
        }
        if (type.rfind("Tree_", 0) != 0 || type.size() < 12 || type.compare(type.size() - 6, 6, "_5_4_3") != 0)
            c.fail("grid '" + e.name + "' has an unknown type '" + type + "'");
        e.type = type.substr(5, type.size() - 11);
        if (!knownGridType(e.type)) c.fail("grid '" + e.name + "' has an unknown type '" + type + "'");
        const bool instance = version >= 216 && !c.str("an instance parent name").empty();
        e.grid_pos = c.num<int64_t>("a grid position");
        e.block_pos = c.num<int64_t>("a block position");
        e.end_pos = c.num<int64_t>("an end position");
        const int64_t here = int64_t(c.pos()), n = int64_t(size);
        const bool ordered = e.grid_pos == here && e.end_pos <= n &&
            (instance ? (e.block_pos == 0 && e.grid_pos <= e.end_pos)
                      : (e.grid_pos <= e.block_pos && e.block_pos <= e.end_pos));
        if (!ordered)
            c.fail("grid '" + e.name + "' has offsets " + std::to_string(e.grid_pos) + ", " +
                   std::to_string(e.block_pos) + ", " + std::to_string(e.end_pos) +
                   " that do not fit (truncated file?)");
        // The grid's own header: compression flags, then its metadata, before the topology.
        c.seek(uint64_t(e.grid_pos), uint64_t(instance ? e.end_pos : e.block_pos));
        if (version >= 222 && c.num<uint32_t>("the grid's compression flags") > 7)
            c.fail("grid '" + e.name + "' has unknown compression flags");
        const auto meta = readMeta(c, "the grid's metadata");
        if (auto it = meta.find("file_voxel_count"); it != meta.end()) e.voxels = it->second;
        if (auto it = meta.find("file_mem_bytes"); it != meta.end()) e.mem_bytes = it->second;
        grids.push_back(e);
        c.seek(uint64_t(e.end_pos), size);
    }
    return grids;
}

}  // namespace smokescan::detail
