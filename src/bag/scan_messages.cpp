#include "smokescan/bag/scan_messages.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "smokescan/sensor_config/laser_kind.hpp"

namespace smokescan {

LaserScanMsg laserScanOf(const Scan& scan, const LrfSpec& spec, const std::string& frame_id)
{
    LaserScanMsg m;
    m.header.stamp = RosTime::fromSeconds(scan.time_s);
    m.header.frame_id = frame_id;
    m.angle_min = float(spec.angle(0));
    m.angle_max = float(spec.angle(spec.n_beams - 1));
    m.angle_increment = float(spec.dangle_rad);
    m.time_increment = 0;  // smokescan takes a 2D scan as instantaneous (sensor_config/beam_pattern.hpp)
    m.scan_time = float(spec.scan_period_s);
    m.range_min = float(spec.range_min_m);
    m.range_max = float(spec.range_max_m);
    const LaserKind& kind = laserKind(spec.type);
    m.ranges.reserve(scan.value.size());
    for (long long v : scan.value)
        m.ranges.push_back(spec.isErrorValue(v) ? kind.rep117(v) : float(double(v) * spec.unit_m));
    return m;
}

PointCloud2Msg pointCloudOf(const LidarFrame& f, const std::string& frame_id)
{
    PointCloud2Msg m;
    m.header.stamp = RosTime::fromSeconds(f.start_s);
    m.header.frame_id = frame_id;
    constexpr uint8_t kU8 = 2, kU16 = 4, kF32 = 7;
    m.fields = {{"x", 0, kF32, 1},     {"y", 4, kF32, 1},      {"z", 8, kF32, 1},      {"intensity", 12, kF32, 1},
                {"ring", 16, kU16, 1}, {"return", 18, kU8, 1}, {"source", 19, kU8, 1}, {"time", 20, kF32, 1}};
    m.point_step = 24;
    m.width = uint32_t(f.points.size());
    m.row_step = m.point_step * m.width;
    m.data.resize(size_t(m.row_step));
    uint8_t* d = m.data.data();
    for (const LidarPoint& p : f.points) {
        std::memcpy(d + 0, &p.x, 4);
        std::memcpy(d + 4, &p.y, 4);
        std::memcpy(d + 8, &p.z, 4);
        std::memcpy(d + 12, &p.intensity, 4);
        std::memcpy(d + 16, &p.ring, 2);
        d[18] = p.return_index;
        d[19] = p.source;
        std::memcpy(d + 20, &p.time_s, 4);
        d += m.point_step;
    }
    return m;
}

std::optional<PlanarFan> planarFan(const std::vector<PatternBeam>& pattern)
{
    if (pattern.size() < 2) return std::nullopt;
    // The steps from the ends: a file's rounding does not add up over the beams.
    const double n = double(pattern.size() - 1);
    PlanarFan f{pattern[0].azimuth_rad, (pattern.back().azimuth_rad - pattern[0].azimuth_rad) / n,
                (pattern.back().time_s - pattern[0].time_s) / n};
    if (!(std::abs(f.step_rad) > 0)) return std::nullopt;
    for (size_t i = 0; i < pattern.size(); ++i) {
        const PatternBeam& b = pattern[i];
        if (b.channel != 0 || std::abs(b.elevation_rad) > 1e-9 ||
            std::abs(b.azimuth_rad - (f.angle_min_rad + double(i) * f.step_rad)) > 0.01 * std::abs(f.step_rad) ||
            std::abs(b.time_s - (pattern[0].time_s + double(i) * f.time_step_s)) > 0.1 * std::abs(f.time_step_s) + 1e-9)
            return std::nullopt;
    }
    return f;
}

MultiEchoLaserScanMsg multiEchoOf(const LidarFrame& frame, const PlanarFan& fan, size_t beams, const LidarSpec& spec,
                                  const std::string& frame_id)
{
    MultiEchoLaserScanMsg m;
    m.header.stamp = RosTime::fromSeconds(frame.start_s);
    m.header.frame_id = frame_id;
    m.angle_min = float(fan.angle_min_rad);
    m.angle_increment = float(fan.step_rad);
    m.angle_max = float(fan.angle_min_rad + double(beams - 1) * fan.step_rad);
    m.time_increment = float(fan.time_step_s);
    m.scan_time = float(1 / spec.rate_hz);
    m.range_min = float(spec.range_min_m);
    m.range_max = float(spec.range_max_m);
    m.ranges.resize(beams);
    m.intensities.resize(beams);
    for (const LidarPoint& p : frame.points) {  // in firing order, a beam's points in return order
        if (p.beam >= beams) continue;
        m.ranges[p.beam].push_back(p.range_m);
        m.intensities[p.beam].push_back(p.intensity);
    }
    return m;
}

ImageMsg imageOf(const Image& display, const RosTime& stamp, const std::string& frame_id)
{
    ImageMsg m;
    m.header.stamp = stamp;
    m.header.frame_id = frame_id;
    m.height = uint32_t(display.height);
    m.width = uint32_t(display.width);
    m.encoding = "rgb8";
    m.step = 3 * m.width;
    m.data.resize(size_t(m.step) * m.height);
    for (size_t p = 0; p < size_t(display.width) * size_t(display.height); ++p)
        for (int c = 0; c < 3; ++c) {
            const float v = display.data[p * size_t(display.channels) + size_t(std::min(c, display.channels - 1))];
            m.data[3 * p + size_t(c)] = uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
        }
    return m;
}

TransformStampedMsg transformOf(const Pose& pose, const RosTime& stamp, const std::string& parent,
                                const std::string& child)
{
    TransformStampedMsg t;
    t.header.stamp = stamp;
    t.header.frame_id = parent;
    t.child_frame_id = child;
    for (int i = 0; i < 3; ++i) t.translation[i] = pose.t[i];
    const Eigen::Quaterniond q(pose.R);
    t.rotation[0] = q.x();
    t.rotation[1] = q.y();
    t.rotation[2] = q.z();
    t.rotation[3] = q.w();
    return t;
}

}  // namespace smokescan
