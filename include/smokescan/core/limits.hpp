#pragma once
/// @file limits.hpp
/// @brief The bounds on every size a user can set, checked before work starts (docs/limits.md
/// lists them with the option or key each bounds). A request beyond one is a one-line error
/// naming the option or key; nothing is allocated or computed first.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace smokescan::limits {

/// Bytes of one text input (laser log, CSV, scene, sensor file, calibration, beam groups).
inline constexpr size_t kTextInputBytes = size_t(512) << 20;
/// Bytes of a scene or sensor file (TOML): its parsed tables take about 15 times the text's size.
inline constexpr size_t kTomlInputBytes = size_t(32) << 20;
/// Bytes of one point-cloud file read back (8 M points of 64 bytes).
inline constexpr size_t kPointCloudBytes = size_t(512) << 20;
/// Bytes of one MCAP chunk or record, compressed or not (a bag's memory is bounded by it).
inline constexpr uint64_t kBagChunkBytes = uint64_t(256) << 20;
/// Ranges read from one bag topic, all scans together (about what a 512 MiB text log holds).
inline constexpr int64_t kBagBeams = 50'000'000;
/// Messages read from one bag topic.
inline constexpr int64_t kBagMessages = 10'000'000;
/// Scans in one `scan` run.
inline constexpr int64_t kScans = 1'000'000;
/// Readings a library run keeps in memory when no sink takes them one by one (pipeline/, the
/// Python module): a 2D laser's beams over all its scans, a lidar's points at most (every beam's
/// echoes) over all its frames.
inline constexpr int64_t kKeptReadings = 50'000'000;
/// Rows of `scan`'s summary table (--bin).
inline constexpr int64_t kSummaryRows = 10'000;
/// Scans drawn by `scan --image` (each 2 px tall).
inline constexpr int64_t kImageScans = 30'000;
/// Pixels of one rendered frame (width × height): 8192 × 8192.
inline constexpr int64_t kFramePixels = int64_t(8192) * 8192;
/// Width or height of one rendered frame [px].
inline constexpr int kFrameSide = 16384;
/// Samples per pixel of one frame.
inline constexpr int kSpp = 1 << 16;
/// Samples of one frame (pixels × spp), and of one calibration sweep (all its frames and batches).
inline constexpr int64_t kFrameSamples = int64_t(1) << 34;
/// Frames in one `render` time series, or camera frames in one `scan --saturation-render` run.
inline constexpr int64_t kFrames = 100'000;
/// Scattering/bounce events of one path (--max-depth).
inline constexpr int kPathDepth = 1'000'000;
/// Voxels of one grid made from a scene (box, mesh or plume), as estimated from its bounding box.
inline constexpr int64_t kGridVoxels = int64_t(1) << 30;
/// Voxels of a dense block a grid is read into or made from (media/dense_voxels.hpp): 1 GiB of floats.
inline constexpr int64_t kDenseVoxels = int64_t(1) << 28;
/// Densities in one calibration sweep; engine densities accepted there (the sweep's smoke).
inline constexpr int kCalibrationDensities = 1000;
inline constexpr double kCalibrationDensityMax = 1.0;
/// Memory a converged target measurement may hold in frames [bytes] (camera/target_radiance.hpp).
inline constexpr int64_t kConvergedBytes = int64_t(2) << 30;
/// Largest smoke density (engine units; the paper's threshold is 0.0028) of a box, mesh, plume
/// puff or timeline factor: beyond it optical depths overflow.
inline constexpr double kDensity = 1e6;
/// How far from the scene's origin a position may lie [m] (sensors, cameras, lights, robots'
/// keyframes, smoke areas): 1000 km. Beyond about 1e18 m Embree's ray set-up asserts.
inline constexpr double kSceneReach_m = 1e6;
/// Voxels the live puffs of all of a scene's plumes may cover at once (each rasterised at every
/// instant a beam or camera needs): the bound is the scene's, not each plume's.
inline constexpr double kPlumeVoxels = 5e8;
/// Memory the grids of a scene's box and mesh smoke areas may take, as estimated from their
/// bounding boxes and soft edges before they are made [bytes].
inline constexpr double kGridBytes = 2.0e9;
/// Voxels a side of a box or mesh smoke area.
inline constexpr double kGridSide = 4000;
/// Density bins of `fit-plume`.
inline constexpr int kPlumeBins = 1000;
/// Triangles of one mesh.
inline constexpr int64_t kMeshTriangles = 50'000'000;
/// Keyframes of one robot's trajectory.
inline constexpr int64_t kKeyframes = 1'000'000;

/// A requested count for an error message, whatever its size ("1.75e+25"; never cast to an
/// integer, which is undefined beyond its range).
inline std::string count(double n)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, n < 1e15 ? "%.0f" : "%.3g", n);
    return buf;
}

}  // namespace smokescan::limits
