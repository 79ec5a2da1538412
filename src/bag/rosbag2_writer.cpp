#include "smokescan/bag/rosbag2_writer.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>

#include "smokescan/core/error.hpp"

namespace smokescan {

struct Rosbag2Writer::Impl {
    AtomicFolder& folder;
    std::string name, file;
    std::ofstream out;
    McapWriter mcap;
    std::map<std::string, uint16_t> schemas;  ///< by type name
    std::map<std::string, std::string> types;  ///< topic → type name
    Impl(AtomicFolder& f, const std::string& n, McapWriterConfig cfg)
        : folder(f), name(n), file(n + "_0.mcap"), out(f.path(file), std::ios::binary), mcap(out, std::move(cfg))
    {
    }
};

namespace {
/// The QoS a topic was offered with, as rosbag2 records it (a YAML list of profiles as text):
/// /tf_static reliable and transient-local, as tf2's static broadcaster offers it, so that
/// `ros2 bag play` re-offers it to late subscribers (RViz); "" (the player's default) elsewhere.
std::string offeredQos(const std::string& topic)
{
    if (topic != "/tf_static") return "";
    const std::string never = "\n    sec: 9223372036\n    nsec: 854775807";
    return "- history: 1\n  depth: 1\n  reliability: 1\n  durability: 1\n  deadline:" + never +
        "\n  lifespan:" + never + "\n  liveliness: 1\n  liveliness_lease_duration:" + never +
        "\n  avoid_ros_namespace_conventions: false";
}
}  // namespace

Rosbag2Writer::Rosbag2Writer(AtomicFolder& folder, const std::string& name, McapWriterConfig cfg)
    : impl_(std::make_unique<Impl>(folder, name, std::move(cfg)))
{
    if (!impl_->out) throw Error(folder.path(impl_->file), "cannot be created");
}

Rosbag2Writer::~Rosbag2Writer() = default;

uint16_t Rosbag2Writer::topic(const std::string& name, const RosType& type)
{
    Impl& m = *impl_;
    auto s = m.schemas.find(type.name);
    if (s == m.schemas.end())
        s = m.schemas.emplace(type.name, m.mcap.addSchema(type.name, "ros2msg", type.definition)).first;
    if (m.types.count(name)) throw Error("bag", "topic " + name + " added twice");
    m.types[name] = type.name;
    return m.mcap.addChannel(s->second, name, "cdr", {{"offered_qos_profiles", offeredQos(name)}});
}

void Rosbag2Writer::write(uint16_t channel, const RosTime& stamp, const std::vector<uint8_t>& cdr)
{
    impl_->mcap.write(channel, stamp.nanoseconds(), stamp.nanoseconds(), cdr);
}

McapWriteResult Rosbag2Writer::finish()
{
    Impl& m = *impl_;
    // A write that failed (a full disk, a file-size limit) is named on the bag's own file.
    const auto failed = [&] {
        return Error(
            m.folder.finalPath(m.file),
            std::string("could not be written") + (errno ? std::string(" (") + std::strerror(errno) + ")" : ""));
    };
    errno = 0;
    McapWriteResult r;
    try {
        r = m.mcap.finish();
    } catch (const Error&) {
        if (!m.out) throw failed();  // the stream failed: say where and why
        throw;
    }
    m.out.close();
    if (!m.out) throw failed();
    // rosbag2's metadata (rosbag2_storage/metadata_io: version 5).
    YAML::Emitter y;
    auto duration = [&](const char* key, uint64_t ns) {
        y << YAML::Key << key << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds" << YAML::Value << ns
          << YAML::EndMap;
    };
    auto start = [&](uint64_t ns) {
        y << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds_since_epoch"
          << YAML::Value << ns << YAML::EndMap;
    };
    y << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value << YAML::BeginMap;
    y << YAML::Key << "version" << YAML::Value << 5 << YAML::Key << "storage_identifier" << YAML::Value << "mcap";
    duration("duration", r.end_ns - r.start_ns);
    start(r.start_ns);
    y << YAML::Key << "message_count" << YAML::Value << r.messages;
    y << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
    for (const auto& [topic, type] : m.types) {
        const auto n = r.per_topic.find(topic);
        y << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap << YAML::Key << "name"
          << YAML::Value << topic << YAML::Key << "type" << YAML::Value << type << YAML::Key << "serialization_format"
          << YAML::Value << "cdr" << YAML::Key << "offered_qos_profiles" << YAML::Value << YAML::DoubleQuoted
          << offeredQos(topic) << YAML::EndMap << YAML::Key << "message_count" << YAML::Value
          << (n == r.per_topic.end() ? uint64_t(0) : n->second) << YAML::EndMap;
    }
    y << YAML::EndSeq;
    y << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted << "" << YAML::Key << "compression_mode"
      << YAML::Value << YAML::DoubleQuoted << "";
    y << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq << m.file << YAML::EndSeq;
    y << YAML::Key << "files" << YAML::Value << YAML::BeginSeq << YAML::BeginMap << YAML::Key << "path" << YAML::Value
      << m.file;
    start(r.start_ns);
    duration("duration", r.end_ns - r.start_ns);
    y << YAML::Key << "message_count" << YAML::Value << r.messages << YAML::EndMap << YAML::EndSeq;
    y << YAML::EndMap << YAML::EndMap;
    std::ofstream meta(m.folder.path("metadata.yaml"));
    meta << y.c_str() << "\n";
    meta.close();
    if (!meta) throw Error(m.folder.finalPath("metadata.yaml"), "could not be written");
    return r;
}

}  // namespace smokescan
