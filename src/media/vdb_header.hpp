#pragma once
// Internal: the structure of a .vdb file checked before OpenVDB reads it. OpenVDB trusts every
// count, length and offset in a file: a truncated or edited file makes it allocate gigabytes for
// a string, or read a grid as another type and spin. checkVdbHeader walks what io::File::open and
// readGrid will read — the header, the file's metadata, each grid descriptor and each grid's
// own metadata — and refuses anything that does not fit the file (OpenVDB file versions 211–224,
// written with grid offsets, as io::File writes them).
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace smokescan::detail {

/// One grid as the file's descriptor names it.
struct VdbGridEntry {
    std::string name;  ///< as OpenVDB shows it ("name", or "name[1]" for repeated names)
    std::string type;  ///< value type: "float", "double", "vec3s", …
    bool half = false;
    int64_t grid_pos = 0, block_pos = 0, end_pos = 0;
    int64_t voxels = -1;  ///< the grid's "file_voxel_count" metadata, −1 if absent
    int64_t mem_bytes = -1;  ///< the grid's "file_mem_bytes" metadata, −1 if absent
};

/// @param in the file, positioned anywhere (it is read from offset 0)
/// @param size the file's size in bytes
/// @param path names the file in errors
/// @return the grids in file order
/// @throw Error "PATH: problem" for anything OpenVDB could misread.
std::vector<VdbGridEntry> checkVdbHeader(std::istream& in, uint64_t size, const std::string& path);

}  // namespace smokescan::detail
