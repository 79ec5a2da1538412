#pragma once
/// @file run_control.hpp
/// @brief What a caller may ask of a long library run (pipeline/): to hear how far it is, and
/// to stop it.
#include <functional>

#include "smokescan/core/error.hpp"

namespace smokescan {

/// | field    | default | meaning                                                              |
/// |----------|---------|----------------------------------------------------------------------|
/// | progress | none    | called after each unit of work (a scan, a frame) with (done, total); total 0: not known (a bag's frames) |
/// | cancel   | none    | asked before each unit; true stops the run, which throws Cancelled    |
///
/// Both are called on the thread that started the run, never from worker threads.
struct RunControl {
    std::function<void(long long done, long long total)> progress;
    std::function<bool()> cancel;
};

/// The run was stopped by its RunControl::cancel; nothing it would have returned exists.
class Cancelled : public Error {
public:
    Cancelled() : Error("run", "cancelled") {}
};

/// @brief Throws Cancelled when the control asks to stop.
inline void checkCancel(const RunControl& c)
{
    if (c.cancel && c.cancel()) throw Cancelled();
}

/// @brief Tells the control that `done` of `total` units are finished.
inline void reportProgress(const RunControl& c, long long done, long long total)
{
    if (c.progress) c.progress(done, total);
}

}  // namespace smokescan
