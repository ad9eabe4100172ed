// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <stdexcept>
#include <string>

namespace vdbmap {

/// Base of every error vdbmap throws. Library code never exits or prints: it throws one of
/// these, and the apps map them to exit codes (ConfigError and PluginError -> 2, everything
/// else -> 1).
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A configuration problem: unknown key, missing key, wrong type, bad value, layer without a
/// writer. Messages carry `file:line:col` and the stage name where they are known.
class ConfigError : public Error {
public:
    using Error::Error;
};

/// A plugin could not be loaded: not a shared object, missing entry symbol, ABI mismatch.
/// The message names the file, the expected value and the value found.
class PluginError : public Error {
public:
    using Error::Error;
};

/// A file could not be read or written, or its content is malformed. Names the file.
class IoError : public Error {
public:
    using Error::Error;
};

/// A public-API precondition was violated by the caller (e.g. a negative voxel size).
class InvalidInput : public Error {
public:
    using Error::Error;
};

}  // namespace vdbmap
