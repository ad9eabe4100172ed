// SPDX-License-Identifier: Apache-2.0
// Shared by the libFuzzer targets (tests/fuzz/*Fuzz.cpp): the readers take paths, so each input
// is written to a per-process scratch folder first. A target may only end an input with a
// vdbmap::Error (the readers' typed errors); anything else (another exception, a crash, an
// ASan/UBSan report) is a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "vdbmap/Error.h"

namespace vdbmap::fuzz {

/// The scratch folder (in /dev/shm when there is one), removed at exit.
inline const std::filesystem::path& scratchDir() {
    static const std::filesystem::path dir = [] {
        std::error_code ec;
        const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                               ? std::filesystem::path("/dev/shm")
                                               : std::filesystem::temp_directory_path();
        std::filesystem::path d = base / ("vdbmap-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code rm_ec;
            std::filesystem::remove_all(scratchDir(), rm_ec);
        });
        return d;
    }();
    return dir;
}

/// Writes `bytes` to `<scratch>/<name>` and returns the path.
inline std::filesystem::path writeInput(const std::string& name, std::string_view bytes) {
    const std::filesystem::path path = scratchDir() / name;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
        std::abort();
    }
    std::fclose(f);
    return path;
}

/// Splits an input at every `separator` (multi-file inputs: OBJ + MTL, YAML + --set values).
inline std::vector<std::string_view> splitInput(std::string_view bytes,
                                                std::string_view separator) {
    std::vector<std::string_view> parts;
    std::size_t pos = 0;
    while (true) {
        const std::size_t next = bytes.find(separator, pos);
        if (next == std::string_view::npos) {
            parts.push_back(bytes.substr(pos));
            return parts;
        }
        parts.push_back(bytes.substr(pos, next - pos));
        pos = next + separator.size();
    }
}

/// Runs `f`; a vdbmap::Error is the expected way to refuse bad input.
template <typename F>
void refusesOnlyWithTypedErrors(F&& f) {
    try {
        f();
    } catch (const vdbmap::Error&) {
    }
}

inline std::string_view asText(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

}  // namespace vdbmap::fuzz
