// Building, loading, validating and writing density grids (OpenVDB).
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/Prune.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <sys/stat.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "vdb_grid.hpp"
#include "vdb_header.hpp"

namespace smokescan {

void ensureOpenVdb()
{
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

namespace {

/// What Impl::make needs of a tree's values: whether any is non-finite or negative, and of the
/// non-zero ones their bounds (voxels and tiles as boxes), least and greatest.
struct ValueScan {
    bool bad = false, any = false, nonzero_tiles = false;  // a tile holds a non-zero value
    double lo = 0, hi = 0;
    openvdb::CoordBBox support;
    void add(float v, const openvdb::CoordBBox& box)
    {
        if (!std::isfinite(v) || v < 0.0f) {
            bad = true;
            return;
        }
        if (v == 0.0f) return;
        support.expand(box);
        lo = any ? std::min(lo, double(v)) : v;
        hi = any ? std::max(hi, double(v)) : v;
        any = true;
    }
    void join(const ValueScan& o)
    {
        bad = bad || o.bad;
        if (!o.any) return;
        support.expand(o.support);
        lo = any ? std::min(lo, o.lo) : o.lo;
        hi = any ? std::max(hi, o.hi) : o.hi;
        any = true;
    }
};

/// The leaves' voxels in parallel, the tiles above them in order: the same whatever the thread
/// count (bounds, least and greatest do not depend on the order).
ValueScan scanValues(const openvdb::FloatTree& tree)
{
    using LeafT = openvdb::FloatTree::LeafNodeType;
    std::vector<const LeafT*> leaves;
    leaves.reserve(tree.leafCount());
    tree.getNodes(leaves);
    ValueScan scan = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, leaves.size()), ValueScan{},
        [&](const tbb::blocked_range<size_t>& r, ValueScan acc) {
            for (size_t i = r.begin(); i != r.end(); ++i) {
                const LeafT& leaf = *leaves[i];
                const float* v = leaf.buffer().data();
                for (openvdb::Index k = 0; k < LeafT::SIZE; ++k) {
                    if (v[k] == 0.0f) continue;
                    const openvdb::Coord c = leaf.offsetToGlobalCoord(k);
                    acc.add(v[k], openvdb::CoordBBox(c, c));
                }
            }
            return acc;
        },
        [](ValueScan a, const ValueScan& b) {
            a.join(b);
            return a;
        });
    // The tiles, node by node (the tree's own iterator over them costs more than the voxels: an
    // upper node alone has 32,768 table entries, nearly all empty).
    using RootT = openvdb::FloatTree::RootNodeType;
    using UpperT = RootT::ChildNodeType;
    using LowerT = UpperT::ChildNodeType;
    auto tile = [&](float v, const openvdb::Coord& origin, int dim) {
        if (v == 0.0f) return;
        scan.add(v, openvdb::CoordBBox::createCube(origin, dim));
        scan.nonzero_tiles = true;
    };
    for (auto it = tree.root().cbeginValueAll(); it; ++it) tile(*it, it.getCoord(), UpperT::DIM);
    std::vector<const UpperT*> uppers;
    tree.getNodes(uppers);
    for (const UpperT* u : uppers)
        for (auto it = u->cbeginValueAll(); it; ++it) tile(*it, it.getCoord(), LowerT::DIM);
    std::vector<const LowerT*> lowers;
    tree.getNodes(lowers);
    for (const LowerT* l : lowers)
        for (auto it = l->cbeginValueAll(); it; ++it) tile(*it, it.getCoord(), LeafT::DIM);
    return scan;
}

void buildLeafTable(DensityGrid::Impl& impl)
{
    const auto& tree = impl.grid->tree();
    const long long leaves = (long long)tree.leafCount();
    if (leaves == 0) return;
    constexpr int kLog2 = openvdb::FloatTree::LeafNodeType::LOG2DIM;
    openvdb::CoordBBox box;  // in blocks
    for (auto it = tree.cbeginLeaf(); it; ++it) box.expand(it->origin() >> kLog2);
    const openvdb::Coord n = box.dim();
    const long long blocks = (long long)n[0] * n[1] * n[2];
    auto& t = impl.leaves;
    if (blocks > DensityGrid::Impl::LeafTable::kMaxBlocksPerLeaf * leaves + 4096) return;
    t.lo = box.min();
    for (int a = 0; a < 3; ++a) t.n[a] = n[a];
    t.values.assign(size_t(blocks), nullptr);
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const openvdb::Coord b = (it->origin() >> kLog2) - t.lo;
        t.values[(size_t(b[0]) * n[1] + b[1]) * n[2] + b[2]] = it->buffer().data();
    }
}

}  // namespace

DensityGrid::DensityGrid(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
DensityGrid::~DensityGrid() = default;

std::shared_ptr<DensityGrid::Impl> DensityGrid::Impl::make(openvdb::FloatGrid::Ptr grid, const std::string& where,
                                                           const std::string& source_type)
{
    auto impl = std::make_shared<Impl>();
    impl->grid = grid;
    impl->source_type = source_type;
    const openvdb::math::Transform& xf = grid->transform();
    if (!xf.isLinear()) throw Error(where, "grid '" + grid->getName() + "' has a non-linear (frustum) transform");
    // Columns of the index→world linear map, measured rather than read, to be convention-proof.
    const openvdb::Vec3d o = xf.indexToWorld(openvdb::Vec3d(0, 0, 0));
    Eigen::Matrix3d A;
    for (int c = 0; c < 3; ++c) {
        openvdb::Vec3d e(0, 0, 0);
        e[c] = 1;
        const openvdb::Vec3d w = xf.indexToWorld(e) - o;
        A.col(c) = Eigen::Vector3d(w[0], w[1], w[2]);
    }
    if (!A.allFinite()) throw Error(where, "grid '" + grid->getName() + "' has a non-finite transform");
    const double det = A.determinant();
    const Eigen::Matrix3d G = A.transpose() * A;
    const double s2 = G.trace() / 3.0;
    if (!(std::abs(det) > 1e-300) || !(s2 > 0))
        throw Error(where, "grid '" + grid->getName() + "' has a singular transform");
    if ((G - s2 * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 * s2)
        throw Error(where, "grid '" + grid->getName() + "' has a non-uniform transform (voxels must be cubes)");
    impl->voxel_size_m = std::sqrt(s2);
    impl->w2i_lin = A.inverse();
    impl->w2i_off = -impl->w2i_lin * Eigen::Vector3d(o[0], o[1], o[2]);

    const float bg = grid->background();
    if (!(bg == 0.0f))
        throw Error(
            where,
            "grid '" + grid->getName() + "' has background " + std::to_string(bg) + "; smoke outside a grid must be 0");
    const ValueScan scan = scanValues(grid->tree());
    if (scan.bad) {
        // The first bad value in the tree's order, named as the serial scan names it.
        for (auto it = grid->cbeginValueAll(); it; ++it) {
            const float v = *it;
            if (!std::isfinite(v))
                throw Error(
                    where,
                    "grid '" + grid->getName() + "' holds a non-finite density at " + it.getCoord().asVec3i().str());
            if (v < 0.0f)
                throw Error(where,
                            "grid '" + grid->getName() + "' holds a negative density (" + std::to_string(v) + ") at " +
                                it.getCoord().asVec3i().str());
        }
    }
    const bool any = scan.any;
    const double lo = scan.lo, hi = scan.hi;
    impl->support = scan.support;
    impl->min_value = lo;
    impl->max_value = hi;
    buildLeafTable(*impl);
    const auto& table = impl->leaves;
    impl->empty_blocks_by_table = !scan.nonzero_tiles && !table.values.empty() &&
        std::max({table.n[0], table.n[1], table.n[2]}) <= Impl::kMaxEmptyBlocksAxis;
    if (any) {
        // World bounds of the support's outer voxel faces.
        const openvdb::Vec3d a = impl->support.min().asVec3d() - 0.5, b = impl->support.max().asVec3d() + 0.5;
        for (int k = 0; k < 8; ++k) {
            const openvdb::Vec3d c((k & 1) ? b[0] : a[0], (k & 2) ? b[1] : a[1], (k & 4) ? b[2] : a[2]);
            const openvdb::Vec3d w = xf.indexToWorld(c);
            impl->world_bounds.extend(Vec3(w[0], w[1], w[2]));
        }
    }
    return impl;
}

DensityGrid wrapFloatGrid(openvdb::FloatGrid::Ptr grid, const std::string& where)
{
    ensureOpenVdb();
    return DensityGrid(DensityGrid::Impl::make(grid, where));
}

namespace {

/// The grid to read: checks the file's structure first (vdb_header.hpp), then picks the named
/// grid, or the first float or double grid, and refuses a wrong type or an oversized grid before
/// OpenVDB reads any of its data.
std::string chooseVdbGrid(const std::string& path, const std::string& wanted)
{
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw Error(path, "no such file");
    if (!S_ISREG(st.st_mode)) throw Error(path, "is not a regular file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot read");
    const auto grids = detail::checkVdbHeader(in, uint64_t(st.st_size), path);
    const detail::VdbGridEntry* g = nullptr;
    std::string names;
    for (const auto& e : grids) {
        names += (names.empty() ? "" : ", ") + e.name;
        if (!g && (wanted.empty() ? (e.type == "float" || e.type == "double") : e.name == wanted)) g = &e;
    }
    if (!g && wanted.empty()) throw Error(path, "holds no float or double grid");
    if (!g) throw Error(path, "no grid named '" + wanted + "' (grids: " + (names.empty() ? "none" : names) + ")");
    if (g->type != "float" && g->type != "double")
        throw Error(
            path, "grid '" + g->name + "' holds " + g->type + " values; a density grid must be scalar float or double");
    if (g->voxels > limits::kGridVoxels)
        throw Error(path,
                    "grid '" + g->name + "' holds " + std::to_string(g->voxels) + " voxels, over the " +
                        std::to_string(limits::kGridVoxels) + " a grid may have");
    return g->name;
}

}  // namespace

DensityGrid DensityGrid::loadVdb(const std::string& path, const VdbLoadConfig& cfg)
{
    ensureOpenVdb();
    if (!(std::isfinite(cfg.scale) && cfg.scale > 0))
        throw Error(path, "scale must be finite and > 0, got " + std::to_string(cfg.scale));
    const std::string name = chooseVdbGrid(path, cfg.grid_name);
    openvdb::io::File file(path);
    try {
        file.open(false);
    } catch (const std::exception& e) {
        throw Error(path, std::string("cannot read as a VDB file (") + e.what() + ")");
    }
    openvdb::GridBase::Ptr base;
    try {
        base = file.readGrid(name);
    } catch (const std::exception& e) {
        throw Error(path, std::string("cannot read grid (") + e.what() + ")");
    }
    file.close();

    openvdb::FloatGrid::Ptr fgrid;
    std::string type = base->valueType();
    if (auto f = openvdb::gridPtrCast<openvdb::FloatGrid>(base)) {
        fgrid = f;
    } else if (auto d = openvdb::gridPtrCast<openvdb::DoubleGrid>(base)) {
        // Value-converting deep copy keeps the tree's topology (tiles stay tiles).
        fgrid = openvdb::FloatGrid::create(std::make_shared<openvdb::FloatTree>(d->tree()));
        fgrid->setTransform(d->transform().copy());
        fgrid->setName(d->getName());
        for (auto it = d->cbeginValueAll(); it; ++it)  // double values beyond float range
            if (std::isfinite(*it) && !std::isfinite(float(*it)))
                throw Error(path, "grid '" + d->getName() + "' holds a value beyond float range");
    } else {
        throw Error(
            path,
            "grid '" + base->getName() + "' holds " + type + " values; a density grid must be scalar float or double");
    }
    if (cfg.scale != 1.0) {
        const float s = float(cfg.scale);
        for (auto it = fgrid->beginValueAll(); it; ++it) it.setValue(*it * s);
    }
    fgrid->setGridClass(openvdb::GRID_FOG_VOLUME);
    return DensityGrid(Impl::make(fgrid, path, type));
}

DensityGrid DensityGrid::fromMesh(const std::vector<Vec3>& points_m, const std::vector<std::array<int, 3>>& triangles,
                                  double value, double voxel_size_m, double edge_m)
{
    ensureOpenVdb();
    if (!(voxel_size_m > 0) || !std::isfinite(voxel_size_m)) throw Error("", "voxel size must be > 0");
    if (!(value >= 0) || !std::isfinite(value)) throw Error("", "smoke density must be finite and >= 0");
    if (!(edge_m >= 0) || !std::isfinite(edge_m)) throw Error("", "edge must be finite and >= 0");
    auto xf = openvdb::math::Transform::createLinearTransform(voxel_size_m);
    std::vector<openvdb::Vec3s> pts;
    pts.reserve(points_m.size());
    for (const Vec3& p : points_m) pts.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(triangles.size());
    for (const auto& t : triangles) {
        for (int k : t)
            if (k < 0 || size_t(k) >= points_m.size()) throw Error("", "mesh triangle index out of range");
        tris.emplace_back(t[0], t[1], t[2]);
    }
    // The narrow band must reach edge_m inside the surface for the ramp.
    const float half_width = std::max(3.0f, float(std::ceil(edge_m / voxel_size_m)) + 2.0f);
    auto sdf = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xf, pts, tris, half_width);
    openvdb::FloatGrid::Ptr grid;
    if (edge_m > 0) {
        openvdb::tools::sdfToFogVolume(*sdf, float(edge_m));  // 0 at the surface → 1 at depth edge_m
        // sdfToFogVolume leaves band voxels deeper than the cutoff above 1: clamp them.
        const float v = float(value);
        for (auto it = sdf->tree().beginValueAll(); it; ++it) it.setValue(std::min(*it, 1.0f) * v);
        grid = sdf;
    } else {
        // Box filtering: a voxel is smoke when its centre is inside the surface.
        auto mask = openvdb::tools::sdfInteriorMask(*sdf);
        grid = openvdb::FloatGrid::create(
            std::make_shared<openvdb::FloatTree>(mask->tree(), 0.0f, float(value), openvdb::TopologyCopy()));
    }
    openvdb::tools::prune(grid->tree());  // constant leaves become tiles
    grid->setTransform(xf);
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setName("density");
    return DensityGrid(Impl::make(grid, "mesh"));
}

DensityGrid DensityGrid::box(const Vec3& lo, const Vec3& hi, double value, double voxel_size_m, double edge_m)
{
    if (!(hi.array() > lo.array()).all()) throw Error("", "smoke box must have hi > lo on every axis");
    std::vector<Vec3> p;
    for (int k = 0; k < 8; ++k)
        p.emplace_back((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    // Two outward-wound triangles per face.
    const std::vector<std::array<int, 3>> t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return fromMesh(p, t, value, voxel_size_m, edge_m);
}

DensityGrid DensityGrid::fromBlobs(const std::vector<Blob>& blobs, double voxel_size_m)
{
    ensureOpenVdb();
    const double inv_h = 1.0 / voxel_size_m;
    // Each blob's cube of voxels, 3σ around its centre (voxel centres sit at integer index points).
    struct Cube {
        Vec3 c;
        double r, inv2s2, peak;
        openvdb::Coord lo, hi;
    };
    std::vector<Cube> cubes;
    for (const Blob& b : blobs) {
        if (!(b.sigma_m > 0) || !(b.peak > 0)) continue;
        Cube q;
        q.c = b.centre_m * inv_h;
        q.r = 3.0 * b.sigma_m * inv_h;
        q.inv2s2 = 0.5 / (b.sigma_m * b.sigma_m * inv_h * inv_h);
        q.peak = b.peak;
        q.lo = openvdb::Coord(int(std::floor(q.c.x() - q.r)), int(std::floor(q.c.y() - q.r)),
                              int(std::floor(q.c.z() - q.r)));
        q.hi =
            openvdb::Coord(int(std::ceil(q.c.x() + q.r)), int(std::ceil(q.c.y() + q.r)), int(std::ceil(q.c.z() + q.r)));
        cubes.push_back(q);
    }
    // Columns one leaf wide along x and y, rasterised in parallel: a voxel lies in one column and
    // sums its blobs there in their order, so the grid is the same whatever the thread count.
    // Only the columns some cube reaches, each with the cubes that reach it (the work stays the
    // voxels'; a plume drifting along one axis still gives both cores work).
    constexpr int kLog2Leaf = openvdb::FloatTree::LeafNodeType::LOG2DIM;
    using Column = std::pair<int, int>;
    std::vector<std::pair<Column, size_t>> reach;  // (column, cube), sorted: the cubes in order in each
    for (size_t n = 0; n < cubes.size(); ++n)
        for (int cx = cubes[n].lo.x() >> kLog2Leaf; cx <= cubes[n].hi.x() >> kLog2Leaf; ++cx)
            for (int cy = cubes[n].lo.y() >> kLog2Leaf; cy <= cubes[n].hi.y() >> kLog2Leaf; ++cy)
                reach.push_back({{cx, cy}, n});
    std::sort(reach.begin(), reach.end());
    std::vector<size_t> starts;  // where each column's run of `reach` starts
    for (size_t k = 0; k < reach.size(); ++k)
        if (k == 0 || reach[k].first != reach[k - 1].first) starts.push_back(k);
    starts.push_back(reach.size());
    std::vector<openvdb::FloatGrid::Ptr> parts(starts.size() - 1);
    tbb::parallel_for(size_t(0), parts.size(), [&](size_t g) {
        auto part = openvdb::FloatGrid::create(0.0f);
        auto acc = part->getAccessor();
        const int ax = reach[starts[g]].first.first * (1 << kLog2Leaf), bx = ax + (1 << kLog2Leaf) - 1;
        const int ay = reach[starts[g]].first.second * (1 << kLog2Leaf), by = ay + (1 << kLog2Leaf) - 1;
        for (size_t k = starts[g]; k < starts[g + 1]; ++k) {
            const Cube& q = cubes[reach[k].second];
            for (int i = std::max(q.lo.x(), ax); i <= std::min(q.hi.x(), bx); ++i)
                for (int j = std::max(q.lo.y(), ay); j <= std::min(q.hi.y(), by); ++j)
                    for (int k2 = q.lo.z(); k2 <= q.hi.z(); ++k2) {
                        const double d2 = (Vec3(i, j, k2) - q.c).squaredNorm();
                        if (d2 > q.r * q.r) continue;
                        const openvdb::Coord ijk(i, j, k2);
                        acc.setValueOn(ijk, acc.getValue(ijk) + float(q.peak * std::exp(-d2 * q.inv2s2)));
                    }
        }
        parts[g] = part;
    });
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size_m));
    grid->setGridClass(openvdb::GRID_FOG_VOLUME);
    grid->setName("density");
    for (const auto& part : parts) grid->tree().merge(part->tree());  // disjoint leaves: moved, not summed
    return DensityGrid(Impl::make(grid, "plume"));
}

DensityGrid DensityGrid::scaled(double factor) const
{
    if (!(factor >= 0) || !std::isfinite(factor)) throw Error("", "density scale must be finite and >= 0");
    auto g = impl_->grid->deepCopy();
    const float s = float(factor);
    for (auto it = g->beginValueAll(); it; ++it) it.setValue(*it * s);
    return DensityGrid(Impl::make(g, g->getName(), impl_->source_type));
}

std::vector<std::pair<Aabb, double>> DensityGrid::blockMaxima() const
{
    const auto& g = *impl_->grid;
    auto worldBox = [&](const openvdb::CoordBBox& b) {
        Aabb w;
        const openvdb::Vec3d lo = b.min().asVec3d() - 0.5, hi = b.max().asVec3d() + 0.5;
        for (int k = 0; k < 8; ++k) {
            const openvdb::Vec3d c((k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]);
            const openvdb::Vec3d p = g.transform().indexToWorld(c);
            w.extend(Vec3(p[0], p[1], p[2]));
        }
        return w;
    };
    std::vector<std::pair<Aabb, double>> out;
    for (auto leaf = g.tree().cbeginLeaf(); leaf; ++leaf) {
        float m = 0.0f;
        for (auto v = leaf->cbeginValueAll(); v; ++v) m = std::max(m, *v);
        if (m > 0.0f) out.emplace_back(worldBox(leaf->getNodeBoundingBox()), double(m));
    }
    // Tiles at every internal level (ValueAll over non-leaf depths visits tiles only).
    auto it = g.tree().cbeginValueAll();
    it.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
    for (; it; ++it) {
        if (*it <= 0.0f) continue;
        openvdb::CoordBBox b;
        it.getBoundingBox(b);
        out.emplace_back(worldBox(b), double(*it));
    }
    return out;
}

GridInfo DensityGrid::info() const
{
    const auto& g = *impl_->grid;
    GridInfo i;
    i.name = g.getName();
    i.source_type = impl_->source_type;
    i.voxel_size_m = impl_->voxel_size_m;
    i.active_voxels = (long long)g.tree().activeVoxelCount();  // voxels in tiles included, as vdb_print counts
    i.leaf_nodes = (long long)g.tree().leafCount();
    i.active_tiles = (long long)g.tree().activeTileCount();
    for (int a = 0; a < 3; ++a) {
        i.index_min[a] = impl_->support.min()[a];
        i.index_max[a] = impl_->support.max()[a];
    }
    i.world_bounds = impl_->world_bounds;
    i.min_value = impl_->min_value;
    i.max_value = impl_->max_value;
    i.memory_bytes = g.memUsage();
    return i;
}

const Aabb& DensityGrid::worldBounds() const { return impl_->world_bounds; }
double DensityGrid::voxelSize() const { return impl_->voxel_size_m; }
double DensityGrid::maxValue() const { return impl_->max_value; }

void DensityGrid::writeVdb(const std::string& path, const std::vector<std::pair<std::string, DensityGrid>>& grids)
{
    ensureOpenVdb();
    openvdb::GridPtrVec out;
    for (const auto& [name, g] : grids) {
        auto copy = g.impl().grid->copyGrid();  // shares the tree, own metadata
        copy->setName(name);
        out.push_back(copy);
    }
    AtomicFile file(path);
    try {
        openvdb::io::File f(file.tempPath());
        f.write(out);
        f.close();
    } catch (const std::exception& e) {
        throw Error(path, std::string("cannot write (") + e.what() + ")");
    }
    file.commit();
}

}  // namespace smokescan
