// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <atomic>
#include <cstddef>
#include <string>

namespace vdbmap {

/// Progress bar for long work (integration over scans, texturing). It draws on stderr only
/// when stderr is a TTY, `quiet` is false and the CI environment variable is unset; otherwise
/// it is silent. `tick()` is thread-safe and cheap (redraws at most ~10 times per second).
class Progress {
public:
    Progress(std::string label, std::size_t total, bool quiet);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    void tick(std::size_t n = 1);
    /// Clears the line. Called by the destructor too.
    void finish();
    bool enabled() const { return enabled_; }

private:
    void draw(std::size_t done);

    std::string label_;
    std::size_t total_;
    bool enabled_;
    std::atomic<std::size_t> done_{0};
    std::atomic<long long> last_draw_ns_{0};
    bool finished_ = false;
};

}  // namespace vdbmap
