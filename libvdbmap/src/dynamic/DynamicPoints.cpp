// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/dynamic/DynamicPoints.h"

#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"

namespace vdbmap {

namespace {

constexpr std::size_t kRecordBytes = 5 * 4;

std::string header(std::size_t count) {
    std::ostringstream os;
    os << "ply\nformat binary_little_endian 1.0\ncomment vdbmap dynamic points: removed as "
          "moving, world frame W, metres\nelement vertex "
       << count
       << "\nproperty float x\nproperty float y\nproperty float z\nproperty uint frame\n"
          "property uint index\nend_header\n";
    return os.str();
}

// x86 and ARM are little-endian; a big-endian host would need byte swaps here.
static_assert(sizeof(float) == 4, "PLY float is 4 bytes");

}  // namespace

void DynamicPoints::append(const DynamicPoints& other) {
    points_W.insert(points_W.end(), other.points_W.begin(), other.points_W.end());
    frame.insert(frame.end(), other.frame.begin(), other.frame.end());
    index.insert(index.end(), other.index.begin(), other.index.end());
}

std::string dynamicPointsPly(const DynamicPoints& points) {
    std::string out = header(points.size());
    const std::size_t head = out.size();
    out.resize(head + points.size() * kRecordBytes);
    char* p = out.data() + head;
    for (std::size_t i = 0; i < points.size(); ++i) {
        std::memcpy(p, points.points_W[i].data(), 12);
        std::memcpy(p + 12, &points.frame[i], 4);
        std::memcpy(p + 16, &points.index[i], 4);
        p += kRecordBytes;
    }
    return out;
}

void writeDynamicPointsPly(const std::filesystem::path& path, const DynamicPoints& points) {
    writeFileAtomically(path, dynamicPointsPly(points));
}

DynamicPoints readDynamicPointsPly(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path.string() + ": cannot open");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t end = bytes.find("end_header\n");
    if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) {
        throw IoError(path.string() + ": not a PLY file (no 'ply' / 'end_header' line)");
    }
    const std::size_t body = end + std::strlen("end_header\n");
    std::istringstream head(bytes.substr(0, body));
    std::string line;
    std::size_t count = 0;
    std::string props;
    bool binary_le = false;
    while (std::getline(head, line)) {
        if (line.rfind("format ", 0) == 0) binary_le = line == "format binary_little_endian 1.0";
        if (line.rfind("element vertex ", 0) == 0) count = std::stoull(line.substr(15));
        if (line.rfind("property ", 0) == 0) props += line.substr(9) + ";";
    }
    if (!binary_le || props != "float x;float y;float z;uint frame;uint index;") {
        throw IoError(path.string() + ": not a dynamic points PLY (expected binary little-endian, "
                                      "float x y z, uint frame, uint index; got properties '" +
                      props + "')");
    }
    if (bytes.size() - body != count * kRecordBytes) {
        throw IoError(path.string() + ": " + std::to_string(count) + " vertices need " +
                      std::to_string(count * kRecordBytes) + " bytes, the file has " +
                      std::to_string(bytes.size() - body));
    }
    DynamicPoints out;
    const char* p = bytes.data() + body;
    for (std::size_t i = 0; i < count; ++i, p += kRecordBytes) {
        Vec3f v;
        std::uint32_t f = 0, k = 0;
        std::memcpy(v.data(), p, 12);
        std::memcpy(&f, p + 12, 4);
        std::memcpy(&k, p + 16, 4);
        out.add(v, f, k);
    }
    return out;
}

std::string dynamicPointsPartName(int rank) {
    return "dynamic_points.part" + std::to_string(rank) + ".ply";
}

std::size_t mergeDynamicPointParts(const std::filesystem::path& output_dir, int processes) {
    std::map<std::uint32_t, DynamicPoints> by_frame;
    bool any = false;
    for (int rank = 0; rank < processes; ++rank) {
        const std::filesystem::path part = output_dir / dynamicPointsPartName(rank);
        if (!std::filesystem::exists(part)) continue;
        any = true;
        const DynamicPoints points = readDynamicPointsPly(part);
        std::map<std::uint32_t, DynamicPoints> mine;
        for (std::size_t i = 0; i < points.size(); ++i) {
            mine[points.frame[i]].add(points.points_W[i], points.frame[i], points.index[i]);
        }
        for (auto& [frame, pts] : mine) by_frame.emplace(frame, std::move(pts));  // lowest rank wins
    }
    if (!any) return 0;
    DynamicPoints all;
    for (const auto& [frame, pts] : by_frame) all.append(pts);
    writeDynamicPointsPly(output_dir / "dynamic_points.ply", all);
    for (int rank = 0; rank < processes; ++rank) {
        std::error_code ec;
        std::filesystem::remove(output_dir / dynamicPointsPartName(rank), ec);
    }
    return all.size();
}

}  // namespace vdbmap
