#include "smokescan/pipeline/bag_run.hpp"

#include <optional>

#include "smokescan/bag/scan_bag.hpp"
#include "smokescan/bag/scan_messages.hpp"

namespace smokescan {

BagRunResult recordLaserBag(const Scene& scene, const ScanConfig& cfg, const std::string& dir,
                            const RunControl& control)
{
    const LaserRun run(scene, cfg);
    ScanBag bag(dir, scene);
    BagRunResult r;
    run.run(
        [&](Scan&& s) {
            bag.add(s, run.spec(), run.mount());
            ++r.messages;
            r.readings += (long long)s.value.size();
        },
        control);
    bag.finish();
    bag.commit();
    return r;
}

BagRunResult recordLidarBag(const Scene& scene, const LidarRunConfig& cfg, const std::string& dir,
                            const RunControl& control)
{
    const LidarRun run(scene, cfg);
    ScanBag bag(dir, scene);
    // A planar pattern is a 2D multi-echo scanner: its frames also as MultiEchoLaserScans.
    const std::vector<PatternBeam> pattern = framePattern(run.spec());
    const std::optional<PlanarFan> fan = planarFan(pattern);
    BagRunResult r;
    run.run(
        [&](LidarFrame&& f) {
            bag.add(f, run.mount());
            if (fan) bag.add(multiEchoOf(f, *fan, pattern.size(), run.spec(), run.mount().name), run.mount());
            ++r.messages;
            r.readings += (long long)f.points.size();
        },
        control);
    bag.finish();
    bag.commit();
    return r;
}

}  // namespace smokescan
