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
/// @throw Error naming the file (and line): missing, unreadable, over the text-input bound, a
/// vertex that is not three finite numbers, no faces, bad indices, over limits::kMeshTriangles.
TriMesh loadObj(const std::string& path);

/// @brief Edges that belong to one triangle only, or to more than two: 0 for a closed mesh
/// (one whose inside is defined, as a smoke area's must be).
size_t openEdges(const TriMesh& mesh);

/// @brief World-space triangles of a surface (cylinders: 128 facets and two caps).
TriMesh tessellate(const Surface& s);

}  // namespace smokescan
