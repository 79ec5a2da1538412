#include "smokescan/scene/mesh.hpp"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/core/overloaded.hpp"
#include "smokescan/io/text_input.hpp"

namespace smokescan {

void TriMesh::append(const TriMesh& o)
{
    const int base = int(points_m.size());
    points_m.insert(points_m.end(), o.points_m.begin(), o.points_m.end());
    for (auto t : o.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

namespace {

/// tinyobjloader reads "nan" or "1e999" as some number: every vertex line must be three finite
/// numbers (an optional fourth, w) before it parses.
void checkVertexLines(const std::string& text, const std::string& path)
{
    std::istringstream in(text);
    std::string line;
    for (int ln = 1; std::getline(in, line); ++ln) {
        std::istringstream ls(line);
        std::string tag, tok;
        if (!(ls >> tag) || tag != "v") continue;
        int n = 0;
        while (ls >> tok) {
            char* end = nullptr;
            errno = 0;
            const double x = std::strtod(tok.c_str(), &end);
            if (*end || end == tok.c_str() || !std::isfinite(x) || errno == ERANGE)
                throw Error(path + ":" + std::to_string(ln), "vertex coordinate '" + tok + "' is not a finite number");
            ++n;
        }
        if (n < 3 || n > 4)
            throw Error(path + ":" + std::to_string(ln), "a vertex needs 3 coordinates, got " + std::to_string(n));
    }
}

}  // namespace

TriMesh loadObj(const std::string& path)
{
    const std::string text = readTextInput(path, "OBJ file");
    checkVertexLines(text, path);
    tinyobj::ObjReaderConfig cfg;
    cfg.triangulate = true;
    cfg.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(text, "", cfg)) {
        std::string msg = reader.Error();
        while (!msg.empty() && (msg.back() == '\n' || msg.back() == '\r')) msg.pop_back();
        throw Error(path, "cannot read as OBJ (" + (msg.empty() ? std::string("parse error") : msg) + ")");
    }
    const auto& v = reader.GetAttrib().vertices;
    TriMesh m;
    for (size_t i = 0; i + 2 < v.size(); i += 3) {
        const Vec3 p(v[i], v[i + 1], v[i + 2]);
        if (!p.allFinite()) throw Error(path, "vertex " + std::to_string(i / 3 + 1) + " is not finite");
        m.points_m.push_back(p);
    }
    for (const auto& shape : reader.GetShapes()) {
        const auto& idx = shape.mesh.indices;
        for (size_t i = 0; i + 2 < idx.size(); i += 3) {
            std::array<int, 3> t{idx[i].vertex_index, idx[i + 1].vertex_index, idx[i + 2].vertex_index};
            for (int k : t)
                if (k < 0 || size_t(k) >= m.points_m.size()) throw Error(path, "face index out of range");
            m.triangles.push_back(t);
        }
        if (int64_t(m.triangles.size()) > limits::kMeshTriangles)
            throw Error(path, "has over " + std::to_string(limits::kMeshTriangles) + " triangles");
    }
    if (m.triangles.empty()) throw Error(path, "holds no faces");
    return m;
}

size_t openEdges(const TriMesh& mesh)
{
    std::map<std::pair<int, int>, int> uses;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    size_t open = 0;
    for (const auto& [edge, n] : uses) open += n != 2;
    return open;
}

namespace {

TriMesh boxMesh(const Vec3& size)
{
    TriMesh m;
    const Vec3 h = 0.5 * size;
    for (int k = 0; k < 8; ++k)
        m.points_m.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
    m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return m;
}

TriMesh cylinderMesh(double r, double h, int n = 128)
{
    TriMesh m;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * M_PI * i / n;
        m.points_m.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
        m.points_m.emplace_back(r * std::cos(a), r * std::sin(a), h);
    }
    const int c0 = int(m.points_m.size());
    m.points_m.emplace_back(0, 0, 0);
    m.points_m.emplace_back(0, 0, h);
    for (int i = 0; i < n; ++i) {
        const int a = 2 * i, b = 2 * ((i + 1) % n);
        m.triangles.push_back({a, b, a + 1});
        m.triangles.push_back({b, b + 1, a + 1});
        m.triangles.push_back({c0, b, a});
        m.triangles.push_back({c0 + 1, a + 1, b + 1});
    }
    return m;
}

}  // namespace

TriMesh tessellate(const Surface& s)
{
    const auto local = [](const TriMesh& m, const Pose& pose, double scale) {
        TriMesh out = m;
        for (Vec3& p : out.points_m) p = pose.apply(scale * p);
        return out;
    };
    return std::visit(
        Overloaded{
            [&](const BoxShape& b) { return local(boxMesh(b.size_m), s.pose, 1.0); },
            [&](const QuadShape& q) {  // quads are given in world coordinates
                TriMesh m;
                m.points_m = {q.corner_m, q.corner_m + q.edge_u_m, q.corner_m + q.edge_u_m + q.edge_v_m,
                              q.corner_m + q.edge_v_m};
                m.triangles = {{0, 1, 2}, {0, 2, 3}};
                return m;
            },
            [&](const CylinderShape& c) { return local(cylinderMesh(c.radius_m, c.height_m), s.pose, 1.0); },
            [&](const MeshShape& mesh) { return local(loadObj(mesh.obj_path), s.pose, mesh.scale); },
        },
        s.shape);
}

}  // namespace smokescan
