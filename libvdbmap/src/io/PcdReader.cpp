// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "io/FileUtil.h"
#include "io/Lzf.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {
namespace {

struct PcdField {
    std::string name;
    std::size_t size = 4;
    char type = 'F';
    std::size_t count = 1;
    std::size_t offset = 0;  // bytes from the start of a point (binary) / first value (ascii)
};

struct PcdHeader {
    std::vector<PcdField> fields;
    std::size_t width = 0, height = 1, points = 0;
    bool have_points = false, have_width = false;
    std::string data;
    std::size_t data_offset = 0;
    std::size_t point_step = 0;   // bytes per point
    std::size_t value_count = 0;  // values per point (sum of COUNT)
};

double loadValue(const char* p, char type, std::size_t size) {
    // Little-endian, as PCL writes on every platform it supports.
    const auto get = [p](auto v) {
        std::memcpy(&v, p, sizeof(v));
        return static_cast<double>(v);
    };
    if (type == 'F') return size == 4 ? get(float{}) : get(double{});
    if (type == 'U') {
        switch (size) {
            case 1:
                return get(std::uint8_t{});
            case 2:
                return get(std::uint16_t{});
            case 4:
                return get(std::uint32_t{});
            default:
                return get(std::uint64_t{});
        }
    }
    switch (size) {
        case 1:
            return get(std::int8_t{});
        case 2:
            return get(std::int16_t{});
        case 4:
            return get(std::int32_t{});
        default:
            return get(std::int64_t{});
    }
}

// The field columns of a header until its DATA line: FIELDS, SIZE, TYPE, COUNT as given.
struct PcdColumns {
    std::vector<std::string> names, sizes, types, counts;
};

// Throws the message for a bad header line: "<file>:<line>: corrupt PCD header line '...': why".
struct PcdHeaderLine {
    const std::filesystem::path& path;
    std::size_t number;
    const std::string& text;

    IoError error(const std::string& why) const {
        return IoError(detail::fileLine(path, number) + ": corrupt PCD header line '" +
                       text.substr(0, 120) + "': " + why);
    }
};

// WIDTH, HEIGHT, POINTS: one non-negative integer. NaN and values past 2^50 are refused
// before the cast (UB otherwise).
std::size_t headerCount(const std::vector<std::string>& rest, const PcdHeaderLine& line) {
    double v = 0;
    if (rest.size() != 1 || !detail::parseDouble(rest[0], v) || !(v >= 0) || v > 1e15 ||
        v != std::floor(v)) {
        throw line.error("expected one non-negative integer");
    }
    return static_cast<std::size_t>(v);
}

// Every token must be one of `allowed` ("SIZE", {"1", "2", "4", "8"}).
void checkTokens(const std::vector<std::string>& rest, std::initializer_list<const char*> allowed,
                 const char* key, const char* expected, const PcdHeaderLine& line) {
    for (const std::string& t : rest) {
        if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return t == a; })) {
            throw line.error(std::string("invalid ") + key + " '" + t + "' (expected " + expected + ")");
        }
    }
}

void checkCounts(const std::vector<std::string>& rest, const PcdHeaderLine& line) {
    for (const std::string& t : rest) {
        double c = 0;
        if (!detail::parseDouble(t, c) || !(c >= 1 && c <= 1e6) || c != std::floor(c)) {
            throw line.error("invalid COUNT '" + t + "' (expected a positive integer)");
        }
    }
}

// At DATA: the fields with their offsets, and the point count checked against WIDTH x HEIGHT.
void finishHeader(const PcdColumns& c, const PcdHeaderLine& line, PcdHeader& h) {
    if (c.names.empty()) throw line.error("DATA before FIELDS");
    if (c.sizes.size() != c.names.size() || c.types.size() != c.names.size() ||
        (!c.counts.empty() && c.counts.size() != c.names.size())) {
        throw line.error("FIELDS has " + std::to_string(c.names.size()) +
                         " names but SIZE/TYPE/COUNT have " + std::to_string(c.sizes.size()) +
                         "/" + std::to_string(c.types.size()) + "/" +
                         std::to_string(c.counts.empty() ? c.names.size() : c.counts.size()));
    }
    for (std::size_t i = 0; i < c.names.size(); ++i) {
        PcdField f;
        f.name = c.names[i];
        f.size = static_cast<std::size_t>(std::stoul(c.sizes[i]));
        f.type = c.types[i][0];
        if (f.type == 'F' && f.size != 4 && f.size != 8) {
            throw line.error("field '" + f.name + "' is TYPE F with SIZE " + c.sizes[i] +
                             " (floats are 4 or 8 bytes)");
        }
        f.count = c.counts.empty() ? 1 : static_cast<std::size_t>(std::stoul(c.counts[i]));
        f.offset = h.point_step;
        h.point_step += f.size * f.count;
        h.value_count += f.count;
        h.fields.push_back(f);
    }
    if (!h.have_width) throw line.error("no WIDTH line before DATA");
    if (h.height != 0 && h.width > std::numeric_limits<std::size_t>::max() / h.height) {
        throw line.error("WIDTH x HEIGHT overflows");
    }
    if (!h.have_points) h.points = h.width * h.height;
    if (h.width * h.height != h.points) {
        throw line.error("WIDTH x HEIGHT = " + std::to_string(h.width * h.height) +
                         " but POINTS = " + std::to_string(h.points));
    }
}

// One header line: its keyword and values into `c` and `h` (h.data set at DATA).
void parseHeaderLine(const std::vector<std::string>& tok, const PcdHeaderLine& line,
                     PcdColumns& c, PcdHeader& h) {
    const std::string& key = tok[0];
    const std::vector<std::string> rest(tok.begin() + 1, tok.end());
    if (key == "VERSION") return;
    if (key == "FIELDS" || key == "COLUMNS") {
        if (rest.empty()) throw line.error("no field names");
        c.names = rest;
    } else if (key == "SIZE") {
        checkTokens(rest, {"1", "2", "4", "8"}, "SIZE", "1, 2, 4 or 8", line);
        c.sizes = rest;
    } else if (key == "TYPE") {
        checkTokens(rest, {"F", "U", "I"}, "TYPE", "F, U or I", line);
        c.types = rest;
    } else if (key == "COUNT") {
        checkCounts(rest, line);
        c.counts = rest;
    } else if (key == "WIDTH") {
        h.width = headerCount(rest, line);
        h.have_width = true;
    } else if (key == "HEIGHT") {
        h.height = headerCount(rest, line);
    } else if (key == "POINTS") {
        h.points = headerCount(rest, line);
        h.have_points = true;
    } else if (key == "VIEWPOINT") {
        std::vector<double> v;
        if (!detail::parseDoubles(rest, 0, v) || v.size() != 7) {
            throw line.error("expected 7 numbers (tx ty tz qw qx qy qz)");
        }
    } else if (key == "DATA") {
        if (rest.size() != 1 ||
            (rest[0] != "ascii" && rest[0] != "binary" && rest[0] != "binary_compressed")) {
            throw line.error("expected 'DATA ascii', 'DATA binary' or 'DATA binary_compressed'");
        }
        finishHeader(c, line, h);
        h.data = rest[0];
    } else {
        throw line.error("unknown keyword '" + key + "'");
    }
}

PcdHeader parseHeader(const std::string& bytes, const std::filesystem::path& path) {
    PcdHeader h;
    PcdColumns columns;
    std::size_t pos = 0;
    std::size_t line_number = 0;
    while (h.data.empty()) {
        const std::size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) {
            throw IoError(path.string() + ": corrupt PCD header: no DATA line");
        }
        const std::string text(detail::trim(std::string_view(bytes).substr(pos, end - pos)));
        pos = end + 1;
        ++line_number;
        if (text.empty() || text[0] == '#') continue;
        parseHeaderLine(detail::splitWhitespace(text), PcdHeaderLine{path, line_number, text},
                        columns, h);
    }
    h.data_offset = pos;
    return h;
}

int findField(const PcdHeader& h, std::initializer_list<const char*> names) {
    for (const char* name : names) {
        for (std::size_t i = 0; i < h.fields.size(); ++i) {
            if (h.fields[i].name == name) return static_cast<int>(i);
        }
    }
    return -1;
}

/// The fields we keep (x, y, z and an optional intensity) and the cloud they fill.
class PointSink {
public:
    PointSink(const PcdHeader& h, const std::filesystem::path& path) {
        fx_ = findField(h, {"x"});
        fy_ = findField(h, {"y"});
        fz_ = findField(h, {"z"});
        if (fx_ < 0 || fy_ < 0 || fz_ < 0) {
            throw IoError(path.string() +
                          ": PCD has no x, y and z fields (FIELDS must include them)");
        }
        fi_ = findField(h, {"intensity", "i", "reflectance", "remission"});
        cloud_.points.resize(h.points);
        if (fi_ >= 0) cloud_.intensity.resize(h.points);
    }
    /// The fields that are read (intensity is -1 when absent).
    std::array<int, 4> usedFields() const { return {fx_, fy_, fz_, fi_}; }
    void store(std::size_t point, int field, double v) {
        if (field == fx_) cloud_.points[point].x() = static_cast<float>(v);
        if (field == fy_) cloud_.points[point].y() = static_cast<float>(v);
        if (field == fz_) cloud_.points[point].z() = static_cast<float>(v);
        if (field == fi_) cloud_.intensity[point] = static_cast<float>(v);
    }
    PointCloud take() { return std::move(cloud_); }

private:
    int fx_ = -1, fy_ = -1, fz_ = -1, fi_ = -1;
    PointCloud cloud_;
};

/// A corrupt POINTS must not make us allocate gigabytes: bound it by what the data can hold
/// (ascii: 2 bytes per value at least; binary: point_step bytes; LZF: at most ~90x).
void checkPointCountFits(const PcdHeader& h, std::size_t available,
                         const std::filesystem::path& path) {
    const std::size_t min_bytes_per_point = h.data == "ascii"    ? 2 * h.value_count
                                            : h.data == "binary" ? h.point_step
                                                                 : 1;
    const std::size_t max_points =
        (h.data == "binary_compressed" ? 100 * available / std::max<std::size_t>(1, h.point_step)
         : h.data == "ascii"           ? available + 1  // no separator after the last value
                                       : available) /
        std::max<std::size_t>(1, min_bytes_per_point);
    if (h.points > max_points) {
        throw IoError(path.string() + ": PCD header says POINTS " + std::to_string(h.points) +
                      " but the file has only " + std::to_string(available) + " bytes of " +
                      h.data + " data (truncated file or corrupt header)");
    }
}

/// DATA ascii: one point per non-empty line, value_count numbers each.
void readAsciiData(const std::string& bytes, const PcdHeader& h, PointSink& sink,
                   const std::filesystem::path& path) {
    std::size_t pos = h.data_offset;
    std::size_t line_number = 0;
    for (std::size_t k = 0; k < h.data_offset; ++k) line_number += bytes[k] == '\n';
    std::vector<double> values;
    std::size_t point = 0;
    while (point < h.points) {
        if (pos >= bytes.size()) {
            throw IoError(path.string() + ": PCD ascii data has " + std::to_string(point) +
                          " points, header says POINTS " + std::to_string(h.points));
        }
        std::size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) end = bytes.size();
        ++line_number;
        const std::string_view line = std::string_view(bytes).substr(pos, end - pos);
        pos = end + 1;
        const std::vector<std::string> tok = detail::splitWhitespace(line);
        if (tok.empty()) continue;
        if (!detail::parseDoubles(tok, 0, values) || values.size() != h.value_count) {
            throw IoError(detail::fileLine(path, line_number) + ": PCD ascii point " +
                          std::to_string(point) + " needs " + std::to_string(h.value_count) +
                          " numbers");
        }
        std::size_t value_index = 0;
        for (std::size_t f = 0; f < h.fields.size(); ++f) {
            sink.store(point, static_cast<int>(f), values[value_index]);
            value_index += h.fields[f].count;
        }
        ++point;
    }
}

/// DATA binary: point-major records of point_step bytes.
void readBinaryData(const std::string& bytes, const PcdHeader& h, PointSink& sink,
                    const std::filesystem::path& path) {
    const std::size_t available = bytes.size() - h.data_offset;
    const std::size_t n = h.points;
    if (available < n * h.point_step) {
        throw IoError(path.string() + ": PCD binary data is truncated: " + std::to_string(n) +
                      " points x " + std::to_string(h.point_step) + " bytes need " +
                      std::to_string(n * h.point_step) + ", file has " +
                      std::to_string(available));
    }
    const char* data = bytes.data() + h.data_offset;
    for (const int f : sink.usedFields()) {
        if (f < 0) continue;
        const PcdField& field = h.fields[f];
        for (std::size_t i = 0; i < n; ++i) {
            sink.store(i, f,
                       loadValue(data + i * h.point_step + field.offset, field.type, field.size));
        }
    }
}

/// DATA binary_compressed: uint32 compressed size, uint32 uncompressed size, LZF stream.
/// The uncompressed buffer is field-major: all points' values of field 0, then field 1, ...
void readCompressedData(const std::string& bytes, const PcdHeader& h, PointSink& sink,
                        const std::filesystem::path& path) {
    const std::size_t available = bytes.size() - h.data_offset;
    const std::size_t n = h.points;
    if (available < 8) {
        throw IoError(path.string() + ": PCD binary_compressed data is truncated (no sizes)");
    }
    std::uint32_t compressed_size = 0, uncompressed_size = 0;
    std::memcpy(&compressed_size, bytes.data() + h.data_offset, 4);
    std::memcpy(&uncompressed_size, bytes.data() + h.data_offset + 4, 4);
    if (compressed_size > available - 8) {
        throw IoError(path.string() + ": PCD binary_compressed data is truncated: header says " +
                      std::to_string(compressed_size) + " compressed bytes, file has " +
                      std::to_string(available - 8));
    }
    if (uncompressed_size != n * h.point_step) {
        throw IoError(path.string() + ": PCD binary_compressed uncompressed size " +
                      std::to_string(uncompressed_size) + " does not match " + std::to_string(n) +
                      " points x " + std::to_string(h.point_step) + " bytes");
    }
    std::vector<std::uint8_t> raw(uncompressed_size);
    if (uncompressed_size > 0 && !detail::lzfDecompress(reinterpret_cast<const std::uint8_t*>(
                                                            bytes.data() + h.data_offset + 8),
                                                        compressed_size, raw.data(), raw.size())) {
        throw IoError(path.string() +
                      ": PCD binary_compressed data is corrupt (LZF decode failed)");
    }
    const char* data = reinterpret_cast<const char*>(raw.data());
    for (const int f : sink.usedFields()) {
        if (f < 0) continue;
        const PcdField& field = h.fields[f];
        const std::size_t stride = field.size * field.count;
        const char* column = data + n * field.offset;
        for (std::size_t i = 0; i < n; ++i) {
            sink.store(i, f, loadValue(column + i * stride, field.type, field.size));
        }
    }
}

}  // namespace

// Phases: header, the fields we keep, a bound on POINTS, then the data in its encoding.
PointCloud readPcd(const std::filesystem::path& path) {
    const std::string bytes = detail::readWholeFile(path);
    const PcdHeader h = parseHeader(bytes, path);
    checkPointCountFits(h, bytes.size() - h.data_offset, path);
    PointSink sink(h, path);
    if (h.data == "ascii") {
        readAsciiData(bytes, h, sink, path);
    } else if (h.data == "binary") {
        readBinaryData(bytes, h, sink, path);
    } else {
        readCompressedData(bytes, h, sink, path);
    }
    return sink.take();
}

}  // namespace vdbmap
