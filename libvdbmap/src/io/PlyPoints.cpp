// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cstring>
#include <sstream>

#include "io/FileUtil.h"
#include "io/PlyFormat.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap {

PointCloud readPlyPoints(const std::filesystem::path& path) {
    const std::string bytes = detail::readWholeFile(path);
    const detail::PlyHeader header = detail::parsePlyHeader(bytes, path);
    const int vertex_index = header.find("vertex");
    if (vertex_index < 0) throw IoError(path.string() + ": PLY has no 'vertex' element");
    const detail::PlyElement& vertex = header.elements[vertex_index];
    // Scalar slots: the position of each property among the non-list properties.
    const auto slot = [&](const std::string& name) {
        int s = 0;
        for (const auto& p : vertex.properties) {
            if (p.name == name) return p.is_list ? -1 : s;
            if (!p.is_list) ++s;
        }
        return -1;
    };
    const int ix = slot("x"), iy = slot("y"), iz = slot("z");
    if (ix < 0 || iy < 0 || iz < 0) {
        throw IoError(path.string() + ": PLY vertex element lacks x, y or z");
    }
    int ii = -1;
    for (const char* name : {"intensity", "scalar_intensity", "reflectance", "scalar_Intensity"}) {
        if (ii < 0) ii = slot(name);
    }
    PointCloud cloud;
    detail::PlyDataReader reader(bytes, header, path);
    std::vector<double> scalars;
    std::vector<std::vector<double>> lists;
    for (int e = 0; e <= vertex_index; ++e) {
        const detail::PlyElement& element = header.elements[e];
        const bool is_vertex = e == vertex_index;
        if (is_vertex) {
            // Bounded by the file size, so a corrupt count cannot trigger a huge allocation.
            const std::size_t reserve = std::min(element.count, bytes.size());
            cloud.points.reserve(reserve);
            if (ii >= 0) cloud.intensity.reserve(reserve);
        }
        for (std::size_t k = 0; k < element.count; ++k) {
            reader.read(element, scalars, lists);
            if (!is_vertex) continue;
            cloud.points.emplace_back(static_cast<float>(scalars[ix]),
                                      static_cast<float>(scalars[iy]),
                                      static_cast<float>(scalars[iz]));
            if (ii >= 0) cloud.intensity.push_back(static_cast<float>(scalars[ii]));
        }
    }
    return cloud;
}

void writePlyPoints(const std::filesystem::path& path, const PointCloud& cloud) {
    const bool has_intensity = cloud.intensity.size() == cloud.points.size();
    std::ostringstream header;
    header << "ply\nformat binary_little_endian 1.0\ncomment vdbmap\nelement vertex "
           << cloud.size()
           << "\nproperty float x\nproperty float y\nproperty float z\nproperty float "
              "intensity\nend_header\n";
    std::string bytes = header.str();
    const std::size_t offset = bytes.size();
    bytes.resize(offset + cloud.size() * 4 * sizeof(float));
    for (std::size_t i = 0; i < cloud.size(); ++i) {
        const float v[4] = {cloud.points[i].x(), cloud.points[i].y(), cloud.points[i].z(),
                            has_intensity ? cloud.intensity[i] : 0.0f};
        std::memcpy(bytes.data() + offset + i * sizeof(v), v, sizeof(v));
    }
    writeFileAtomically(path, bytes);
}

}  // namespace vdbmap
