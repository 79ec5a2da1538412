#include "smokescan/pipeline/laser_run.hpp"

#include "smokescan/core/limits.hpp"

namespace smokescan {

LaserRun::LaserRun(const Scene& scene, const ScanConfig& cfg)
    : scene_(scene), surfaces_(std::make_unique<SurfaceSet>(scene))
{
    scanner_ = std::make_unique<Scanner>(scene_, *surfaces_, cfg);  // checks the sensor, model and span
    times_ = scanner_->times();
}

LaserRun::~LaserRun() = default;

const LrfSpec& LaserRun::spec() const { return scanner_->spec(); }

const SensorMount& LaserRun::mount() const { return scanner_->mount(); }

void LaserRun::run(const std::function<void(Scan&&)>& sink, const RunControl& control) const
{
    const long long total = (long long)times_.size();
    for (size_t k = 0; k < times_.size(); ++k) {
        checkCancel(control);
        sink(scanner_->scanAt(times_[k], k));
        reportProgress(control, (long long)k + 1, total);
    }
}

std::vector<Scan> LaserRun::collect(const RunControl& control) const
{
    const double readings = double(times_.size()) * double(spec().n_beams);
    if (readings > double(limits::kKeptReadings))
        throw Error("--to",
                    limits::count(double(times_.size())) + " scans of " + std::to_string(spec().n_beams) +
                        " beams would keep " + limits::count(readings) + " readings in memory (at most " +
                        std::to_string(limits::kKeptReadings) + "; a shorter span or a lower rate)");
    std::vector<Scan> out;
    out.reserve(times_.size());
    run([&](Scan&& s) { out.push_back(std::move(s)); }, control);
    return out;
}

}  // namespace smokescan
