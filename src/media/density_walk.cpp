// Exact line integrals through an OpenVDB density grid.
//
// Box reconstruction: a hierarchical DDA. In "cell space" (index + ½) voxel c covers [c, c+1)³, so
// every node and tile is an aligned power-of-two cube. At each cell the walker finds where the
// value lives (the grid's leaf table, else the tree): inside a leaf it steps voxel by voxel
// (Amanatides–Woo, boundaries recomputed from integers on entering the leaf); anywhere else
// (background, constant tile) it crosses the whole constant cube in one step. Each step
// contributes value × length exactly.
//
// Trilinear reconstruction: the interpolant is a cubic polynomial along the ray inside each dual
// cell (between voxel centres), so 2-point Gauss–Legendre per cell is exact.
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "vdb_grid.hpp"

namespace smokescan {
namespace {

using TreeT = openvdb::FloatTree;
using LeafT = TreeT::LeafNodeType;
// Unregistered accessors: the walkers only read, and registration costs a concurrent hash-map
// insert per beam.
using Acc = openvdb::tree::ValueAccessor<const TreeT, /*IsSafe=*/false>;
using openvdb::Coord;

constexpr int kRootChildDim = TreeT::RootNodeType::ChildNodeType::DIM;  // 4096
constexpr int kUpperChildDim = TreeT::RootNodeType::ChildNodeType::ChildNodeType::DIM;  // 128
constexpr int kLeafDim = LeafT::DIM;  // 8

/// Edge length (voxels) of the constant cube a value stored at tree depth `depth` stands for.
inline int regionSize(int depth)
{
    switch (depth) {
    case -1:  // background: not in the root table
    case 0:
        return kRootChildDim;
    case 1:
        return kUpperChildDim;
    case 2:
        return kLeafDim;
    default:
        return 1;
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

// The voxel DDA's branch-free axis choice: a time held in a register and a mask (all ones or all
// zeros) from comparing two times. SSE2 scalar instructions on x86-64; elsewhere the same
// operations on the bits (build with -DSMOKESCAN_PORTABLE_DDA to test that path on x86).
#if defined(__SSE2__) && !defined(SMOKESCAN_PORTABLE_DDA)
struct Lane {
    __m128d v;
};
inline Lane lane(double x) { return {_mm_set_sd(x)}; }
inline double value(Lane a) { return _mm_cvtsd_f64(a.v); }
inline Lane le(Lane a, Lane b) { return {_mm_cmple_sd(a.v, b.v)}; }
inline Lane operator&(Lane a, Lane b) { return {_mm_and_pd(a.v, b.v)}; }
inline Lane operator|(Lane a, Lane b) { return {_mm_or_pd(a.v, b.v)}; }
inline Lane andNot(Lane a, Lane b) { return {_mm_andnot_pd(a.v, b.v)}; }  ///< ~a & b
inline Lane operator+(Lane a, Lane b) { return {_mm_add_sd(a.v, b.v)}; }
inline int bit(Lane m) { return _mm_movemask_pd(m.v) & 1; }
#else
struct Lane {
    uint64_t u;
};
inline Lane lane(double x)
{
    Lane l;
    std::memcpy(&l.u, &x, sizeof x);
    return l;
}
inline double value(Lane a)
{
    double x;
    std::memcpy(&x, &a.u, sizeof x);
    return x;
}
inline Lane le(Lane a, Lane b) { return {-uint64_t(value(a) <= value(b))}; }
inline Lane operator&(Lane a, Lane b) { return {a.u & b.u}; }
inline Lane operator|(Lane a, Lane b) { return {a.u | b.u}; }
inline Lane andNot(Lane a, Lane b) { return {~a.u & b.u}; }
inline Lane operator+(Lane a, Lane b) { return lane(value(a) + value(b)); }
inline int bit(Lane m) { return int(m.u & 1); }
#endif

/// Consecutive pieces of the line, structure of arrays: piece k covers [tb[k−1], tb[k]) (the
/// first starts at ta0) with the value *p[k] (a voxel, or a tile's value kept in `tile`).
template <int N>
struct Pieces {
    double ta0 = 0;
    double tb[N];
    const float* p[N];
    float tile[N];
    int n = 0;
};

/// Hierarchical walk with box-filtered voxels. visit(t0, t1, value) is called for each piece of
/// non-zero density, in order, and returns true to stop.
///
/// The walk is memory-bound on large grids (a leaf's voxels are a separate heap block), so it runs
/// one chunk ahead of the visits: the DDA, on registers and a cached table alone, writes the pieces
/// of chunk k+1 and prefetches their voxels while chunk k — whose loads were issued a chunk
/// earlier — is read and visited. The misses of many leaves then overlap instead of stalling one
/// by one.
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
    const auto& table = g.leaves;
    // Byte offsets, in the table, of the next leaf along each axis in the direction of travel.
    const intptr_t table_step[3] = {intptr_t(r.step[0]) * table.n[1] * table.n[2] * intptr_t(sizeof(const float*)),
                                    intptr_t(r.step[1]) * table.n[2] * intptr_t(sizeof(const float*)),
                                    intptr_t(r.step[2]) * intptr_t(sizeof(const float*))};
    // The values of the leaf holding cell c, or nullptr when c is not in a leaf.
    auto leafValues = [&](const Coord& c) -> const float* {
        if (table.values.empty()) {
            const LeafT* leaf = acc.probeConstLeaf(c);
            return leaf ? leaf->buffer().data() : nullptr;
        }
        int b[3];
        for (int a = 0; a < 3; ++a) {
            b[a] = (c[a] >> LeafT::LOG2DIM) - table.lo[a];
            if (unsigned(b[a]) >= unsigned(table.n[a])) return nullptr;
        }
        const size_t i = (size_t(b[0]) * table.n[1] + b[1]) * table.n[2] + b[2];
        const float* values = table.values[i];
        if (values) {
            // The line leaves through one of three faces: fetch those neighbours' entries now, so
            // the next lookup does not wait for the table (which the voxel stream evicts from cache).
            const uintptr_t base = uintptr_t(table.values.data() + i);
            for (int a = 0; a < 3; ++a) __builtin_prefetch((const void*)(base + table_step[a]));
        }
        return values;
    };

    double t = t0;  // where the walk is: the end of the last piece written
    // A line crosses at most 3·8 − 2 voxels of a leaf, so a chunk closed after kChunk pieces fits.
    constexpr int kChunk = 96, kCap = kChunk + 3 * kLeafDim;
    Pieces<kCap> buf[2];
    int cur = 0;
    buf[cur].ta0 = t0;
    // Visits the previous chunk and starts a new one; true when visit stopped. Rounding may leave a
    // piece of zero or (by an ulp) negative length: it is skipped, so the pieces visited ascend.
    auto flush = [&]() {
        Pieces<kCap>& q = buf[cur ^ 1];
        double ta = q.ta0;
        for (int k = 0; k < q.n; ++k) {
            const double tb = q.tb[k];
            if (!(tb > ta)) continue;
            const float v = *q.p[k];
            if (v != 0.0f && visit(ta, tb, double(v))) return true;
            ta = tb;
        }
        q.n = 0;
        q.ta0 = t;
        cur ^= 1;
        return false;
    };

    // Per-axis constants of the voxel DDA: time per voxel, offset per step inside a leaf.
    static constexpr int kStride[3] = {kLeafDim * kLeafDim, kLeafDim, 1};
    const Lane dx = lane(r.still[0] ? 0.0 : std::abs(r.inv[0])), dy = lane(r.still[1] ? 0.0 : std::abs(r.inv[1])),
               dz = lane(r.still[2] ? 0.0 : std::abs(r.inv[2]));
    int doff[3];
    for (int a = 0; a < 3; ++a) doff[a] = r.step[a] * kStride[a];
    // Leaf entry without branches: steps left in the leaf = left0 + left_per_l·(cell & 7), and the
    // next boundary time = (cell + up − o)·inv + never (never = ∞ on an axis without motion).
    int left0[3], left_per_l[3], up[3];
    double inv[3], never[3];
    for (int a = 0; a < 3; ++a) {
        left0[a] = r.still[a] ? kLeafDim : (r.step[a] > 0 ? kLeafDim - 1 : 0);
        left_per_l[a] = r.still[a] ? 0 : -r.step[a];
        up[a] = r.step[a] > 0 ? 1 : 0;
        inv[a] = r.still[a] ? 0.0 : r.inv[a];
        never[a] = r.still[a] ? kInf : 0.0;
    }

    Coord c;
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(cellOf(r.o[a] + r.d[a] * t0, r.d[a]), smin[a], smax[a]);
    while (t < t1 && g.support.isInside(c)) {
        Pieces<kCap>& out = buf[cur];
        int n = out.n;
        if (const float* data = leafValues(c)) {
            // Inside a leaf: Amanatides–Woo, one piece per voxel. Boundary times are computed from
            // integers on entry and advanced by dt inside the leaf (≤ 8 additions per axis). They
            // live in vector registers and the axis is chosen by bit masks, so the loop has no
            // data-dependent branch to mispredict.
            int off = 0, left[3];  // steps left before leaving the leaf along each axis
            double tn[3];
            for (int a = 0; a < 3; ++a) {
                const int l = c[a] & (kLeafDim - 1);
                off += l * kStride[a];
                left[a] = left0[a] + left_per_l[a] * l;
                tn[a] = (double(c[a] + up[a]) - r.o[a]) * inv[a] + never[a];  // = r.boundaryT(a, c[a], 1)
            }
            Lane tx = lane(tn[0]), ty = lane(tn[1]), tz = lane(tn[2]);
            int lx = left[0], ly = left[1], lz = left[2];
            double te;
            for (;;) {
                // The nearest boundary; ties go to the lowest axis.
                const Lane mx = le(tx, ty) & le(tx, tz);
                const Lane my = andNot(mx, le(ty, tz));
                te = std::min(std::min(std::min(value(tx), value(ty)), value(tz)), t1);
                out.tb[n] = te;
                out.p[n] = data + off;
                __builtin_prefetch(data + off);
                ++n;
                if (te >= t1) break;
                const int sx = bit(mx), sy = bit(my), sz = 1 - sx - sy;
                const int axis = 2 - 2 * sx - sy;
                lx -= sx;
                ly -= sy;
                lz -= sz;
                if ((lx | ly | lz) < 0) break;  // left the leaf
                off += doff[axis];
                tx = tx + (mx & dx);
                ty = ty + (my & dy);
                tz = tz + andNot(mx | my, dz);
            }
            out.n = n;
            t = std::max(t, te);
            if (te >= t1) break;
            // The cell entered: every axis moved by the steps it took in the leaf; the exit axis
            // by one more, out of the leaf.
            const int now[3] = {lx, ly, lz};
            for (int a = 0; a < 3; ++a) c[a] += r.step[a] * (left[a] - now[a]);
        } else {
            // Background or a constant tile: the whole cube in one step. Where no tile holds smoke
            // and the leaf table is compact, the cell's empty 8³ block without the tree.
            int S = kLeafDim;
            float v = 0.0f;
            if (!g.empty_blocks_by_table) {
                const int depth = acc.getValueDepth(c);
                v = depth < 0 ? 0.0f : acc.getValue(c);
                S = regionSize(depth);
            }
            const Coord lo(c[0] & ~(S - 1), c[1] & ~(S - 1), c[2] & ~(S - 1));
            double tn[3];
            for (int a = 0; a < 3; ++a) tn[a] = r.boundaryT(a, lo[a], S);
            const int a = argmin3(tn);
            const double te = std::min(tn[a], t1);
            out.tb[n] = te;
            out.tile[n] = v;
            out.p[n] = &out.tile[n];
            out.n = n + 1;
            t = std::max(t, te);
            if (t < t1) {
                for (int b = 0; b < 3; ++b)
                    if (b != a) c[b] = std::clamp(cellOf(r.o[b] + r.d[b] * t, r.d[b]), lo[b], lo[b] + S - 1);
                c[a] = r.step[a] > 0 ? lo[a] + S : lo[a] - 1;
            }
        }
        if (buf[cur].n >= kChunk && flush()) return;
    }
    if (!flush()) flush();
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
        const Vec3 w((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(),
                     (k & 4) ? box.hi.z() : box.lo.z());
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
    return acc.getValue(Coord(int(std::floor(x[0] + 0.5)), int(std::floor(x[1] + 0.5)), int(std::floor(x[2] + 0.5))));
}

}  // namespace smokescan
