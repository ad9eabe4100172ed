// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

/// Which file a URL path of `vdbmap view` names: a pure function, unit-tested on its own
/// (tests/unit/ViewServedPathTest.cpp) because it is the server's only safety check.

namespace vdbmap::view {

/// Decodes %XX escapes (once; '+' stays '+'). nullopt on a malformed escape or a decoded NUL.
std::optional<std::string> percentDecode(std::string_view text);

/// The regular file that `relative_url_path` (a URL path below a mount point, already
/// percent-decoded once by the server) names under `root`, or nullopt when it must not be
/// served: a ".." segment, a backslash, a NUL, a path that does not exist or is not a regular
/// file, or one whose canonical path (symbolic links resolved) is not under `root`'s
/// canonical path. Any remaining %XX escape is decoded a second time before the checks, so
/// "%252e%252e" cannot smuggle a ".." through a later decoding. `root` must exist.
std::optional<std::filesystem::path> resolveServedPath(const std::filesystem::path& root,
                                                       std::string_view relative_url_path);

/// The Content-Type for a file name by its extension (application/octet-stream otherwise).
std::string contentTypeFor(const std::filesystem::path& file);

}  // namespace vdbmap::view
