#pragma once
// The CLI's progress bar on stderr: only when stderr is a terminal, one line redrawn in place.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace smokescan::cli {

class Progress {
public:
    /// @param what the work's name ("calibrate", "camera frames"), @param unit what is counted
    Progress(std::string what, std::string unit)
        : what_(std::move(what)), unit_(std::move(unit)), tty_(::isatty(2)), t0_(std::chrono::steady_clock::now())
    {
    }

    /// @brief `done` of `total` finished: a bar, the count, the time spent and the time left.
    void update(long long done, long long total) const
    {
        if (!tty_ || total <= 0) return;
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        const int w = 30, k = int(w * done / total);
        std::fprintf(stderr, "\r%s [%.*s%*s] %lld/%lld %s  %.0f s, ETA %.0f s ", what_.c_str(), k,
                     "==============================", w - k, "", done, total, unit_.c_str(), el,
                     done > 0 ? el * double(total - done) / double(done) : 0.0);
        if (done == total) std::fprintf(stderr, "\n");
    }

private:
    std::string what_, unit_;
    bool tty_;
    std::chrono::steady_clock::time_point t0_;
};

}  // namespace smokescan::cli
