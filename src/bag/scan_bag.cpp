#include "smokescan/bag/scan_bag.hpp"

#include <filesystem>
#include <map>
#include <set>

#include "smokescan/bag/rosbag2_writer.hpp"
#include "smokescan/bag/scan_messages.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/io/atomic_folder.hpp"

namespace smokescan {

namespace {
constexpr const char* kWorld = "map";

/// The bag's name: its folder's (`runs/b1/` → b1). It names the bag's file (NAME_0.mcap) and
/// metadata.yaml holds it, so it must be UTF-8 without control characters and short enough.
std::string bagName(const std::string& dir)
{
    std::filesystem::path p = std::filesystem::path(dir).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    const std::string name = p.filename().string();
    if (printableWhole(name) != name)
        throw Error(dir,
                    "a bag's folder name must be UTF-8 without control characters (its file's name and "
                    "metadata.yaml hold it)");
    const size_t file = name.size() + std::string("_0.mcap").size();
    if (file > 255)
        throw Error(dir,
                    "would name the bag's file " + std::to_string(file) + " bytes long (NAME_0.mcap, at most 255)");
    return name;
}
}  // namespace

BagFrame bagFrameOf(const SensorMount& m) { return {m.name, m.pose, m.robot}; }

BagFrame bagFrameOf(const Camera& c) { return {c.name, c.pose, c.robot}; }

struct ScanBag::Impl {
    const Scene& scene;
    std::string name;  ///< checked before the folder is made
    AtomicFolder folder;
    Rosbag2Writer bag;
    std::map<std::string, uint16_t> topics;
    std::set<std::string> mounted;  ///< frames whose mount is on /tf_static
    std::map<int, uint64_t> robot_stamp;  ///< each robot's last pose on /tf [ns]
    Impl(const std::string& dir, const Scene& s)
        : scene(s), name(bagName(dir)), folder(dir, "the bag", "--bag"), bag(folder, name)
    {
    }
    uint16_t topic(const std::string& name, const RosType& type)
    {
        const auto it = topics.find(name);
        return it != topics.end() ? it->second : topics[name] = bag.topic(name, type);
    }
    /// The frame's mount once (and its optical frame's, when named), its robot's pose at `t_s`
    /// (once a stamp), then the message.
    void write(uint16_t data, const RosTime& stamp, const std::vector<uint8_t>& bytes, const BagFrame& where,
               double t_s, const std::string& optical = "")
    {
        const std::string robot = where.robot >= 0 ? scene.robots[size_t(where.robot)].name : "";
        if (mounted.insert(where.name).second) {
            TfMsg mounts;
            mounts.transforms.push_back(transformOf(where.pose, stamp, robot.empty() ? kWorld : robot, where.name));
            if (!optical.empty()) {
                // REP 103: the optical frame looks along +z with +x right and +y down; smokescan's
                // pinhole looks along its local +x with +z up and +y left (render/camera.hpp).
                Pose axes;
                axes.R << 0, 0, 1, -1, 0, 0, 0, -1, 0;
                mounts.transforms.push_back(transformOf(axes, stamp, where.name, optical));
            }
            bag.write(topic("/tf_static", kTfType), stamp, encode(mounts));
        }
        if (!robot.empty()) {
            const RosTime at = RosTime::fromSeconds(t_s);
            const auto last = robot_stamp.find(where.robot);
            if (last == robot_stamp.end() || last->second != at.nanoseconds()) {
                TfMsg moving;
                moving.transforms.push_back(transformOf(scene.robots[size_t(where.robot)].at(t_s), at, kWorld, robot));
                bag.write(topic("/tf", kTfType), at, encode(moving));
                robot_stamp[where.robot] = at.nanoseconds();
            }
        }
        bag.write(data, stamp, bytes);
    }
};

ScanBag::ScanBag(const std::string& dir, const Scene& scene) : impl_(std::make_unique<Impl>(dir, scene)) {}

ScanBag::~ScanBag() = default;

void ScanBag::add(const Scan& s, const LrfSpec& spec, const SensorMount& mount)
{
    add("/scan", laserScanOf(s, spec, mount.name), bagFrameOf(mount));
}

void ScanBag::add(const std::string& topic, const LaserScanMsg& scan, const BagFrame& where)
{
    Impl& m = *impl_;
    const uint16_t id = m.topic(topic, kLaserScanType);
    m.write(id, scan.header.stamp, encode(scan), where, double(scan.header.stamp.nanoseconds()) * 1e-9);
}

void ScanBag::add(const LidarFrame& f, const SensorMount& mount)
{
    Impl& m = *impl_;
    const uint16_t id = m.topic("/points", kPointCloud2Type);
    m.write(id, RosTime::fromSeconds(f.start_s), encode(pointCloudOf(f, mount.name)), bagFrameOf(mount), f.start_s);
}

void ScanBag::add(const MultiEchoLaserScanMsg& echoes, const SensorMount& mount)
{
    Impl& m = *impl_;
    const uint16_t id = m.topic("/echoes", kMultiEchoLaserScanType);
    m.write(id, echoes.header.stamp, encode(echoes), bagFrameOf(mount),
            double(echoes.header.stamp.nanoseconds()) * 1e-9);
}

void ScanBag::addImage(const Image& display, double camera_time_s, double scene_time_s, const Camera& camera)
{
    Impl& m = *impl_;
    const uint16_t id = m.topic("/camera/image", kImageType);
    const RosTime stamp = RosTime::fromSeconds(camera_time_s);
    // A pinhole's pictures are in its optical frame, as ROS's camera drivers publish them.
    const std::string frame = camera.kind == CameraKind::Pinhole ? camera.name + "_optical_frame" : camera.name;
    m.write(id, stamp, encode(imageOf(display, stamp, frame)), bagFrameOf(camera), scene_time_s,
            frame == camera.name ? "" : frame);
}

void ScanBag::finish() { impl_->bag.finish(); }

void ScanBag::commit() { impl_->folder.commit(); }

}  // namespace smokescan
