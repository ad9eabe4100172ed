// SPDX-License-Identifier: Apache-2.0
#include <charconv>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "io/Lzf.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {

void writePcd(const std::filesystem::path& path, const PointCloud& cloud, PcdEncoding encoding) {
    const std::size_t n = cloud.size();
    const bool has_intensity = cloud.intensity.size() == n;
    const auto value = [&](std::size_t i, int field) {
        return field < 3 ? cloud.points[i][field] : (has_intensity ? cloud.intensity[i] : 0.0f);
    };
    std::ostringstream header;
    header << "# .PCD v0.7 - Point Cloud Data file format (written by vdbmap)\n"
           << "VERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\n"
           << "COUNT 1 1 1 1\nWIDTH " << n << "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " << n
           << "\nDATA "
           << (encoding == PcdEncoding::Ascii    ? "ascii"
               : encoding == PcdEncoding::Binary ? "binary"
                                                 : "binary_compressed")
           << "\n";
    std::string bytes = header.str();
    if (encoding == PcdEncoding::Ascii) {
        char buffer[64];
        bytes.reserve(bytes.size() + n * 48);
        for (std::size_t i = 0; i < n; ++i) {
            for (int f = 0; f < 4; ++f) {
                // Shortest text that reads back as the same float (std::to_chars guarantee);
                // NaN is written "nan", which readPcd (strtod) accepts.
                const std::to_chars_result r =
                    std::to_chars(buffer, buffer + sizeof(buffer), value(i, f));
                bytes.append(buffer, r.ptr);
                bytes += f < 3 ? ' ' : '\n';
            }
        }
    } else {
        // Binary: point-major (x y z i per point). Compressed: field-major, then LZF.
        std::string raw(n * 4 * sizeof(float), '\0');
        for (std::size_t i = 0; i < n; ++i) {
            for (int f = 0; f < 4; ++f) {
                const float v = value(i, f);
                const std::size_t at = encoding == PcdEncoding::Binary
                                           ? (i * 4 + f) * sizeof(float)
                                           : (f * n + i) * sizeof(float);
                std::memcpy(raw.data() + at, &v, sizeof(float));
            }
        }
        if (encoding == PcdEncoding::Binary) {
            bytes += raw;
        } else {
            const std::string packed =
                detail::lzfCompress(reinterpret_cast<const std::uint8_t*>(raw.data()), raw.size());
            const std::uint32_t sizes[2] = {static_cast<std::uint32_t>(packed.size()),
                                            static_cast<std::uint32_t>(raw.size())};
            bytes.append(reinterpret_cast<const char*>(sizes), sizeof(sizes));
            bytes += packed;
        }
    }
    writeFileAtomically(path, bytes);
}

}  // namespace vdbmap
