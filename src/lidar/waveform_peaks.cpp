#include "smokescan/lidar/waveform_peaks.hpp"

#include <stdexcept>

namespace smokescan {
namespace {

/// The peaks of the run [k0, k1] (every sample ≥ the threshold) into `out`.
void runPeaks(const Waveform& f, int k0, int k1, double prominence, std::vector<WaveformPeak>& out)
{
    const std::vector<double>& w = f.w;
    const int n = int(w.size());
    // Peaks (sample, pedestal, where it rises from) and the valleys that end them.
    struct Found {
        int kp;
        double pedestal, fall;
        int from;
        int valley;
    };
    thread_local std::vector<Found> found;  // storage kept for the thread's next run
    found.clear();
    int kp = k0, from = k0, kv = k0;
    double pedestal = 0, fall = 0;
    bool rising = true;  // looking for the peak (else for the valley after it)
    for (int k = k0 + 1; k <= k1; ++k) {
        const double x = w[size_t(k)];
        if (rising) {
            if (x > w[size_t(kp)])
                kp = k;
            else if (w[size_t(kp)] - x >= prominence)
                rising = false, kv = k;
        } else if (x < w[size_t(kv)]) {
            kv = k;
        } else if (x - w[size_t(kv)] >= prominence) {
            found.push_back({kp, pedestal, fall, from, kv});
            fall = w[size_t(kp)] - w[size_t(kv)];
            pedestal = w[size_t(kv)], from = kv, kp = k, rising = true;
        }
    }
    found.push_back({kp, pedestal, fall, from, n - 1});  // the last peak's half-height may lie past the run
    for (size_t i = 0; i < found.size(); ++i) {
        WaveformPeak p;
        p.echo = waveformPeakAt(f, found[i].kp, found[i].pedestal, found[i].from, found[i].valley);
        p.pedestal = found[i].pedestal;
        p.fall = found[i].fall;
        p.opens_run = i == 0;
        p.first_sample = found[i].from;
        out.push_back(p);
    }
}

}  // namespace

std::vector<WaveformPeak> waveformPeaks(const Waveform& f, double threshold, double prominence)
{
    std::vector<WaveformPeak> out;
    waveformPeaks(f, threshold, prominence, out);
    return out;
}

void waveformPeaks(const Waveform& f, double threshold, double prominence, std::vector<WaveformPeak>& out)
{
    if (!(prominence > 0)) throw std::invalid_argument("waveformPeaks: the prominence must be > 0");
    out.clear();
    const std::vector<double>& w = f.w;
    const int n = int(w.size());
    for (int k0 = 0; k0 < n;) {
        while (k0 < n && w[size_t(k0)] < threshold) ++k0;
        if (k0 == n) break;
        int k1 = k0;
        while (k1 + 1 < n && w[size_t(k1 + 1)] >= threshold) ++k1;
        runPeaks(f, k0, k1, prominence, out);
        k0 = k1 + 1;
    }
}

}  // namespace smokescan
