#include "smokescan/bag/scan_bag.hpp"

#include <filesystem>

#include "smokescan/bag/rosbag2_writer.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_folder.hpp"

namespace smokescan {

namespace {
constexpr const char* kWorld = "map";

/// The bag's name: its folder's (`runs/b1/` → b1).
std::string bagName(const std::string& dir)
{
    std::filesystem::path p = std::filesystem::path(dir).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    return p.filename().string();
}
}  // namespace

struct ScanBag::Impl {
    const Scene& scene;
    SensorMount mount;
    AtomicFolder folder;
    Rosbag2Writer bag;
    uint16_t data, tf, tf_static, image = 0;
    bool static_written = false;
    Impl(const std::string& dir, const Scene& s, const SensorMount& m, bool lidar)
        : scene(s),
          mount(m),
          folder(dir, "the bag", "--bag"),
          bag(folder, bagName(dir)),
          data(lidar ? bag.topic("/points", kPointCloud2Type) : bag.topic("/scan", kLaserScanType)),
          tf(bag.topic("/tf", kTfType)),
          tf_static(bag.topic("/tf_static", kTfType))
    {
    }
    /// The mount once, then the robot's pose at each message.
    void transforms(double t_s, const RosTime& stamp)
    {
        const std::string robot = mount.robot >= 0 ? scene.robots[size_t(mount.robot)].name : "";
        if (!static_written) {
            TfMsg mounts;
            mounts.transforms.push_back(transformOf(mount.pose, stamp, robot.empty() ? kWorld : robot, mount.name));
            bag.write(tf_static, stamp, encode(mounts));
            static_written = true;
        }
        if (robot.empty()) return;
        TfMsg moving;
        moving.transforms.push_back(transformOf(scene.robots[size_t(mount.robot)].at(t_s), stamp, kWorld, robot));
        bag.write(tf, stamp, encode(moving));
    }
};

ScanBag::ScanBag(const std::string& dir, const Scene& scene, const SensorMount& mount, bool lidar)
    : impl_(std::make_unique<Impl>(dir, scene, mount, lidar))
{
}

ScanBag::~ScanBag() = default;

void ScanBag::add(const Scan& s, const LrfSpec& spec)
{
    Impl& m = *impl_;
    const RosTime stamp = RosTime::fromSeconds(s.time_s);
    m.transforms(s.time_s, stamp);
    m.bag.write(m.data, stamp, encode(laserScanOf(s, spec, m.mount.name)));
}

void ScanBag::add(const LidarFrame& f)
{
    Impl& m = *impl_;
    const RosTime stamp = RosTime::fromSeconds(f.start_s);
    m.transforms(f.start_s, stamp);
    m.bag.write(m.data, stamp, encode(pointCloudOf(f, m.mount.name)));
}

void ScanBag::addImage(const Image& display, double camera_time_s, const std::string& camera)
{
    Impl& m = *impl_;
    if (m.image == 0) m.image = m.bag.topic("/camera/image", kImageType);
    const RosTime stamp = RosTime::fromSeconds(camera_time_s);
    m.bag.write(m.image, stamp, encode(imageOf(display, stamp, camera)));
}

void ScanBag::finish() { impl_->bag.finish(); }

void ScanBag::commit() { impl_->folder.commit(); }

}  // namespace smokescan
