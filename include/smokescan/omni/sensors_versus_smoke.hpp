#pragma once
/// @file sensors_versus_smoke.hpp
/// @brief The omnicam rangefinder beside every laser of the scene on the same drive, each against
/// its own truth and binned by the smoke column it looks through (range_tally.hpp): how a camera
/// and a laser fail differently in smoke (experiments/omnicam_smoke).
///
/// The omnicam's truth and column are per scanline (scanline_truth.hpp); a laser's truth is the
/// surface its beam meets in clear air (none beyond its maximum range) and its column the smoke
/// along the beam up to that surface. Each laser is scanned with the scene's model for it.
///
/// | parameter | default | unit | meaning                                     |
/// |-----------|---------|------|---------------------------------------------|
/// | tally     | range_tally.hpp | | tolerance and column bins, all sensors  |
/// | truth     | scanline_truth.hpp | | the omnicam's probe rays             |
#include <memory>
#include <vector>

#include "smokescan/omni/omni_run.hpp"
#include "smokescan/omni/range_tally.hpp"
#include "smokescan/omni/scanline_truth.hpp"

namespace smokescan {

struct VersusSmokeConfig {
    RangeTallyConfig tally;
    ScanlineTruthConfig truth;
    uint64_t seed = 1;  ///< the lasers' noise
};

class SensorsVersusSmoke {
public:
    /// @throw Error for a scene without lasers or a bad tally configuration.
    SensorsVersusSmoke(const Scene& scene, const SurfaceSet& surfaces, const OmniRangeConfig& omni,
                       const VersusSmokeConfig& cfg = {});

    /// @brief Adds the omnicam's frame (against its truth, at `height_m` above the floor) and every
    /// laser's scan at the frame's time (`k` keys their noise).
    void add(const OmniFrame& f, double height_m, uint64_t k);

    /// The omnicam's tally first, then each laser's in the scene's order.
    const std::vector<RangeTally>& tallies() const { return tallies_; }

private:
    const Scene& scene_;
    const SurfaceSet& surfaces_;
    OmniRangeConfig omni_;
    VersusSmokeConfig cfg_;
    std::vector<std::unique_ptr<Scanner>> lasers_;
    std::vector<RangeTally> tallies_;
};

}  // namespace smokescan
