// SPDX-License-Identifier: Apache-2.0
// Readers of vdbmap's meshes into numpy arrays (docs/DATA.md has the formats): a PLY with
// every vertex and face property (mesh.ply, semantic/mesh.ply with labels and confidences),
// and an OBJ with its texture coordinates and materials (textured/mesh.obj).
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "Bindings.h"
#include "io/FileUtil.h"
#include "io/PlyFormat.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap::python {
namespace {

template <typename T>
py::array_t<T> toArray(const std::vector<T>& values, std::size_t rows, std::size_t cols) {
    const auto r = static_cast<py::ssize_t>(rows), c = static_cast<py::ssize_t>(cols);
    py::array_t<T> out = cols == 1 ? py::array_t<T>(std::vector<py::ssize_t>{r})
                                   : py::array_t<T>(std::vector<py::ssize_t>{r, c});
    if (!values.empty()) std::memcpy(out.mutable_data(), values.data(), values.size() * sizeof(T));
    return out;
}

/// Every scalar property of `element`'s instances as a float64 column, by name.
struct Columns {
    std::vector<std::string> names;
    std::vector<std::vector<double>> values;
};

/// read_ply(path): {"vertices": (n,3) float32, "faces": (m,3) int64, "vertex": {name: (n,)},
/// "face": {name: (m,)}}. Faces must be triangles (vdbmap writes only triangles).
py::dict readPly(const std::string& path) {
    const std::string bytes = detail::readWholeFile(path);
    const detail::PlyHeader header = detail::parsePlyHeader(bytes, path);
    detail::PlyDataReader reader(bytes, header, path);
    std::vector<float> xyz;
    std::vector<std::int64_t> faces;
    Columns vertex_columns, face_columns;
    std::size_t n_vertices = 0, n_faces = 0;
    std::vector<double> scalars;
    std::vector<std::vector<double>> lists;
    for (const detail::PlyElement& element : header.elements) {
        const bool is_vertex = element.name == "vertex";
        const bool is_face = element.name == "face";
        Columns* columns = is_vertex ? &vertex_columns : is_face ? &face_columns : nullptr;
        int ix = -1, iy = -1, iz = -1, scalar_index = 0;
        std::vector<int> column_of_scalar;
        for (const detail::PlyProperty& p : element.properties) {
            if (p.is_list) continue;
            if (is_vertex && p.name == "x") ix = scalar_index;
            if (is_vertex && p.name == "y") iy = scalar_index;
            if (is_vertex && p.name == "z") iz = scalar_index;
            column_of_scalar.push_back(columns ? static_cast<int>(columns->names.size()) : -1);
            if (columns) {
                columns->names.push_back(p.name);
                columns->values.emplace_back();
                columns->values.back().reserve(element.count);
            }
            ++scalar_index;
        }
        if (is_vertex && (ix < 0 || iy < 0 || iz < 0))
            throw IoError(path + ": PLY vertex element lacks x, y or z");
        for (std::size_t k = 0; k < element.count; ++k) {
            reader.read(element, scalars, lists);
            if (columns == nullptr) continue;
            for (std::size_t s = 0; s < scalars.size(); ++s)
                columns->values[static_cast<std::size_t>(column_of_scalar[s])].push_back(scalars[s]);
            if (is_vertex) {
                xyz.push_back(static_cast<float>(scalars[static_cast<std::size_t>(ix)]));
                xyz.push_back(static_cast<float>(scalars[static_cast<std::size_t>(iy)]));
                xyz.push_back(static_cast<float>(scalars[static_cast<std::size_t>(iz)]));
            } else if (is_face) {
                if (lists.empty() || lists[0].size() != 3)
                    throw IoError(path + ": PLY face " + std::to_string(k) + " is not a triangle (" +
                                  std::to_string(lists.empty() ? 0 : lists[0].size()) + " corners)");
                for (const double v : lists[0]) faces.push_back(static_cast<std::int64_t>(v));
            }
        }
        if (is_vertex) n_vertices = element.count;
        if (is_face) n_faces = element.count;
    }
    for (const std::int64_t v : faces)
        if (v < 0 || static_cast<std::size_t>(v) >= n_vertices)
            throw IoError(path + ": PLY face refers to vertex " + std::to_string(v) + " of " +
                          std::to_string(n_vertices));
    py::dict out;
    out["vertices"] = toArray(xyz, n_vertices, 3);
    out["faces"] = toArray(faces, n_faces, 3);
    py::dict vertex, face;
    for (std::size_t c = 0; c < vertex_columns.names.size(); ++c)
        vertex[py::str(vertex_columns.names[c])] = toArray(vertex_columns.values[c], n_vertices, 1);
    for (std::size_t c = 0; c < face_columns.names.size(); ++c)
        face[py::str(face_columns.names[c])] = toArray(face_columns.values[c], n_faces, 1);
    out["vertex"] = vertex;
    out["face"] = face;
    return out;
}

/// read_obj(path): positions (n,3) float32, uvs (k,2) float32, faces (m,3) int64, face_uvs
/// (m,3) int64 (-1 without uvs), face_material (m,) int64, materials [{name, diffuse, texture}].
py::dict readObjArrays(const std::string& path) {
    const ObjMesh obj = readObj(path);
    std::vector<float> positions, uvs;
    for (const Vec3f& p : obj.positions) positions.insert(positions.end(), {p.x(), p.y(), p.z()});
    for (const Eigen::Vector2f& t : obj.uvs) uvs.insert(uvs.end(), {t.x(), t.y()});
    std::vector<std::int64_t> faces, face_uvs, face_material;
    for (const ObjMesh::Triangle& t : obj.triangles) {
        for (int c = 0; c < 3; ++c) {
            faces.push_back(t.v[static_cast<std::size_t>(c)]);
            face_uvs.push_back(obj.uvs.empty() ? -1 : static_cast<std::int64_t>(t.vt[static_cast<std::size_t>(c)]));
        }
        face_material.push_back(t.material);
    }
    py::list materials;
    for (const ObjMaterial& mat : obj.materials) {
        py::dict d;
        d["name"] = mat.name;
        d["diffuse"] = py::make_tuple(mat.diffuse[0], mat.diffuse[1], mat.diffuse[2]);
        d["texture"] = mat.texture;
        materials.append(d);
    }
    py::dict out;
    out["positions"] = toArray(positions, obj.positions.size(), 3);
    out["uvs"] = toArray(uvs, obj.uvs.size(), 2);
    out["faces"] = toArray(faces, obj.triangles.size(), 3);
    out["face_uvs"] = toArray(face_uvs, obj.triangles.size(), 3);
    out["face_material"] = toArray(face_material, obj.triangles.size(), 1);
    out["materials"] = materials;
    return out;
}

}  // namespace

void registerReaders(py::module_& m) {
    m.def("_read_ply", &readPly, py::arg("path"));
    m.def("_read_obj", &readObjArrays, py::arg("path"));
}

}  // namespace vdbmap::python
