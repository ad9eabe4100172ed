// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/core/Log.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <mutex>
#include <utility>

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

std::mutex g_sink_mutex;
LogSink g_sink;            ///< guarded by g_sink_mutex
std::atomic<bool> g_has_sink{false};

/// Sends a message to the sink; false if there is none (the caller logs to stderr).
bool toSink(LogLevel level, const std::string& message) {
    if (!g_has_sink.load()) return false;
    std::lock_guard<std::mutex> lock(g_sink_mutex);
    if (!g_sink) return false;
    g_sink(level, message);
    return true;
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

void setLogSink(LogSink sink) {
    std::lock_guard<std::mutex> lock(g_sink_mutex);
    g_sink = std::move(sink);
    g_has_sink.store(static_cast<bool>(g_sink));
}

void logDebug(const std::string& message) {
    if (enabled(LogLevel::Debug) && !toSink(LogLevel::Debug, message)) logger().debug(message);
}
void logInfo(const std::string& message) {
    if (enabled(LogLevel::Info) && !toSink(LogLevel::Info, message)) logger().info(message);
}
void logWarn(const std::string& message) {
    if (enabled(LogLevel::Warn) && !toSink(LogLevel::Warn, message)) logger().warn(message);
}
void logError(const std::string& message) {
    if (enabled(LogLevel::Error) && !toSink(LogLevel::Error, message)) logger().error(message);
}

}  // namespace vdbmap
