#pragma once
/// @file waveform_peaks.hpp
/// @brief A multi-echo lidar receiver's peak detection: the peaks of a received waveform, also
/// where one rises out of another's run above the threshold (a wall behind the near field's smoke,
/// a target inside a fog). The LMS200's receiver (sensors/physical_model.hpp, waveformEchoes)
/// takes each run above the threshold as one echo; a lidar that digitises its waveform and reports
/// several returns finds each peak that stands out of the signal around it.
///
/// A peak *stands out* when the signal rises at least `prominence` above the lowest point since
/// the previous peak, after having fallen at least `prominence` below that previous peak (a
/// hysteresis on the waveform, so that the receiver's noise on a smooth slope does not split it).
/// A valley that dips below the threshold ends the run instead: the peak after it is then a run's
/// first, read from zero — a weak peak after a valley just above the threshold needs the
/// prominence over it, one after a valley just below it only the threshold.
#include <vector>

#include "smokescan/sensors/physical_model.hpp"

namespace smokescan {

/// One peak of a waveform.
struct WaveformPeak {
    /// Its peak sample, where it peaks and its half-height crossings [m]: half-way between the
    /// pedestal and the peak (half the peak for the first of a run, whose pedestal is 0).
    WaveformEcho echo;
    double pedestal = 0;  ///< the lowest sample between it and the previous peak of its run (0: the run's first)
    /// How far the signal fell from the previous peak to that valley (0 for the run's first peak):
    /// with the peak's own height over the valley, what the noise must not undo for it to stand out.
    double fall = 0;
    bool opens_run = true;  ///< the first peak of its run (the run's first sample is its start)
    int first_sample = 0;  ///< the run's or the valley's sample it rises from
};

/// @brief The peaks of waveform `f` in order of range: each run of samples at or above
/// `threshold` split at the valleys that fall at least `prominence` below the peaks on both sides.
/// A run without such a valley is one peak whose WaveformEcho is waveformEchoes' for the run.
/// @param f the waveform, @param threshold the detection threshold (normalised power)
/// @param prominence how far a peak must stand above the valley before it, and the peak before
/// that above the valley (normalised power, > 0) @throw std::invalid_argument when it is not > 0
std::vector<WaveformPeak> waveformPeaks(const Waveform& f, double threshold, double prominence);
/// @brief The same into `out`, whose storage is reused.
void waveformPeaks(const Waveform& f, double threshold, double prominence, std::vector<WaveformPeak>& out);

}  // namespace smokescan
