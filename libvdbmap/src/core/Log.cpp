// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/Log.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>

namespace vdbmap {
namespace {

std::atomic<LogLevel> g_level{LogLevel::Info};

spdlog::logger& logger() {
    // stderr, so that stdout stays clean for machine-readable output (describe, eval --json).
    static std::shared_ptr<spdlog::logger> instance = [] {
        auto l = spdlog::stderr_color_mt("vdbmap");
        l->set_pattern("[%^%l%$] %v");
        l->set_level(spdlog::level::trace);
        return l;
    }();
    return *instance;
}

bool enabled(LogLevel level) {
    return static_cast<int>(level) >= static_cast<int>(g_level.load());
}

}  // namespace

void setLogLevel(LogLevel level) { g_level.store(level); }

void setLogPrefix(const std::string& prefix) {
    std::string text;
    for (const char c : prefix)
        if (c != '%') text.push_back(c);
    logger().set_pattern("[%^%l%$] " + text + "%v");
}
LogLevel logLevel() { return g_level.load(); }

void logDebug(const std::string& message) {
    if (enabled(LogLevel::Debug)) logger().debug(message);
}
void logInfo(const std::string& message) {
    if (enabled(LogLevel::Info)) logger().info(message);
}
void logWarn(const std::string& message) {
    if (enabled(LogLevel::Warn)) logger().warn(message);
}
void logError(const std::string& message) {
    if (enabled(LogLevel::Error)) logger().error(message);
}

}  // namespace vdbmap
