// `smokescan omnirange`: the omnidirectional camera as a colour-based rangefinder beside a laser.
#include <cmath>
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "progress.hpp"
#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/limits.hpp"
#include "smokescan/io/atomic_file.hpp"
#include "smokescan/io/image.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/io/text_input.hpp"
#include "smokescan/omni/omni_compare.hpp"
#include "smokescan/omni/omni_log.hpp"
#include "smokescan/omni/omni_plots.hpp"
#include "smokescan/omni/omni_run.hpp"
#include "smokescan/omni/omni_scan_message.hpp"
#include "smokescan/omni/sensors_versus_smoke.hpp"
#include "smokescan/pipeline/omnirange_run.hpp"
#include "smokescan/scene/scene_io.hpp"

namespace smokescan::cli {
namespace {

struct OmniArgs {
    std::string scene, out, bag, laser_out, histogram, save_histogram, train, plot, map, fig8, truth;
    double from = NAN, to = NAN, rate_hz = 1;
    OmniRunConfig cfg;
};

/// The frame on the bag: the omnicam's ranges on /omni/scan, the laser's scan on /scan.
void addToBag(ScanBag& bag, const OmniFrame& f, const OmniRun& run, const Scene& scene, const OmniArgs& a)
{
    const Camera& cam = *scene.findCamera(run.cameraName());
    bag.add("/omni/scan", omniLaserScanOf(f.omni, a.cfg.range, f.time_s, 1 / a.rate_hz, cam.name), bagFrameOf(cam));
    Scan s;
    s.time_s = f.time_s;
    s.angle_rad = f.laser_angle_rad;
    s.value = f.laser_value;
    bag.add(s, run.laser().spec(), run.laser().mount());
}

int runOmnirange(const OmniArgs& a)
{
    const Scene scene = loadScene(a.scene);
    RunFiles files;
    recordSceneInputs(files, a.scene, scene);
    files.input(a.histogram, "--histogram");
    files.output(a.out, "--out");
    files.outputFolder(a.bag, "--bag");
    if (a.out.empty() && a.bag.empty()) throw Error("--out", "give where the ranges go: --out LOG, --bag DIR or both");
    files.output(a.laser_out, "--laser-out");
    files.output(a.save_histogram, "--save-histogram");
    files.output(a.plot, "--plot");
    files.output(a.map, "--map");
    files.output(a.fig8, "--fig8");
    files.output(a.truth, "--truth");
    for (const std::string* p : {&a.plot, &a.map, &a.fig8, &a.truth})
        if (!p->empty() && !isImageExtension(*p)) throw Error(*p, "unknown image format (png, jpg, tif)");
    OmnirangeRunConfig rc;
    rc.run = a.cfg;
    rc.train_s = a.train.empty() ? std::vector<double>{} : parseNumberList(a.train, "--train");
    rc.histogram = a.histogram;
    rc.from_s = a.from;
    rc.to_s = a.to;
    rc.rate_hz = a.rate_hz;
    OmnirangeRun omni(scene, rc);
    omni.train();
    OmniRun& run = omni.omni();
    const SurfaceSet& surfaces = omni.surfaces();
    const std::vector<double>& times = omni.times();
    const long long trained = omni.trainedPixels();
    std::unique_ptr<AtomicFile> log_file;
    if (!a.out.empty()) log_file = std::make_unique<AtomicFile>(files.stage(a.out));
    if (log_file)
        writeOmniLogHeader(log_file->stream(), scene.source, run.cameraName(),
                           a.histogram.empty() ? std::to_string(trained) + " pixels at " + a.train : a.histogram,
                           a.cfg.range);
    std::unique_ptr<AtomicFile> laser;
    if (!a.laser_out.empty()) {
        laser = std::make_unique<AtomicFile>(files.stage(a.laser_out));
        writeOmniLaserLogHeader(laser->stream(), scene.source, run.laser());
    }
    std::unique_ptr<ScanBag> bag;
    if (!a.bag.empty()) bag = std::make_unique<ScanBag>(a.bag, scene);
    std::unique_ptr<SensorsVersusSmoke> versus;
    if (!a.truth.empty()) {
        VersusSmokeConfig vc;
        vc.seed = a.cfg.seed;
        versus = std::make_unique<SensorsVersusSmoke>(scene, surfaces, a.cfg.range, vc);
    }
    const Progress progress("omnirange", "frames");
    OmniComparison cmp;
    cmp.outlier_m = a.cfg.outlier_m;
    std::vector<OmniFrame> kept;  // for --map
    RunControl control;
    control.progress = [&](long long done, long long total) { progress.update(done, total); };
    size_t k = 0;
    omni.run(
        [&](OmniFrame&& f) {
            if (log_file) writeOmniLogScan(log_file->stream(), f);
            if (laser) writeOmniLaserLogScan(laser->stream(), f, run.laser().spec());
            if (bag) addToBag(*bag, f, run, scene, a);
            cmp.add(f);
            if (versus) versus->add(f, run.rangeAt(f.time_s).height_m, (uint64_t(1) << 32) + k);
            if (!a.map.empty()) kept.push_back(std::move(f));
            ++k;
        },
        control);
    if (log_file) log_file->commit();
    if (bag) bag->finish();
    if (laser) laser->commit();
    if (!a.save_histogram.empty()) omni.histogram().save(files.stage(a.save_histogram));
    if (!a.plot.empty())
        writeDifferenceHistogram(files.stage(a.plot), cmp.differences_m, cmp.outlier_m,
                                 "laser - omnicam per scanline, " + scene.source);
    if (!a.map.empty()) writeOccupancyGrids(files.stage(a.map), kept, OccupancyConfig{});
    if (!a.fig8.empty())
        writePixelDistancePlot(files.stage(a.fig8), run.cameraAt(times.front()), run.rangeAt(times.front()).height_m,
                               a.cfg.range.max_range_m);
    if (versus)
        writeVersusSmokePlot(files.stage(a.truth), versus->tallies(),
                             "each sensor against the truth, by the smoke it looks through: " + scene.source);
    files.commit([&] {
        if (bag) bag->commit();
    });
    if (versus) {
        say("against the truth, by the smoke column along each line of sight:\n");
        for (const RangeTally& t : versus->tallies()) say("%s", t.table().c_str());
    }
    if (cmp.pairs == 0)
        say("omnicam against the laser: no scanline to compare (the omnicam read no hit where the laser "
            "read a range); %lld outliers over %.2f m\n",
            cmp.outliers, cmp.outlier_m);
    else
        say("omnicam against the laser: %lld scanline pairs, mean |difference| %.4f m, %.2f %%, mean "
            "(laser - omnicam) %+.4f m; %lld outliers over %.2f m left out\n",
            cmp.pairs, cmp.meanAbsM(), cmp.meanPercent(), cmp.meanSignedM(), cmp.outliers, cmp.outlier_m);
    say("wrote %s (%zu scans, exposure %.4g)%s%s%s%s\n", printable(a.out.empty() ? a.bag : a.out).c_str(), times.size(),
        run.exposure(), a.out.empty() || a.bag.empty() ? "" : ", ", a.out.empty() ? "" : printable(a.bag).c_str(),
        a.laser_out.empty() ? "" : ", ", printable(a.laser_out).c_str());
    return 0;
}

}  // namespace

void addOmnirange(CLI::App& app, Runner& run)
{
    auto a = std::make_shared<OmniArgs>();
    auto* c = app.add_subcommand(
        "omnirange", "The omnidirectional camera as a colour-based rangefinder beside a laser (docs/omnicam.md)");
    c->add_option("scene", a->scene, "Built-in scene name or scene file (.toml) with an omni camera")->required();
    c->add_option("--out", a->out, "The omnicam's ranges as a laser log (one range per scanline)");
    c->add_option("--bag", a->bag,
                  "Also (or instead) write a ROS 2 bag: a new folder with the omnicam's ranges on /omni/scan and the "
                  "laser's on /scan (docs/bags.md)")
        ->check(nonEmpty());
    c->add_option("--train", a->train, "Times [s] at which the laser's scan trains the colour histogram (comma list)");
    c->add_option("--histogram", a->histogram, "A trained colour histogram to use instead of --train");
    c->add_option("--save-histogram", a->save_histogram, "Also write the trained colour histogram");
    c->add_option("--laser-out", a->laser_out, "Also write the laser's log at the same times");
    c->add_option("--fig8", a->fig8,
                  "Also draw the floor distance against the pixel distance and one pixel's error (Fig. 8; PNG)");
    c->add_option("--plot", a->plot,
                  "Also draw the histogram of laser - omnicam per scanline (the paper's Fig. 9; PNG)");
    c->add_option(
        "--map", a->map,
        "Also draw occupancy grids from the laser's and the omnicam's scans with the true poses (Fig. 10; PNG)");
    c->add_option("--truth", a->truth,
                  "Also compare the omnicam and every laser of the scene with the truth: failure rate and range "
                  "error against the smoke column (PNG; tables printed)");
    c->add_option("--camera", a->cfg.camera, "Omni camera of the scene (default: the first)");
    c->add_option("--laser", a->cfg.laser, "Sensor that trains it (default: the scene's first)");
    c->add_option("--from", a->from, "First frame time [s] (default: scene start)")->check(finite());
    c->add_option("--to", a->to, "Last frame time [s] (default: scene end)")->check(finite());
    c->add_option("--rate", a->rate_hz, "Frames per second [Hz]")->capture_default_str()->check(positive());
    c->add_option("--spp", a->cfg.spp, "Samples per pixel")->capture_default_str()->check(intRange(1, limits::kSpp));
    c->add_option("--seed", a->cfg.seed, "Noise seed")->transform(seedRule())->capture_default_str();
    c->add_option("--threshold", a->cfg.range.threshold, "Θ: a pixel is free when its bin's share is at least this")
        ->capture_default_str();
    c->add_option("--n-behind", a->cfg.range.filter.n_behind, "N: non-free pixels behind a hit point")
        ->capture_default_str();
    c->add_option("--k-free", a->cfg.range.filter.k_free, "K: free pixels that break an obstacle")
        ->capture_default_str();
    c->add_option("--scanlines", a->cfg.range.scanlines, "Scanlines")->capture_default_str();
    c->add_option("--min-range", a->cfg.range.min_range_m, "Minimum range [m]")->capture_default_str();
    c->add_option("--max-range", a->cfg.range.max_range_m, "Maximum range [m]")->capture_default_str();
    c->add_option("--outlier", a->cfg.outlier_m,
                  "Scanlines this far from the laser [m] are left out of training and of the comparison")
        ->capture_default_str();
    c->add_option("--floor-z", a->cfg.floor_z_m, "Floor height [m]")->capture_default_str()->check(finite());
    c->add_option("--exposure", a->cfg.exposure,
                  "Radiance scale of the frames (<= 0: a saved histogram's, else metered once, then held)")
        ->capture_default_str()
        ->check(finite());
    c->callback([&run, a] { run = [a] { return runOmnirange(*a); }; });
}

}  // namespace smokescan::cli
