#pragma once
// Internal: a long library call on a thread of its own while the calling thread reports its
// progress and asks whether to stop (pipeline/run_control.hpp: the control is only ever called on
// the calling thread, so a caller such as Python can answer it).
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <optional>
#include <thread>
#include <utility>

#include "smokescan/pipeline/run_control.hpp"
#include "smokescan/render/renderer.hpp"

namespace smokescan::detail {

/// @brief Runs work() on another thread; about every 50 ms this thread reports progress_now()
/// (when it changed and some unit is done) and asks the control's cancel, which sets watch.stop: work must then return
/// or throw soon, and the run throws Cancelled. work's own exceptions are rethrown here.
template <class R>
R runWatched(const std::function<R()>& work, RenderWatch& watch,
             const std::function<std::pair<long long, long long>()>& progress_now, const RunControl& control)
{
    std::optional<R> result;
    std::exception_ptr failed;
    std::atomic<bool> finished{false};
    std::thread worker([&] {
        try {
            result.emplace(work());
        } catch (...) {
            failed = std::current_exception();
        }
        finished = true;
    });
    std::pair<long long, long long> shown{-1, -1};
    auto report = [&] {
        const auto now = progress_now();
        if (now != shown && now.first > 0) reportProgress(control, now.first, now.second);
        shown = now;
    };
    try {
        while (!finished) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            if (control.cancel && control.cancel()) watch.stop = true;
            if (watch.stop) break;
            report();
        }
    } catch (...) {  // the control itself threw: the work stops, and the control's error goes on
        watch.stop = true;
        worker.join();
        throw;
    }
    worker.join();
    if (watch.stop) throw Cancelled();
    if (failed) std::rethrow_exception(failed);
    report();
    return std::move(*result);
}

}  // namespace smokescan::detail
