// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/Progress.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace vdbmap {
namespace {

long long nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

bool progressAllowed(bool quiet) {
    if (quiet) return false;
    if (std::getenv("CI") != nullptr) return false;
    return ::isatty(STDERR_FILENO) == 1;
}

}  // namespace

Progress::Progress(std::string label, std::size_t total, bool quiet)
    : label_(std::move(label)), total_(total), enabled_(progressAllowed(quiet)) {}

Progress::~Progress() { finish(); }

void Progress::tick(std::size_t n) {
    const std::size_t done = done_.fetch_add(n) + n;
    if (!enabled_) return;
    const long long now = nowNs();
    long long last = last_draw_ns_.load();
    if (done < total_ && now - last < 100'000'000LL) return;
    if (!last_draw_ns_.compare_exchange_strong(last, now)) return;  // another thread draws
    draw(done);
}

void Progress::draw(std::size_t done) {
    constexpr int kWidth = 30;
    const double fraction = total_ > 0 ? static_cast<double>(done) / total_ : 1.0;
    const int filled = static_cast<int>(fraction * kWidth + 0.5);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%-24s [%s] %zu/%zu", label_.c_str(), bar.c_str(), done, total_);
    std::fflush(stderr);
}

void Progress::finish() {
    if (finished_) return;
    finished_ = true;
    if (!enabled_) return;
    draw(done_.load());
    std::fprintf(stderr, "\n");
    std::fflush(stderr);
}

}  // namespace vdbmap
