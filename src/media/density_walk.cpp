// Exact line integrals through an OpenVDB density grid.
//
// Box reconstruction: a hierarchical DDA. In "cell space" (index + ½) voxel c covers [c, c+1)³, so
// every node and tile is an aligned power-of-two cube. At each cell the walker asks the tree where
// the value lives: inside a leaf it steps voxel by voxel (Amanatides–Woo, boundaries recomputed
// from integers so nothing drifts); anywhere else (background, constant tile) it crosses the whole
// constant cube in one step. Each step contributes value × length exactly.
//
// Trilinear reconstruction: the interpolant is a cubic polynomial along the ray inside each dual
// cell (between voxel centres), so 2-point Gauss–Legendre per cell is exact.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

#include "vdb_grid.hpp"

namespace smokescan {
namespace {

using TreeT = openvdb::FloatTree;
using LeafT = TreeT::LeafNodeType;
// Unregistered accessors: the walkers only read, and registration costs a concurrent hash-map
// insert per beam.
using Acc = openvdb::tree::ValueAccessor<const TreeT, /*IsSafe=*/false>;
using openvdb::Coord;

constexpr int kRootChildDim = TreeT::RootNodeType::ChildNodeType::DIM;                // 4096
constexpr int kUpperChildDim = TreeT::RootNodeType::ChildNodeType::ChildNodeType::DIM;  // 128
constexpr int kLeafDim = LeafT::DIM;                                                  // 8

/// Edge length (voxels) of the constant cube a value stored at tree depth `depth` stands for.
inline int regionSize(int depth)
{
    switch (depth) {
        case -1:  // background: not in the root table
        case 0: return kRootChildDim;
        case 1: return kUpperChildDim;
        case 2: return kLeafDim;
        default: return 1;
    }
}

/// Cell of coordinate x for a ray moving with direction d: on an exact boundary, the cell ahead.
inline int cellOf(double x, double d) { return d >= 0 ? int(std::floor(x)) : int(std::ceil(x)) - 1; }

struct IndexRay {
    double o[3], d[3], inv[3];
    int step[3];
    bool still[3];  // no motion along this axis
    double boundaryT(int a, int cell_lo, int size) const
    {
        if (still[a]) return kInf;
        return (double(cell_lo + (step[a] > 0 ? size : 0)) - o[a]) * inv[a];
    }
};

IndexRay toIndex(const DensityGrid::Impl& g, const Ray& ray, double shift)
{
    const Eigen::Vector3d o = g.w2i_lin * ray.o + g.w2i_off + Eigen::Vector3d::Constant(shift);
    const Eigen::Vector3d d = g.w2i_lin * ray.d;
    IndexRay r;
    for (int a = 0; a < 3; ++a) {
        r.o[a] = o[a];
        r.d[a] = d[a];
        r.still[a] = d[a] == 0.0;
        r.inv[a] = r.still[a] ? 0.0 : 1.0 / d[a];
        r.step[a] = d[a] >= 0 ? 1 : -1;
    }
    return r;
}

/// Clips [t0, t1] to the cube [lo, hi] in the walker's space.
bool clipTo(const IndexRay& r, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double& t0, double& t1)
{
    for (int a = 0; a < 3; ++a) {
        if (r.still[a]) {
            if (r.o[a] < lo[a] || r.o[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - r.o[a]) * r.inv[a], tb = (hi[a] - r.o[a]) * r.inv[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 < t1;
}

/// Axis of the nearest boundary (ties: the lowest axis), written as selects.
inline int argmin3(const double t[3])
{
    const int a = t[1] < t[0] ? 1 : 0;
    return t[2] < t[a] ? 2 : a;
}

/// Hierarchical walk with box-filtered voxels. visit(t0, t1, value) returns true to stop.
template <class Visit>
void walkBox(const DensityGrid::Impl& g, const Ray& ray, double t0, double t1, Visit&& visit)
{
    if (g.support.empty()) return;
    const IndexRay r = toIndex(g, ray, 0.5);
    const Coord smin = g.support.min(), smax = g.support.max();
    if (!clipTo(r, Eigen::Vector3d(smin[0], smin[1], smin[2]),
                Eigen::Vector3d(smax[0] + 1.0, smax[1] + 1.0, smax[2] + 1.0), t0, t1))
        return;
    Acc acc(g.grid->tree());
    Coord c;
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(cellOf(r.o[a] + r.d[a] * t0, r.d[a]), smin[a], smax[a]);
    double t = t0;
    while (t < t1 && g.support.isInside(c)) {
        // One query per region: where does the value of cell c live?
        const int depth = acc.getValueDepth(c);
        if (depth == int(TreeT::DEPTH) - 1) {
            // Inside a leaf. The walk is memory-bound (a leaf's voxels are a separate heap block),
            // so first run the DDA on integers alone — offsets and lengths, prefetching each voxel
            // — then gather: the loads are independent and their cache misses overlap.
            const LeafT* leaf = acc.probeConstLeaf(c);
            const float* data = leaf->buffer().data();
            int lc[3], doff[3];
            double tn[3];
            static constexpr int kStride[3] = {kLeafDim * kLeafDim, kLeafDim, 1};
            int off = 0;
            for (int a = 0; a < 3; ++a) {
                lc[a] = c[a] & (kLeafDim - 1);
                off += lc[a] * kStride[a];
                doff[a] = r.step[a] * kStride[a];
                tn[a] = r.boundaryT(a, c[a], 1);
            }
            struct Piece { int off; double ta, tb; };
            Piece pieces[3 * kLeafDim];  // a line crosses at most 3·8 − 2 voxels of a leaf
            int n = 0;
            bool end = false;
            for (;;) {
                const int a = argmin3(tn);
                const double te = std::min(tn[a], t1);
                if (te > t) {
                    __builtin_prefetch(data + off);
                    pieces[n++] = {off, t, te};
                }
                t = std::max(t, te);
                if (t >= t1) {
                    end = true;
                    break;
                }
                c[a] += r.step[a];
                lc[a] += r.step[a];
                if (unsigned(lc[a]) >= unsigned(kLeafDim)) break;  // left the leaf
                off += doff[a];
                tn[a] = r.boundaryT(a, c[a], 1);
            }
            for (int k = 0; k < n; ++k)
                if (visit(pieces[k].ta, pieces[k].tb, double(data[pieces[k].off]))) return;
            if (end) return;
        } else {
            const double v = depth < 0 ? 0.0 : double(acc.getValue(c));
            const int S = regionSize(depth);
            const Coord lo(c[0] & ~(S - 1), c[1] & ~(S - 1), c[2] & ~(S - 1));
            double tn[3];
            for (int a = 0; a < 3; ++a) tn[a] = r.boundaryT(a, lo[a], S);
            const int a = argmin3(tn);
            const double te = std::min(tn[a], t1);
            if (te > t && v != 0.0 && visit(t, te, v)) return;
            t = std::max(t, te);
            if (t >= t1) return;
            for (int b = 0; b < 3; ++b)
                if (b != a) c[b] = std::clamp(cellOf(r.o[b] + r.d[b] * t, r.d[b]), lo[b], lo[b] + S - 1);
            c[a] = r.step[a] > 0 ? lo[a] + S : lo[a] - 1;
        }
    }
}

/// Per dual cell walk with trilinear reconstruction; visit(t0, t1, mean density on the piece).
template <class Visit>
void walkTrilinear(const DensityGrid::Impl& g, const Ray& ray, double t0, double t1, Visit&& visit)
{
    if (g.support.empty()) return;
    const IndexRay r = toIndex(g, ray, 0.0);
    const Coord smin = g.support.min(), smax = g.support.max();
    // The interpolant vanishes beyond one voxel outside the support.
    if (!clipTo(r, Eigen::Vector3d(smin[0] - 1.0, smin[1] - 1.0, smin[2] - 1.0),
                Eigen::Vector3d(smax[0] + 1.0, smax[1] + 1.0, smax[2] + 1.0), t0, t1))
        return;
    Acc acc(g.grid->tree());
    auto f = [&](double t) {
        const openvdb::Vec3R p(r.o[0] + r.d[0] * t, r.o[1] + r.d[1] * t, r.o[2] + r.d[2] * t);
        return double(openvdb::tools::BoxSampler::sample(acc, p));
    };
    Coord c;
    double tn[3];
    for (int a = 0; a < 3; ++a) {
        c[a] = cellOf(r.o[a] + r.d[a] * t0, r.d[a]);
        tn[a] = r.boundaryT(a, c[a], 1);
    }
    static const double kGl = 0.5 / std::sqrt(3.0);  // Gauss–Legendre nodes on [0,1]: ½ ± 1/(2√3)
    double t = t0;
    while (t < t1) {
        const int a = argmin3(tn);
        const double te = std::min(tn[a], t1);
        if (te > t) {
            const double h = te - t, m = 0.5 * (t + te);
            const double mean = 0.5 * (f(m - kGl * h) + f(m + kGl * h));
            if (mean != 0.0 && visit(t, te, mean)) return;
        }
        t = std::max(t, te);
        c[a] += r.step[a];
        tn[a] = r.boundaryT(a, c[a], 1);
    }
}

}  // namespace

double DensityGrid::integrate(const Ray& ray, double t0_m, double t1_m, Reconstruction recon,
                              std::vector<ProfileSegment>* profile) const
{
    if (!(t1_m > t0_m)) return 0.0;
    double sum = 0.0;
    auto visit = [&](double a, double b, double v) {
        if (v == 0.0) return false;
        sum += v * (b - a);
        if (profile) {
            if (!profile->empty() && profile->back().t1_m == a && profile->back().density == v)
                profile->back().t1_m = b;
            else
                profile->push_back({a, b, v});
        }
        return false;
    };
    if (recon == Reconstruction::Box)
        walkBox(*impl_, ray, t0_m, t1_m, visit);
    else
        walkTrilinear(*impl_, ray, t0_m, t1_m, visit);
    return sum;
}

double DensityGrid::firstAbove(const Ray& ray, double t0_m, double t1_m, double threshold) const
{
    double hit = kInf;
    if (!(t1_m > t0_m) || impl_->max_value < threshold) return hit;
    walkBox(*impl_, ray, t0_m, t1_m, [&](double a, double, double v) {
        if (v >= threshold) {
            hit = a;
            return true;
        }
        return false;
    });
    return hit;
}

bool DensityGrid::rangeIn(const Aabb& box, double& mn, double& mx, long long max_voxels) const
{
    const auto& g = *impl_;
    if (box.empty()) return false;
    // Index-space bounds of the box's corners; voxel c covers [c − ½, c + ½).
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf), hi = -lo;
    for (int k = 0; k < 8; ++k) {
        const Vec3 w((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(), (k & 4) ? box.hi.z() : box.lo.z());
        const Eigen::Vector3d x = g.w2i_lin * w + g.w2i_off;
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    Coord a, b;
    long long count = 1;
    for (int k = 0; k < 3; ++k) {
        a[k] = int(std::floor(lo[k] + 0.5));
        b[k] = int(std::floor(hi[k] + 0.5));
        count *= (long long)(b[k] - a[k] + 1);
    }
    if (count > max_voxels) return false;
    const openvdb::CoordBBox region(a, b);
    double lo_v = kInf, hi_v = 0;
    if (!g.support.isInside(region)) lo_v = 0;  // some of it is background
    Acc acc(g.grid->tree());
    for (auto it = region.begin(); it; ++it) {
        const double v = acc.getValue(*it);
        lo_v = std::min(lo_v, v);
        hi_v = std::max(hi_v, v);
    }
    mn = lo_v;
    mx = hi_v;
    return true;
}

double DensityGrid::sample(const Vec3& p_m, Reconstruction recon) const
{
    const Eigen::Vector3d x = impl_->w2i_lin * p_m + impl_->w2i_off;
    Acc acc(impl_->grid->tree());
    if (recon == Reconstruction::Trilinear)
        return openvdb::tools::BoxSampler::sample(acc, openvdb::Vec3R(x[0], x[1], x[2]));
    return acc.getValue(Coord(int(std::floor(x[0] + 0.5)), int(std::floor(x[1] + 0.5)),
                              int(std::floor(x[2] + 0.5))));
}

}  // namespace smokescan
