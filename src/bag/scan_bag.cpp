#include "smokescan/bag/scan_bag.hpp"

#include <filesystem>

#include "smokescan/bag/rosbag2_writer.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_folder.hpp"

namespace smokescan {

namespace {
constexpr const char* kWorld = "map";
}

struct ScanBag::Impl {
    const Scene& scene;
    const Scanner& scanner;
    AtomicFolder folder;
    Rosbag2Writer bag;
    uint16_t scan, tf, tf_static;
    bool static_written = false;
    Impl(const std::string& dir, const Scene& s, const Scanner& sc)
        : scene(s),
          scanner(sc),
          folder(dir, "the bag", "--bag"),
          bag(folder, std::filesystem::path(dir).lexically_normal().filename().string()),
          scan(bag.topic("/scan", kLaserScanType)),
          tf(bag.topic("/tf", kTfType)),
          tf_static(bag.topic("/tf_static", kTfType))
    {
    }
};

ScanBag::ScanBag(const std::string& dir, const Scene& scene, const Scanner& scanner)
    : impl_(std::make_unique<Impl>(dir, scene, scanner))
{
}

ScanBag::~ScanBag() = default;

void ScanBag::add(const Scan& s)
{
    Impl& m = *impl_;
    const SensorMount& mount = m.scanner.mount();
    const RosTime stamp = RosTime::fromSeconds(s.time_s);
    const std::string robot = mount.robot >= 0 ? m.scene.robots[size_t(mount.robot)].name : "";
    if (!m.static_written) {
        TfMsg mounts;
        mounts.transforms.push_back(transformOf(mount.pose, stamp, robot.empty() ? kWorld : robot, mount.name));
        m.bag.write(m.tf_static, stamp, encode(mounts));
        m.static_written = true;
    }
    if (!robot.empty()) {
        TfMsg moving;
        moving.transforms.push_back(
            transformOf(m.scene.robots[size_t(mount.robot)].at(s.time_s), stamp, kWorld, robot));
        m.bag.write(m.tf, stamp, encode(moving));
    }
    m.bag.write(m.scan, stamp, encode(laserScanOf(s, m.scanner.spec(), mount.name)));
}

void ScanBag::finish() { impl_->bag.finish(); }

void ScanBag::commit() { impl_->folder.commit(); }

}  // namespace smokescan
