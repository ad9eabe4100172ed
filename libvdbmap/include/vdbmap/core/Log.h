// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <functional>
#include <string>

namespace vdbmap {

/// Log levels of the process-wide logger (spdlog underneath, kept out of the ABI).
enum class LogLevel { Debug, Info, Warn, Error, Off };

/// Sets the process-wide log level. The apps set it once from --quiet / --verbose.
void setLogLevel(LogLevel level);
LogLevel logLevel();
/// Text put in front of every message (after the level), e.g. "rank 2: " in the processes of
/// a distributed run. '%' is not allowed (spdlog pattern syntax) and is dropped.
void setLogPrefix(const std::string& prefix);

/// Where log lines go instead of stderr: `sink(level, message)` for every message that passes
/// the level (called from any thread, one call at a time). An empty function restores stderr.
/// The Python module sends them to Python's `logging`.
using LogSink = std::function<void(LogLevel, const std::string&)>;
void setLogSink(LogSink sink);

/// Thread-safe log lines to stderr, prefixed with the level.
void logDebug(const std::string& message);
void logInfo(const std::string& message);
void logWarn(const std::string& message);
void logError(const std::string& message);

}  // namespace vdbmap
