// SPDX-License-Identifier: Apache-2.0
#include "SemanticExport.h"

#include <cctype>

#include "vdbmap/Error.h"
#include "vdbmap/io/MeshIO.h"
#include "vdbmap/map/Layers.h"

namespace vdbmap::semantic {

namespace {

template <typename T>
void checkSize(const TriMesh& mesh, const std::vector<T>& face_labels, const char* who) {
    if (face_labels.size() != mesh.n_faces()) {
        throw InvalidInput(std::string(who) + ": " + std::to_string(face_labels.size()) +
                           " face labels for a mesh of " + std::to_string(mesh.n_faces()) +
                           " faces");
    }
}

std::string sanitized(const std::string& name) {
    std::string out;
    for (const char ch : name) {
        out += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    }
    return out;
}

}  // namespace

std::map<std::uint8_t, ClassStats> classStatistics(const TriMesh& mesh,
                                                   const std::vector<std::uint8_t>& face_labels) {
    checkSize(mesh, face_labels, "classStatistics");
    std::map<std::uint8_t, ClassStats> stats;
    for (const auto fh : mesh.faces()) {
        auto it = mesh.cfv_begin(fh);
        const auto a = mesh.point(*it++);
        const auto b = mesh.point(*it++);
        const auto c = mesh.point(*it);
        ClassStats& s = stats[face_labels[static_cast<std::size_t>(fh.idx())]];
        ++s.faces;
        s.area_m2 += 0.5 * static_cast<double>(((b - a) % (c - a)).norm());
    }
    return stats;
}

void setFaceLabelProperty(TriMesh& mesh, const std::vector<std::uint8_t>& face_labels) {
    checkSize(mesh, face_labels, "setFaceLabelProperty");
    OpenMesh::FPropHandleT<std::uint8_t> prop;
    if (!mesh.get_property_handle(prop, kFaceLabelProperty)) {
        mesh.add_property(prop, kFaceLabelProperty);
    }
    for (const auto fh : mesh.faces()) {
        mesh.property(prop, fh) = face_labels[static_cast<std::size_t>(fh.idx())];
    }
}

void setFaceConfidenceProperty(TriMesh& mesh, const std::vector<float>& confidence) {
    checkSize(mesh, confidence, "setFaceConfidenceProperty");
    OpenMesh::FPropHandleT<float> prop;
    if (!mesh.get_property_handle(prop, kFaceLabelConfidenceProperty)) {
        mesh.add_property(prop, kFaceLabelConfidenceProperty);
    }
    for (const auto fh : mesh.faces()) {
        mesh.property(prop, fh) = confidence[static_cast<std::size_t>(fh.idx())];
    }
}

void writeSemanticPly(const std::filesystem::path& path, const TriMesh& mesh,
                      const std::vector<std::uint8_t>& face_labels, const LabelSet& labels,
                      const std::vector<float>* confidence) {
    checkSize(mesh, face_labels, "writeSemanticPly");
    std::vector<std::array<std::uint8_t, 3>> colors(face_labels.size());
    for (std::size_t f = 0; f < face_labels.size(); ++f) colors[f] = labels.color(face_labels[f]);
    PlyWriteOptions options;
    options.face_labels = &face_labels;
    options.face_colors = &colors;
    options.face_confidence = confidence;
    writeMeshPly(path, mesh, options);
}

std::string classMaterialName(std::uint8_t id, const LabelSet& labels) {
    if (id == kUnknownLabel || labels.indexOf(id) < 0) return "unknown";
    return "class_" + std::to_string(id) + "_" + sanitized(labels.name(id));
}

void writeSemanticObj(const std::filesystem::path& path, const TriMesh& mesh,
                      const std::vector<std::uint8_t>& face_labels, const LabelSet& labels) {
    checkSize(mesh, face_labels, "writeSemanticObj");
    ObjMesh obj;
    obj.positions.reserve(mesh.n_vertices());
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        obj.positions.emplace_back(p[0], p[1], p[2]);
    }
    std::array<std::uint32_t, 256> material_of{};
    for (const LabelClass& c : labels.classes()) {
        material_of[c.id] = static_cast<std::uint32_t>(obj.materials.size());
        ObjMaterial m;
        m.name = classMaterialName(c.id, labels);
        m.diffuse = {c.rgb[0] / 255.0f, c.rgb[1] / 255.0f, c.rgb[2] / 255.0f};
        obj.materials.push_back(m);
    }
    const auto unknown = static_cast<std::uint32_t>(obj.materials.size());
    obj.materials.push_back({"unknown", {0.0f, 0.0f, 0.0f}, ""});
    obj.triangles.reserve(mesh.n_faces());
    for (const auto fh : mesh.faces()) {
        ObjMesh::Triangle t;
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            if (k < 3) t.v[k++] = static_cast<std::uint32_t>(vh.idx());
        }
        t.vt = {0, 0, 0};
        const std::uint8_t id = face_labels[static_cast<std::size_t>(fh.idx())];
        t.material = labels.indexOf(id) >= 0 ? material_of[id] : unknown;
        obj.triangles.push_back(t);
    }
    writeObj(path, obj);
}

TriMesh extractClassMesh(const TriMesh& mesh, const std::vector<std::uint8_t>& face_labels,
                         std::uint8_t id) {
    checkSize(mesh, face_labels, "extractClassMesh");
    TriMesh out;
    std::vector<int> new_index(mesh.n_vertices(), -1);
    for (const auto fh : mesh.faces()) {
        if (face_labels[static_cast<std::size_t>(fh.idx())] != id) continue;
        std::array<TriMesh::VertexHandle, 3> corners;
        int k = 0;
        for (const auto vh : mesh.fv_range(fh)) {
            if (k == 3) break;
            int& ni = new_index[static_cast<std::size_t>(vh.idx())];
            if (ni < 0) ni = out.add_vertex(mesh.point(vh)).idx();
            corners[k++] = TriMesh::VertexHandle(ni);
        }
        out.add_face(corners[0], corners[1], corners[2]);
    }
    out.update_normals();
    return out;
}

std::string classMeshFileName(std::uint8_t id, const LabelSet& labels) {
    const std::string name = labels.indexOf(id) >= 0 ? sanitized(labels.name(id)) : "unknown";
    return "class_" + std::to_string(id) + "_" + name + ".ply";
}

}  // namespace vdbmap::semantic
