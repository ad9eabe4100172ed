// SPDX-License-Identifier: Apache-2.0
#include "ServedPath.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <system_error>

namespace fs = std::filesystem;

namespace vdbmap::view {
namespace {

int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

/// True when `inner` is `outer` or below it; both canonical.
bool isWithin(const fs::path& outer, const fs::path& inner) {
    auto o = outer.begin();
    auto i = inner.begin();
    for (; o != outer.end(); ++o, ++i) {
        if (i == inner.end() || *o != *i) return false;
    }
    return true;
}

}  // namespace

std::optional<std::string> percentDecode(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t k = 0; k < text.size(); ++k) {
        char c = text[k];
        if (c == '%') {
            if (k + 2 >= text.size()) return std::nullopt;
            const int hi = hexValue(text[k + 1]);
            const int lo = hexValue(text[k + 2]);
            if (hi < 0 || lo < 0) return std::nullopt;
            c = static_cast<char>(hi * 16 + lo);
            k += 2;
        }
        if (c == '\0') return std::nullopt;
        out.push_back(c);
    }
    return out;
}

std::optional<fs::path> resolveServedPath(const fs::path& root, std::string_view relative_url_path) {
    // A second decoding: the server decoded once; whatever still looks escaped is decoded
    // again so that no later layer can turn it into a separator or a "..".
    std::optional<std::string> decoded = percentDecode(relative_url_path);
    if (!decoded) return std::nullopt;
    const std::string& text = *decoded;
    if (text.find('\\') != std::string::npos) return std::nullopt;

    fs::path relative;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find('/', start), text.size());
        const std::string segment = text.substr(start, end - start);
        start = end + 1;
        if (segment.empty() || segment == ".") continue;
        if (segment == "..") return std::nullopt;
        relative /= segment;
    }
    if (relative.empty()) return std::nullopt;

    std::error_code ec;
    const fs::path canonical_root = fs::canonical(root, ec);
    if (ec) return std::nullopt;
    const fs::path candidate = fs::canonical(canonical_root / relative, ec);
    if (ec) return std::nullopt;  // missing, or a dangling link
    if (!isWithin(canonical_root, candidate)) return std::nullopt;
    if (!fs::is_regular_file(candidate, ec) || ec) return std::nullopt;
    return candidate;
}

std::string contentTypeFor(const fs::path& file) {
    static const std::map<std::string, std::string> kTypes = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".json", "application/json"},
        {".glb", "model/gltf-binary"},
        {".gltf", "model/gltf+json"},
        {".bin", "application/octet-stream"},
        {".png", "image/png"},
        {".jpg", "image/jpeg"},
        {".jpeg", "image/jpeg"},
        {".ktx2", "image/ktx2"},
        {".wasm", "application/wasm"},
        {".txt", "text/plain; charset=utf-8"},
        {".md", "text/plain; charset=utf-8"},
        {".ply", "application/octet-stream"},
        {".svg", "image/svg+xml"},
        {".ico", "image/x-icon"},
    };
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto it = kTypes.find(ext);
    return it == kTypes.end() ? "application/octet-stream" : it->second;
}

}  // namespace vdbmap::view
