// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <string>

namespace vdbmap {

/// Log levels of the process-wide logger (spdlog underneath, kept out of the ABI).
enum class LogLevel { Debug, Info, Warn, Error, Off };

/// Sets the process-wide log level. The apps set it once from --quiet / --verbose.
void setLogLevel(LogLevel level);
LogLevel logLevel();

/// Thread-safe log lines to stderr, prefixed with the level.
void logDebug(const std::string& message);
void logInfo(const std::string& message);
void logWarn(const std::string& message);
void logError(const std::string& message);

}  // namespace vdbmap
