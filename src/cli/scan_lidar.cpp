#include "scan_lidar.hpp"

#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "progress.hpp"
#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/lidar/frame_pictures.hpp"
#include "smokescan/lidar/point_cloud_io.hpp"
#include "smokescan/pipeline/lidar_run.hpp"
#include "smokescan/scene/scene.hpp"

namespace smokescan::cli {
namespace fs = std::filesystem;

int runLidarScan(const Scene& scene, const LidarScanArgs& a)
{
    RunFiles files;
    recordSceneInputs(files, a.scene, scene);
    files.input(a.sensor, "--sensor");
    files.outputFolder(a.points_dir, "--points");
    files.outputFolder(a.bag, "--bag");
    files.output(a.range_image, "--range-image");
    files.output(a.top_view, "--top-view");
    for (const auto& [path, option] :
         {std::pair{a.range_image, "--range-image"}, std::pair{a.top_view, "--top-view"}}) {
        if (path.empty()) continue;
        if (!isImageExtension(path)) throw Error(path, "unknown image format (png, exr, jpg, tif)");
        std::error_code e1, e2;
        if (!a.points_dir.empty() &&
            fs::weakly_canonical(fs::absolute(path), e1).parent_path() ==
                fs::weakly_canonical(fs::absolute(a.points_dir), e2) &&
            !e1 && !e2)
            throw Error(option, "'" + path + "' lies inside the --points folder, which must be new or empty");
    }
    if (a.points_dir.empty() && a.bag.empty())
        throw Error("--points", "a lidar's frames need a folder or a bag to go to (--points DIR, --bag DIR)");
    if (a.points_dir.empty() && a.format != "pcd") throw Error("--points-format", "goes with --points DIR");
    if (a.format != "pcd" && a.format != "ply") throw Error("--points-format", "must be pcd or ply");
    if (a.top_view_m != LidarScanArgs{}.top_view_m && a.top_view.empty())
        throw Error("--top-view-width", "needs --top-view");
    if (a.returns_given) parseReturnMode(a.returns, "--returns");  // "" too: the option was given
    LidarRunConfig cfg;
    cfg.sensor = a.sensor;
    cfg.returns = a.returns_given ? a.returns : "";
    cfg.rate_hz = a.rate_hz;
    cfg.columns = a.columns;
    cfg.from_s = a.from;
    cfg.to_s = a.to;
    cfg.seed = a.seed;
    const LidarRun run(scene, cfg);
    const LidarSpec& spec = run.spec();
    files.input(spec.pattern_file, "--sensor (its pattern file)");
    if (!a.range_image.empty() && spec.pattern != PatternKind::Spinning)
        throw Error("--range-image",
                    "the " + spec.name + " fires a pattern file: it has no channels × columns to draw");
    const ReturnMode mode = run.mode();
    const SensorMount& mount = run.mount();
    std::unique_ptr<AtomicFolder> out;
    if (!a.points_dir.empty()) out = std::make_unique<AtomicFolder>(a.points_dir, "the point-cloud folder", "--points");
    std::unique_ptr<ScanBag> bag;
    if (!a.bag.empty()) bag = std::make_unique<ScanBag>(a.bag, scene);
    // A planar pattern is a 2D multi-echo scanner: its frames also as MultiEchoLaserScans.
    const std::vector<PatternBeam> pattern = bag ? framePattern(spec) : std::vector<PatternBeam>{};
    const std::optional<PlanarFan> fan = planarFan(pattern);
    const long long frames = run.frames();
    const Progress progress("scanning", "lidar frames");
    long long points = 0, smoke = 0;
    std::string index = frameIndexHeader();
    RunControl control;
    control.progress = [&](long long done, long long total) { progress.update(done, total); };
    run.run(
        [&](LidarFrame&& f) {
            const long long k = (long long)f.index;
            char name[32];
            std::snprintf(name, sizeof name, "%06lld.%s", k, a.format.c_str());
            if (out) {
                (a.format == "pcd" ? writePcd : writePly)(out->path(name), f);
                index += frameIndexRow(f, name);
            }
            if (bag) bag->add(f, mount);
            if (bag && fan) bag->add(multiEchoOf(f, *fan, pattern.size(), spec, mount.name), mount);
            if (k == 0 && !a.range_image.empty()) writeImage(files.stage(a.range_image), rangeImage(f, spec, 0));
            if (k == 0 && !a.top_view.empty()) writeImage(files.stage(a.top_view), topView(f, a.top_view_m, 800));
            points += (long long)f.points.size();
            for (const LidarPoint& p : f.points) smoke += p.source == uint8_t(EchoSource::Smoke);
        },
        control);
    if (out) {
        AtomicFile csv(out->path("frames.csv"));
        csv.stream() << index;
        csv.commit();
    }
    if (bag) bag->finish();
    files.commit([&] {  // the folders last: when one fails, the pictures are taken back
        if (out) out->commit();
        if (bag) bag->commit();
    });
    char shape[96];
    if (spec.pattern == PatternKind::Spinning)
        std::snprintf(shape, sizeof shape, "%d channels x %d columns", spec.channels(), frameColumns(spec));
    else
        std::snprintf(shape, sizeof shape, "%zu beams a frame", spec.file_beams.size());
    say("wrote %s%s%s: %lld %s frames of the %s (%s, %g Hz, %s returns), %lld points, %lld from smoke\n",
        printable(a.points_dir).c_str(), a.points_dir.empty() || a.bag.empty() ? "" : ", ", printable(a.bag).c_str(),
        frames, a.points_dir.empty() ? "bag" : a.format.c_str(), spec.name.c_str(), shape, spec.rate_hz,
        returnModeName(mode), points, smoke);
    return 0;
}

}  // namespace smokescan::cli
