#pragma once
// Internal: Ceres logs through glog to stderr (rank-deficient covariances, line-search notes).
// The fits report what matters in their results and diagnoses, and a CLI error is one line, so
// glog is told to say nothing below FATAL. Every fit calls quietCeres() before it solves.
#include <glog/logging.h>

#include <mutex>

namespace smokescan::detail {

inline void quietCeres()
{
    static std::once_flag once;
    std::call_once(once, [] {
        if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("smokescan");
        FLAGS_minloglevel = google::GLOG_FATAL;
        FLAGS_stderrthreshold = google::GLOG_FATAL;
        FLAGS_logtostderr = false;
    });
}

}  // namespace smokescan::detail
