// SPDX-License-Identifier: Apache-2.0
#include <cstring>
#include <sstream>

#include "io/FileUtil.h"
#include "io/PlyFormat.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/Log.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap {
namespace {

template <typename T>
void put(std::string& out, T value) {
    char buffer[sizeof(T)];
    std::memcpy(buffer, &value, sizeof(T));  // little-endian host (x86-64, aarch64)
    out.append(buffer, sizeof(T));
}

void checkSize(const void* data, std::size_t size, std::size_t expected, const char* what,
               const std::filesystem::path& path) {
    if (data != nullptr && size != expected) {
        throw InvalidInput("writeMeshPly(" + path.string() + "): " + what + " has " +
                           std::to_string(size) + " entries, the mesh has " +
                           std::to_string(expected));
    }
}

}  // namespace

void writeMeshPly(const std::filesystem::path& path, const TriMesh& mesh,
                  const PlyWriteOptions& options) {
    checkSize(options.face_labels, options.face_labels ? options.face_labels->size() : 0,
              mesh.n_faces(), "face_labels", path);
    checkSize(options.face_colors, options.face_colors ? options.face_colors->size() : 0,
              mesh.n_faces(), "face_colors", path);
    checkSize(options.face_confidence,
              options.face_confidence ? options.face_confidence->size() : 0, mesh.n_faces(),
              "face_confidence", path);
    checkSize(options.vertex_colors, options.vertex_colors ? options.vertex_colors->size() : 0,
              mesh.n_vertices(), "vertex_colors", path);
    const bool normals = options.vertex_normals && mesh.has_vertex_normals();
    // Deleted (not yet garbage-collected) elements are skipped; vertices are renumbered.
    std::vector<std::int32_t> new_index(mesh.n_vertices(), -1);
    std::size_t num_vertices = 0;
    for (const auto vh : mesh.vertices())
        new_index[vh.idx()] = static_cast<std::int32_t>(num_vertices++);
    std::size_t num_faces = 0;
    for (const auto fh : mesh.faces()) {
        (void)fh;
        ++num_faces;
    }
    std::ostringstream header;
    header << "ply\nformat binary_little_endian 1.0\ncomment vdbmap\nelement vertex "
           << num_vertices << "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) header << "property float nx\nproperty float ny\nproperty float nz\n";
    if (options.vertex_colors) {
        header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    }
    header << "element face " << num_faces << "\nproperty list uchar int vertex_indices\n";
    if (options.face_labels) header << "property uchar label\n";
    if (options.face_colors) {
        header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    }
    if (options.face_confidence) header << "property float confidence\n";
    header << "end_header\n";
    std::string bytes = header.str();
    bytes.reserve(bytes.size() + num_vertices * 27 + num_faces * 17);
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        put(bytes, p[0]);
        put(bytes, p[1]);
        put(bytes, p[2]);
        if (normals) {
            const auto& n = mesh.normal(vh);
            put(bytes, n[0]);
            put(bytes, n[1]);
            put(bytes, n[2]);
        }
        if (options.vertex_colors) {
            for (const std::uint8_t c : (*options.vertex_colors)[vh.idx()]) put(bytes, c);
        }
    }
    for (const auto fh : mesh.faces()) {
        std::int32_t corners[3];
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            if (k < 3) corners[k] = new_index[vh.idx()];
            ++k;
        }
        if (k != 3) {
            throw InvalidInput("writeMeshPly(" + path.string() + "): face " +
                               std::to_string(fh.idx()) + " has " + std::to_string(k) +
                               " vertices, expected a triangle");
        }
        put(bytes, std::uint8_t{3});
        for (const std::int32_t v : corners) put(bytes, v);
        if (options.face_labels) put(bytes, (*options.face_labels)[fh.idx()]);
        if (options.face_colors) {
            for (const std::uint8_t c : (*options.face_colors)[fh.idx()]) put(bytes, c);
        }
        if (options.face_confidence) put(bytes, (*options.face_confidence)[fh.idx()]);
    }
    writeFileAtomically(path, bytes);
}

TriMesh readMeshPly(const std::filesystem::path& path, std::vector<std::uint8_t>* face_labels) {
    return readMeshPly(path, face_labels, nullptr);
}

namespace {

// Scalar slot of a property (its position among the element's non-list properties), or -1.
int scalarSlot(const detail::PlyElement& element, const std::string& name) {
    int s = 0;
    for (const auto& p : element.properties) {
        if (p.name == name) return p.is_list ? -1 : s;
        if (!p.is_list) ++s;
    }
    return -1;
}

// List slot of a property (its position among the element's list properties), or -1.
int listSlot(const detail::PlyElement& element, const std::string& name) {
    int s = 0;
    for (const auto& p : element.properties) {
        if (p.name == name) return p.is_list ? s : -1;
        if (p.is_list) ++s;
    }
    return -1;
}

// What readMeshPly builds while it walks the elements.
struct PlyMeshBuild {
    TriMesh mesh;
    std::vector<TriMesh::VertexHandle> handles;  // file vertex index -> handle
    std::vector<std::uint8_t>* face_labels = nullptr;
    PlyReadStats counts;
};

void readVertices(const detail::PlyElement& element, detail::PlyDataReader& reader,
                  const std::filesystem::path& path, PlyMeshBuild& build) {
    const int ix = scalarSlot(element, "x"), iy = scalarSlot(element, "y");
    const int iz = scalarSlot(element, "z");
    const int inx = scalarSlot(element, "nx"), iny = scalarSlot(element, "ny");
    const int inz = scalarSlot(element, "nz");
    if (ix < 0 || iy < 0 || iz < 0) {
        throw IoError(path.string() + ": PLY vertex element lacks x, y or z");
    }
    const bool has_normals = inx >= 0 && iny >= 0 && inz >= 0;
    std::vector<double> s;
    std::vector<std::vector<double>> lists;
    for (std::size_t k = 0; k < element.count; ++k) {
        reader.read(element, s, lists);
        const auto vh = build.mesh.add_vertex(TriMesh::Point(
            static_cast<float>(s[ix]), static_cast<float>(s[iy]), static_cast<float>(s[iz])));
        if (has_normals) {
            build.mesh.set_normal(vh, TriMesh::Normal(static_cast<float>(s[inx]),
                                                      static_cast<float>(s[iny]),
                                                      static_cast<float>(s[inz])));
        }
        build.handles.push_back(vh);
    }
}

// Fan triangulation of one polygon; triangles OpenMesh rejects (non-manifold, repeated
// corners) are skipped and counted, so that labels stay aligned with the faces that exist.
void addPolygon(const std::vector<TriMesh::VertexHandle>& corners, int label,
                PlyMeshBuild& build) {
    ++build.counts.file_faces;
    for (std::size_t c = 1; c + 1 < corners.size(); ++c) {
        ++build.counts.triangles;
        const bool repeated = corners[0] == corners[c] || corners[c] == corners[c + 1] ||
                              corners[0] == corners[c + 1];
        const auto fh = repeated ? TriMesh::FaceHandle()
                                 : build.mesh.add_face(corners[0], corners[c], corners[c + 1]);
        if (!fh.is_valid()) {
            ++build.counts.rejected_triangles;
        } else if (build.face_labels != nullptr) {
            build.face_labels->push_back(static_cast<std::uint8_t>(label));
        }
    }
}

void readFaces(const detail::PlyElement& element, detail::PlyDataReader& reader,
               const std::filesystem::path& path, PlyMeshBuild& build) {
    int il = listSlot(element, "vertex_indices");
    if (il < 0) il = listSlot(element, "vertex_index");
    if (il < 0) throw IoError(path.string() + ": PLY face element has no vertex_indices list");
    const int ilabel = scalarSlot(element, "label");
    std::vector<double> s;
    std::vector<std::vector<double>> lists;
    std::vector<TriMesh::VertexHandle> corners;
    for (std::size_t k = 0; k < element.count; ++k) {
        reader.read(element, s, lists);
        if (ilabel >= 0 && !(s[ilabel] >= 0 && s[ilabel] <= 255)) {
            throw IoError(path.string() + ": PLY face " + std::to_string(k) + " has label " +
                          std::to_string(s[ilabel]) + " (class ids are 0..255)");
        }
        corners.clear();
        for (const double index : lists[il]) {
            if (!(index >= 0 && index < static_cast<double>(build.handles.size()))) {
                throw IoError(path.string() + ": PLY face " + std::to_string(k) +
                              " refers to vertex " + std::to_string(index) + " of " +
                              std::to_string(build.handles.size()));
            }
            corners.push_back(build.handles[static_cast<std::size_t>(index)]);
        }
        addPolygon(corners, ilabel >= 0 ? static_cast<int>(s[ilabel]) : 255, build);
    }
}

}  // namespace

TriMesh readMeshPly(const std::filesystem::path& path, std::vector<std::uint8_t>* face_labels,
                    PlyReadStats* stats) {
    const std::string bytes = detail::readWholeFile(path);
    const detail::PlyHeader header = detail::parsePlyHeader(bytes, path);
    PlyMeshBuild build;
    build.face_labels = face_labels;
    if (face_labels != nullptr) face_labels->clear();
    detail::PlyDataReader reader(bytes, header, path);
    std::vector<double> scalars;
    std::vector<std::vector<double>> lists;
    bool any_label = false;
    for (const detail::PlyElement& element : header.elements) {
        if (element.name == "vertex") {
            readVertices(element, reader, path, build);
        } else if (element.name == "face") {
            any_label = any_label || element.find("label") >= 0;
            readFaces(element, reader, path, build);
        } else {
            for (std::size_t k = 0; k < element.count; ++k) reader.read(element, scalars, lists);
        }
    }
    if (face_labels != nullptr && !any_label) face_labels->clear();
    const PlyReadStats& counts = build.counts;
    if (counts.rejected_triangles > 0) {
        logWarn(path.string() + ": " + std::to_string(counts.rejected_triangles) + " of " +
                std::to_string(counts.triangles) +
                " triangles were dropped (non-manifold or repeated corners; OpenMesh refuses "
                "them)");
    }
    if (stats != nullptr) *stats = counts;
    return std::move(build.mesh);
}

}  // namespace vdbmap
