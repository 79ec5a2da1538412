#pragma once
/// @file laser_kind.hpp
/// @brief A laser range finder kind, asked rather than switched on: its name, its datasheet spec
/// and error values, its receiver, its physical model's defaults, its own scene keys, and what
/// smokescan can fit and learn for it. Each kind is one file, src/sensor_config/kinds/NAME.cpp;
/// its beam models and their factory are in src/sensors/NAME/ (sensors/beam_model.hpp).
///
/// | kind    | receiver | its own keys                 | learns extensions | physical model in fit, diagnose | fit-plume |
/// |---------|----------|------------------------------|-------------------|---------------------------------|-----------|
/// | urg04lx | AMCW     | –                            | yes               | yes (the noise floor)           | no        |
/// | lms200  | pulsed   | resolution_deg, range_mode_m | no                | no (a Monte Carlo per beam)     | yes       |
///
/// The 3D lidars are data, not code: presets (lidar/lidar_spec.hpp) with a pulsed receiver.
#include <string>

#include "smokescan/sensor_config/lrf.hpp"
#include "smokescan/sensor_config/physical_params.hpp"

namespace smokescan {

struct SensorConfig;
class TomlTable;

/// How a receiver measures range: the parameters of the physical model it takes
/// (sensor_config/physical_params.hpp).
enum class Receiver {
    Amcw,  ///< phase of two modulation frequencies (the URG-04LX)
    Pulsed  ///< time of flight of a pulse's echoes (the LMS200, the 3D lidars)
};

/// One kind of laser range finder (see the table above).
class LaserKind {
public:
    virtual ~LaserKind() = default;
    virtual SensorType type() const = 0;
    /// @brief The name in scene and sensor files and options ("urg04lx").
    virtual const char* name() const = 0;
    /// @brief The name with its article, for messages ("an urg04lx", "an lms200": as spoken).
    std::string withArticle() const { return std::string(article()) + " " + name(); }
    /// @brief "a" or "an", as the name is spoken.
    virtual const char* article() const = 0;
    virtual Receiver receiver() const = 0;
    /// @brief The datasheet spec for the options `config` holds.
    virtual LrfSpec spec(const SensorConfig& config) const = 0;
    /// @brief Which reported values are error codes, in words (log headers).
    virtual std::string errorValueSummary() const = 0;
    /// @brief An error value as ROS's REP 117 writes it in a LaserScan: +Inf when nothing was in
    /// range (no echo), −Inf when it was too close, NaN for a measurement that failed.
    virtual float rep117(long long error_value) const = 0;
    /// @brief The error code a recorded REP 117 value stands for (a bag read back): its code for
    /// nothing in range (+Inf), for a failed measurement (NaN), for too close (−Inf).
    virtual long long codeOfRep117(float range) const = 0;
    /// @brief The calibrated defaults of its physical model.
    virtual PhysicalParams physicalDefaults() const = 0;
    /// @brief Reads the kind's own keys of a scene's `[[sensor]]` into `config` (none by default;
    /// the caller refuses keys nobody read, so another kind's are refused).
    virtual void readOwnKeys(TomlTable& t, SensorConfig& config) const;
    /// @brief Whether a diagnosis's extensions (sensor_config/extensions.hpp) apply to its models.
    virtual bool learnsExtensions() const = 0;
    /// @brief Whether fit and diagnose take its physical model (an error probability per beam
    /// in closed form: the AMCW receiver's).
    virtual bool fitsPhysicalModel() const = 0;
    /// @brief Whether fit-plume applies (plumes read as obstacles: the pulsed receiver's first echo).
    virtual bool fitsPlume() const = 0;
};

/// @brief The kind of `type`.
const LaserKind& laserKind(SensorType type);
/// @brief The kind named `name`, or null.
const LaserKind* findLaserKind(const std::string& name);

}  // namespace smokescan
