#pragma once
// Internal: what the diagnosis's reports (diagnosis.json, lidar_diagnosis.json) share.
#include <nlohmann/json.hpp>

#include <cmath>

namespace smokescan::detail {

/// A number for a JSON report; null when it is not finite (JSON has no NaN or infinity).
inline nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace smokescan::detail
