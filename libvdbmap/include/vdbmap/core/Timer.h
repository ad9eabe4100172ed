// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <chrono>

namespace vdbmap {

/// Wall-clock stopwatch (steady clock), seconds as double.
class Timer {
public:
    Timer() : start_(Clock::now()) {}
    void reset() { start_ = Clock::now(); }
    double elapsedSeconds() const {
        return std::chrono::duration<double>(Clock::now() - start_).count();
    }

private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point start_;
};

/// Peak resident set size of this process in bytes (from /proc/self/status VmHWM; 0 if unknown),
/// over the whole run (also across resetPeakMemoryWindow()).
std::size_t peakMemoryBytes();

/// Starts a new peak-memory window (Linux: writes 5 to /proc/self/clear_refs, which resets
/// VmHWM to the current RSS); peakMemoryBytes() keeps the peak of earlier windows. Returns false
/// if the kernel does not allow it (then windows are not separated).
bool resetPeakMemoryWindow();

/// Peak resident set size since the last resetPeakMemoryWindow() (the whole run before one).
std::size_t windowPeakMemoryBytes();

/// User + system CPU time of this process so far (all threads), seconds (getrusage). Unlike
/// wall time it does not grow when other processes share the machine.
double processCpuTimeS();

}  // namespace vdbmap
