// Ctrl-C and SIGTERM for long-running tools: the first signal asks the work to stop (the tool then
// writes a valid file with what it has and exits with 128 + the signal's number, the shell's convention:
// 130 for SIGINT, 143 for SIGTERM); a second one kills the process as usual.
#pragma once

#include <atomic>
#include <csignal>

namespace lt::tool {

inline std::atomic<bool>& stopRequested() {
    static std::atomic<bool> flag{false};
    return flag;
}

// The signal that asked the work to stop (0: none).
inline std::atomic<int>& stopSignal() {
    static std::atomic<int> sig{0};
    return sig;
}

// The exit status of a run the first signal cut short.
inline int interruptedExitCode() {
    const int sig = stopSignal().load();
    return 128 + (sig > 0 ? sig : SIGINT);
}

extern "C" inline void onInterrupt(int sig) {
    int none = 0;
    stopSignal().compare_exchange_strong(none, sig);
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
