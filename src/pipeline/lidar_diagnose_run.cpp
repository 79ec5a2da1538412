#include "smokescan/pipeline/lidar_diagnose_run.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/lidar/frame_index.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan {
namespace {

bool hasField(const PointCloudFile& pc, const char* a, const char* b = nullptr)
{
    return std::any_of(pc.fields.begin(), pc.fields.end(),
                       [&](const std::string& f) { return f == a || (b && f == b); });
}

/// Refuses frames whose points mostly match no beam of the sensor (checked as they come).
void checkMatched(long long unmatched, long long first_returns, const std::string& points, const std::string& sensor)
{
    if (2 * unmatched > first_returns)
        throw Error(points,
                    std::to_string(unmatched) + " of " + std::to_string(first_returns) +
                        " points match no beam of the " + sensor +
                        " (by ring, firing time and direction): are these its frames, at its rate and "
                        "columns?");
}

}  // namespace

LidarDiagnoseRunResult runLidarDiagnosis(const LidarDiagnoseRunConfig& cfg, const RunControl& control)
{
    if (cfg.points.empty()) throw Error("--points", "names no folder");
    const Scene scene = loadScene(cfg.scene);
    if (cfg.on_scene) cfg.on_scene(scene);
    const std::vector<FrameIndexEntry> frames = readFrameIndex(cfg.points);
    if (frames.size() < 2)
        throw Error(cfg.points + "/frames.csv",
                    "holds " + std::to_string(frames.size()) +
                        " frames: the diagnosis needs two at least (one to search, one "
                        "held out)");
    LidarRunConfig sc = cfg.sensor;
    sc.from_s = frames.front().start_s;
    sc.to_s = NAN;
    const LidarRun run(scene, sc);
    const LidarScanner& scanner = run.scanner();
    const double readings = double(frames.size()) * double(scanner.pattern().size());
    if (readings > double(limits::kKeptReadings))
        throw Error("--points",
                    limits::count(double(frames.size())) + " frames of " +
                        limits::count(double(scanner.pattern().size())) + " beams would keep " +
                        limits::count(readings) + " readings (at most " + std::to_string(limits::kKeptReadings) +
                        "; fewer frames)");
    LidarTally tally(scanner.pattern(), run.spec().channels(), returnTolerance_m(run.spec()));
    LidarDiagnoseRunResult out;
    out.sensor = run.spec().name;
    double mismatch_m = 0, mismatch_deg = 0;
    long long first_returns = 0;
    for (size_t k = 0; k < frames.size(); ++k) {
        checkCancel(control);
        const FrameIndexEntry& e = frames[k];
        const std::string path = cfg.points + "/" + e.file;
        const PointCloudFile pc = readPointCloud(path);
        if (!hasField(pc, "ring") || !hasField(pc, "time", "t"))
            throw Error(path,
                        "has no ring or time field: the diagnosis tells a point's beam by its channel and "
                        "firing time");
        for (const LidarPoint& p : pc.points) first_returns += p.return_index == 0;
        tally.add(scanner.expected(e.start_s), pc.points, int(k % 2));
        if (first_returns >= 1000) checkMatched(tally.unmatched(), first_returns, cfg.points, out.sensor);
        const Pose scene_pose = scene.sensorAt(run.mount(), e.start_s).pose;
        mismatch_m = std::max(mismatch_m, (scene_pose.t - e.start_pose.t).norm());
        const double angle = Eigen::AngleAxisd(scene_pose.R.transpose() * e.start_pose.R).angle() * 180 / M_PI;
        mismatch_deg = std::max(mismatch_deg, angle);
        reportProgress(control, (long long)k + 1, (long long)frames.size());
    }
    checkMatched(tally.unmatched(), first_returns, cfg.points, out.sensor);
    out.diagnosis = diagnoseLidar(tally, run.spec().range_sigma_m, cfg.diag);
    for (const Surface& sf : scene.surfaces) out.diagnosis.surface_names.push_back(sf.name);
    out.diagnosis.pose_mismatch_m = mismatch_m;
    out.diagnosis.pose_mismatch_deg = mismatch_deg;
    return out;
}

void writeLidarDiagnosisFolder(AtomicFolder& out, const LidarDiagnoseRunResult& r)
{
    {
        AtomicFile f(out.path("diagnosis.json"));
        f.stream() << lidarDiagnosisJson(r.diagnosis);
        f.commit();
    }
    {
        AtomicFile f(out.path("report.md"));
        f.stream() << lidarDiagnosisMarkdown(r.diagnosis, r.sensor);
        f.commit();
    }
    out.commit();
}

}  // namespace smokescan
