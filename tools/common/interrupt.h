// Ctrl-C and SIGTERM for long-running tools: the first signal asks the work to stop (the tool then
// writes a valid file with what it has); a second one kills the process as usual.
#pragma once

#include <atomic>
#include <csignal>

namespace lt::tool {

inline std::atomic<bool>& stopRequested() {
    static std::atomic<bool> flag{false};
    return flag;
}

extern "C" inline void onInterrupt(int sig) {
    if (stopRequested().exchange(true)) {
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
}

inline void installInterruptHandler() {
    std::signal(SIGINT, onInterrupt);
    std::signal(SIGTERM, onInterrupt);
}

} // namespace lt::tool
