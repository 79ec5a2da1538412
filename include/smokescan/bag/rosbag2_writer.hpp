#pragma once
/// @file rosbag2_writer.hpp
/// @brief A ROS 2 bag as `ros2 bag record -s mcap` leaves it: a folder holding metadata.yaml
/// (rosbag2's bagfile information, version 5) and one MCAP file, NAME_0.mcap, whose messages are
/// CDR with ros2msg schemas (bag/ros_messages.hpp). The folder is an AtomicFolder the caller
/// commits: an error leaves nothing.
#include <memory>
#include <string>

#include "smokescan/bag/mcap_writer.hpp"
#include "smokescan/bag/ros_messages.hpp"
#include "smokescan/io/atomic_folder.hpp"

namespace smokescan {

class Rosbag2Writer {
public:
    /// @param folder the bag's folder (staged); its name names the MCAP file.
    /// @param name the bag's name (the folder's final name, without its path).
    Rosbag2Writer(AtomicFolder& folder, const std::string& name, McapWriterConfig cfg = {});
    ~Rosbag2Writer();
    /// @brief A topic of `type`; returns its channel. The same type's schema is written once.
    uint16_t topic(const std::string& name, const RosType& type);
    /// @brief One message, logged and published at `stamp`.
    void write(uint16_t channel, const RosTime& stamp, const std::vector<uint8_t>& cdr);
    /// @brief Closes the MCAP file and writes metadata.yaml. @throw Error when a file fails.
    McapWriteResult finish();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
