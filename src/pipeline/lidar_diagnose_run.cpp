#include "smokescan/pipeline/lidar_diagnose_run.hpp"

#include <algorithm>

#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/pipeline/lidar_frames.hpp"

namespace smokescan {

LidarDiagnoseRunResult runLidarDiagnosis(const LidarDiagnoseRunConfig& cfg, const RunControl& control)
{
    LidarFramesConfig fc{cfg.scene, cfg.points, cfg.sensor, cfg.on_scene, {}, false, false, cfg.topic};
    fc.on_run = [](const LidarRun& run) {  // room in lidar.toml for one more sector
        if (run.spec().extensions.sectors.size() >= lidar_limits::kExtensionSectors)
            throw Error("--sensor",
                        "the " + run.spec().name + " already has " + std::to_string(lidar_limits::kExtensionSectors) +
                            " sectors, the most a preset holds: the extended preset could not add one");
    };
    LidarDiagnoseRunResult out;
    tallyLidarFrames(fc, 2, control, [&](const TalliedFrames& t) {
        out.sensor = t.run.spec().name;
        out.diagnosis = diagnoseLidar(t.tally, t.run.spec().range_sigma_m, cfg.diag);
        for (const Surface& sf : t.scene.surfaces) out.diagnosis.surface_names.push_back(sf.name);
        out.diagnosis.pose_mismatch_m = t.pose_mismatch_m;
        out.diagnosis.pose_mismatch_deg = t.pose_mismatch_deg;
        out.diagnosis.empty_frames = t.empty_frames;
        out.diagnosis.sensor = out.sensor;
        out.diagnosis.returns = returnModeName(t.run.mode());
        out.diagnosis.scene = t.scene.source;
        out.diagnosis.points = cfg.points;
        out.diagnosis.topic = t.topic;
        out.diagnosis.extended_preset = extendedLidarPreset(out.diagnosis, t.run.spec(), t.base);
    });
    return out;
}

std::string extendedLidarPreset(const LidarDiagnosis& d, const LidarSpec& diagnosed, const std::string& base)
{
    LidarExtensions e = diagnosed.extensions;
    // The dropout that turns the other beams' missed share into the group's: excess / (1 − theirs).
    auto dropout = [](const LidarFinding& f) {
        return std::clamp(f.effect / (1 - std::min(0.99, f.base_rate)), 0.0, 1.0);
    };
    auto channel = [&](int ring) -> LidarChannelExtension& {
        for (LidarChannelExtension& c : e.channels)
            if (c.ring == ring) return c;
        e.channels.push_back({ring, 0, 0});
        return e.channels.back();
    };
    std::string not_yet;
    for (const LidarFinding& f : d.tried) {
        if (!f.named) continue;
        switch (f.cause) {
        case LidarCause::DroppingChannel: {
            LidarChannelExtension& c = channel(f.ring);  // another dropout on top of the one it had
            c.dropout = 1 - (1 - c.dropout) * (1 - dropout(f));
            break;
        }
        case LidarCause::BiasedChannel:
            channel(f.ring).range_offset_m = std::clamp(channel(f.ring).range_offset_m + f.effect, -1.0, 1.0);
            break;
        case LidarCause::WindowSector:
            e.sectors.push_back({f.from_deg, f.to_deg, dropout(f)});
            break;
        case LidarCause::SmokeFirstReturns:
        case LidarCause::SurfaceThreshold:
            not_yet += std::string(not_yet.empty() ? "" : ", ") + lidarCauseName(f.cause) + " (" +
                lidarFindingTarget(d, f) + ")";
            break;
        }
    }
    std::sort(e.channels.begin(), e.channels.end(),
              [](const LidarChannelExtension& a, const LidarChannelExtension& b) { return a.ring < b.ring; });
    std::string o = "# The " + diagnosed.name + " extended by smokescan diagnose --points (verdict: " + d.verdict +
        ").\n# Scan with it: smokescan scan SCENE --sensor this_file.toml\n";
    for (char& c : not_yet)  // a surface's name on one comment line
        if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    if (!not_yet.empty()) o += "# Named but not an extension yet (docs/lidar.md): " + not_yet + "\n";
    return o + "name = " + tomlQuoted(extendedPresetName(diagnosed.name)) + "\nbase = " + tomlQuoted(base) + "\n" +
        lidarExtensionsToml(e);
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
    {
        AtomicFile f(out.path("lidar.toml"));
        f.stream() << r.diagnosis.extended_preset;
        f.commit();
    }
    out.commit();
}

}  // namespace smokescan
