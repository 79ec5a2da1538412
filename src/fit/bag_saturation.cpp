#include "smokescan/fit/bag_saturation.hpp"

#include "smokescan/bag/bag_input.hpp"
#include "smokescan/core/error.hpp"

namespace smokescan {

SaturationSeries measureBagSaturation(const std::string& path, const std::string& topic, const FrameRegions& regions,
                                      const std::function<void(long long)>& each)
{
    if (regions.by_id || regions.patches.empty())
        throw Error(path, "give the target's region in its frames (--rect or --polygon): a bag holds no id frames");
    FrameSeries series(regions);
    long long frames = 0;
    const std::string read = readBagImages(path, topic, [&](ImageMsg&& m, const std::string& what) {
        series.add(imageOf(m, what), false, nullptr, double(m.header.stamp.nanoseconds()) * 1e-9, what);
        if (each) each(++frames);
    });
    SaturationSeries s = series.take();
    s.path = path + " " + read;
    return s;
}

}  // namespace smokescan
