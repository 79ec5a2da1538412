#pragma once
/// @file mesh.hpp
/// @brief Triangle meshes: OBJ files (tinyobjloader) and the tessellation of scene shapes.
#include <array>
#include <string>
#include <vector>

#include "smokescan/scene/scene.hpp"

namespace smokescan {

struct TriMesh {
    std::vector<Vec3> points_m;
    std::vector<std::array<int, 3>> triangles;
    void append(const TriMesh& other);
};

/// @brief Reads the triangles of an OBJ file (polygons are fan-triangulated).
/// @throw Error naming the file: missing, unreadable, no faces, bad indices.
TriMesh loadObj(const std::string& path);

/// @brief World-space triangles of a surface (cylinders: 128 facets and two caps).
TriMesh tessellate(const Surface& s);

}  // namespace smokescan
