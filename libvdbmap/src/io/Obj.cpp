// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"
#include "vdbmap/io/AtomicFile.h"
#include "vdbmap/io/MeshIO.h"

namespace vdbmap {
namespace {

void appendf(std::string& out, const char* format, double a, double b, double c = 0.0) {
    char buffer[160];
    std::snprintf(buffer, sizeof(buffer), format, a, b, c);
    out += buffer;
}

/// Reads a .mtl: newmtl, Kd, map_Kd (other statements ignored). Throws IoError.
std::vector<ObjMaterial> readMtl(const std::filesystem::path& path) {
    std::vector<ObjMaterial> materials;
    std::vector<double> v;
    detail::forEachLine(path, [&](const detail::TextLine& line) {
        const std::vector<std::string>& tok = line.tokens;
        if (tok.empty() || tok[0][0] == '#') return;
        const auto fail = [&](const std::string& why) {
            return IoError(detail::lineMessage(path, line, why));
        };
        if (tok[0] == "newmtl") {
            if (tok.size() != 2) throw fail("expected 'newmtl <name>'");
            materials.emplace_back();
            materials.back().name = tok[1];
        } else if (tok[0] == "Kd" || tok[0] == "map_Kd") {
            if (materials.empty()) throw fail(tok[0] + " before newmtl");
            if (tok[0] == "Kd") {
                if (!detail::parseDoubles(tok, 1, v) || v.size() != 3) throw fail("Kd needs r g b");
                for (int k = 0; k < 3; ++k) materials.back().diffuse[k] = static_cast<float>(v[k]);
            } else {
                if (tok.size() < 2) throw fail("map_Kd needs a file name");
                materials.back().texture = tok.back();  // options (-s, -o ...) come first
            }
        }
    });
    return materials;
}

/// A 1-based (or negative, from the end) OBJ index as a 0-based one below `count`. Written so
/// that NaN and fractions fail too (no UB in the cast). Throws IoError.
std::uint32_t objIndex(double index, std::size_t count, const char* what,
                       const std::filesystem::path& path, const detail::TextLine& line) {
    const double a = index < 0 ? static_cast<double>(count) + index : index - 1;
    if (index == 0 || !(a >= 0 && a < static_cast<double>(count)) || a != std::floor(a)) {
        throw IoError(detail::lineMessage(path, line, std::string(what) + " index " +
                                                          std::to_string(index) +
                                                          " out of range (have " +
                                                          std::to_string(count) + ")"));
    }
    return static_cast<std::uint32_t>(a);
}

/// The triangles of an 'f' line (a fan over its corners). Corner forms: v, v/vt, v//vn,
/// v/vt/vn; negative indices count from the end.
void parseFace(const std::filesystem::path& path, const detail::TextLine& line,
               std::uint32_t material, ObjMesh& mesh) {
    const std::vector<std::string>& tok = line.tokens;
    const auto fail = [&](const std::string& why) { return IoError(detail::lineMessage(path, line, why)); };
    if (tok.size() < 4) throw fail("a face needs at least 3 corners");
    std::vector<std::array<std::uint32_t, 2>> corners;
    for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string& c = tok[k];
        const std::size_t slash = c.find('/');
        double iv = 0, ivt = 0;
        if (!detail::parseDouble(c.substr(0, slash), iv)) throw fail("bad vertex index");
        if (slash != std::string::npos) {
            const std::size_t slash2 = c.find('/', slash + 1);
            const std::string vt = c.substr(
                slash + 1, slash2 == std::string::npos ? std::string::npos : slash2 - slash - 1);
            if (!vt.empty() && !detail::parseDouble(vt, ivt)) throw fail("bad uv index");
        }
        const std::uint32_t vi = objIndex(iv, mesh.positions.size(), "vertex", path, line);
        const std::uint32_t ti = ivt != 0 ? objIndex(ivt, mesh.uvs.size(), "uv", path, line) : 0;
        corners.push_back({vi, ti});
    }
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        ObjMesh::Triangle tri;
        tri.v = {corners[0][0], corners[k][0], corners[k + 1][0]};
        tri.vt = {corners[0][1], corners[k][1], corners[k + 1][1]};
        tri.material = material;
        mesh.triangles.push_back(tri);
    }
}

}  // namespace

void writeObj(const std::filesystem::path& path, const ObjMesh& mesh) {
    const bool has_uvs = !mesh.uvs.empty();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const ObjMesh::Triangle& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri.v[k] >= mesh.positions.size() || (has_uvs && tri.vt[k] >= mesh.uvs.size())) {
                throw InvalidInput("writeObj(" + path.string() + "): triangle " +
                                   std::to_string(t) + " refers to a missing vertex or uv");
            }
        }
        if (!mesh.materials.empty() && tri.material >= mesh.materials.size()) {
            throw InvalidInput("writeObj(" + path.string() + "): triangle " + std::to_string(t) +
                               " uses material " + std::to_string(tri.material) + " of " +
                               std::to_string(mesh.materials.size()));
        }
    }
    std::filesystem::path mtl_path = path;
    mtl_path.replace_extension(".mtl");
    std::string obj = "# vdbmap\n";
    if (!mesh.materials.empty()) {
        std::string mtl = "# vdbmap\n";
        for (const ObjMaterial& m : mesh.materials) {
            mtl += "newmtl " + m.name + "\n";
            appendf(mtl, "Ka %.6g %.6g %.6g\n", 0.0, 0.0, 0.0);
            appendf(mtl, "Kd %.6g %.6g %.6g\n", m.diffuse[0], m.diffuse[1], m.diffuse[2]);
            appendf(mtl, "Ks %.6g %.6g %.6g\nillum 1\n", 0.0, 0.0, 0.0);
            if (!m.texture.empty()) mtl += "map_Kd " + m.texture + "\n";
        }
        writeFileAtomically(mtl_path, mtl);
        obj += "mtllib " + mtl_path.filename().string() + "\n";
    }
    obj.reserve(mesh.positions.size() * 40 + mesh.uvs.size() * 24 + mesh.triangles.size() * 36);
    for (const Vec3f& p : mesh.positions) appendf(obj, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    for (const auto& uv : mesh.uvs) appendf(obj, "vt %.9g %.9g\n", uv.x(), uv.y());
    std::uint32_t current = static_cast<std::uint32_t>(-1);
    char buffer[128];
    for (const ObjMesh::Triangle& tri : mesh.triangles) {
        if (!mesh.materials.empty() && tri.material != current) {
            current = tri.material;
            obj += "usemtl " + mesh.materials[current].name + "\n";
        }
        if (has_uvs) {
            std::snprintf(buffer, sizeof(buffer), "f %u/%u %u/%u %u/%u\n", tri.v[0] + 1,
                          tri.vt[0] + 1, tri.v[1] + 1, tri.vt[1] + 1, tri.v[2] + 1, tri.vt[2] + 1);
        } else {
            std::snprintf(buffer, sizeof(buffer), "f %u %u %u\n", tri.v[0] + 1, tri.v[1] + 1,
                          tri.v[2] + 1);
        }
        obj += buffer;
    }
    writeFileAtomically(path, obj);
}

ObjMesh readObj(const std::filesystem::path& path) {
    ObjMesh mesh;
    std::map<std::string, std::uint32_t> material_index;
    std::uint32_t current = 0;
    std::vector<double> v;
    detail::forEachLine(path, [&](const detail::TextLine& line) {
        const std::vector<std::string>& tok = line.tokens;
        if (tok.empty() || tok[0][0] == '#') return;
        const auto fail = [&](const std::string& why) {
            return IoError(detail::lineMessage(path, line, why));
        };
        if (tok[0] == "v") {
            if (!detail::parseDoubles(tok, 1, v) || v.size() < 3) throw fail("'v' needs x y z");
            mesh.positions.emplace_back(static_cast<float>(v[0]), static_cast<float>(v[1]),
                                        static_cast<float>(v[2]));
        } else if (tok[0] == "vt") {
            if (!detail::parseDoubles(tok, 1, v) || v.size() < 2) throw fail("'vt' needs u v");
            mesh.uvs.emplace_back(static_cast<float>(v[0]), static_cast<float>(v[1]));
        } else if (tok[0] == "f") {
            parseFace(path, line, current, mesh);
        } else if (tok[0] == "mtllib") {
            if (tok.size() < 2) throw fail("'mtllib' needs a file name");
            for (ObjMaterial& m : readMtl(path.parent_path() / tok[1])) {
                if (material_index.count(m.name) == 0) {
                    material_index[m.name] = static_cast<std::uint32_t>(mesh.materials.size());
                    mesh.materials.push_back(std::move(m));
                }
            }
        } else if (tok[0] == "usemtl") {
            if (tok.size() < 2) throw fail("'usemtl' needs a material name");
            if (material_index.count(tok[1]) == 0) {
                // A material the .mtl does not define: keep it, with default colour.
                material_index[tok[1]] = static_cast<std::uint32_t>(mesh.materials.size());
                mesh.materials.push_back(ObjMaterial{tok[1], {0.8f, 0.8f, 0.8f}, ""});
            }
            current = material_index[tok[1]];
        }
    });
    return mesh;
}

}  // namespace vdbmap
