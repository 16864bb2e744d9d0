// Progress on stderr: a redrawn bar on a terminal, plain lines (every 10 % or 10 s) otherwise, so logs
// of batch runs stay readable.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "run/run_summary.h"

namespace lt::tool {

class Progress {
public:
    explicit Progress(std::string label, bool quiet = false)
        : label_(std::move(label)), quiet_(quiet), tty_(isatty(STDERR_FILENO) != 0),
          last_(std::chrono::steady_clock::now() - std::chrono::hours(1)) {}

    // fraction in [0, 1], or negative when unknown; detail is shown after the bar.
    void update(double fraction, const std::string& detail) {
        if (quiet_) return;
        const auto now = std::chrono::steady_clock::now();
        const double since = std::chrono::duration<double>(now - last_).count();
        if (tty_) {
            if (since < 0.1 && fraction < 1) return;
            const int width = 30;
            const int fill = fraction < 0 ? 0 : int(fraction * width + 0.5);
            std::string bar(size_t(fill), '=');
            bar.resize(size_t(width), ' ');
            if (fraction >= 0)
                std::fprintf(stderr, "\r%s [%s] %3d%% %s\033[K", label_.c_str(), bar.c_str(), int(fraction * 100 + 0.5),
                             detail.c_str());
            else
                std::fprintf(stderr, "\r%s %s\033[K", label_.c_str(), detail.c_str());
            drawn_ = true;
        } else {
            const bool step = fraction >= 0 && int(fraction * 10) > lastDecile_;
            if (!step && since < 10) return;
            if (fraction >= 0) lastDecile_ = int(fraction * 10);
            std::fprintf(stderr, "%s %s\n", label_.c_str(), detail.c_str());
        }
        last_ = now;
        std::fflush(stderr);
    }

    void finish() {
        if (tty_ && drawn_ && !quiet_) std::fprintf(stderr, "\n");
        drawn_ = false;
    }

private:
    std::string label_;
    bool quiet_, tty_, drawn_ = false;
    int lastDecile_ = -1;
    std::chrono::steady_clock::time_point last_;
};

} // namespace lt::tool
