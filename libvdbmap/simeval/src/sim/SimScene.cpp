// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/sim/SimScene.h"

#include <cmath>
#include <random>

#include "vdbmap/Error.h"
#include "vdbmap/io/Image.h"

namespace vdbmap {

std::uint32_t SimScene::addMaterial(const std::string& name, const cv::Mat& texture_bgr) {
    if (texture_bgr.empty() || texture_bgr.type() != CV_8UC3) {
        throw InvalidInput("SimScene::addMaterial: texture of material '" + name +
                           "' must be a non-empty 8-bit BGR image");
    }
    ObjMaterial material;
    material.name = name;
    mesh.materials.push_back(material);
    textures.push_back(texture_bgr);
    return static_cast<std::uint32_t>(mesh.materials.size() - 1);
}

void SimScene::addTriangle(const Vec3f& a, const Vec3f& b, const Vec3f& c,
                           const Eigen::Vector2f& uv_a, const Eigen::Vector2f& uv_b,
                           const Eigen::Vector2f& uv_c, std::uint32_t material,
                           std::uint8_t label) {
    const auto v0 = static_cast<std::uint32_t>(mesh.positions.size());
    const auto t0 = static_cast<std::uint32_t>(mesh.uvs.size());
    mesh.positions.insert(mesh.positions.end(), {a, b, c});
    mesh.uvs.insert(mesh.uvs.end(), {uv_a, uv_b, uv_c});
    ObjMesh::Triangle tri;
    tri.v = {v0, v0 + 1, v0 + 2};
    tri.vt = {t0, t0 + 1, t0 + 2};
    tri.material = material;
    mesh.triangles.push_back(tri);
    face_labels.push_back(label);
}

void SimScene::addQuad(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& d,
                       float tile_m, std::uint32_t material, std::uint8_t label) {
    const Vec3f e_u = b - a;
    const Vec3f e_v = d - a;
    const float len_u = e_u.norm();
    const float len_v = e_v.norm();
    auto uvOf = [&](const Vec3f& p) {
        const Vec3f r = p - a;
        return Eigen::Vector2f(len_u > 0 ? r.dot(e_u) / len_u / tile_m : 0.0f,
                               len_v > 0 ? r.dot(e_v) / len_v / tile_m : 0.0f);
    };
    addTriangle(a, b, c, uvOf(a), uvOf(b), uvOf(c), material, label);
    addTriangle(a, c, d, uvOf(a), uvOf(c), uvOf(d), material, label);
}

void SimScene::addBox(const Isometry3d& pose, const Vec3f& half_m, float tile_m,
                      std::uint32_t material, std::uint8_t label) {
    const Eigen::Isometry3f T = pose.cast<float>();
    auto corner = [&](float sx, float sy, float sz) {
        return Vec3f(T * Vec3f(sx * half_m.x(), sy * half_m.y(), sz * half_m.z()));
    };
    // Each face counter-clockwise seen from outside.
    addQuad(corner(-1, -1, 1), corner(1, -1, 1), corner(1, 1, 1), corner(-1, 1, 1), tile_m,
            material, label);  // +z
    addQuad(corner(-1, 1, -1), corner(1, 1, -1), corner(1, -1, -1), corner(-1, -1, -1), tile_m,
            material, label);  // -z
    addQuad(corner(1, -1, -1), corner(1, 1, -1), corner(1, 1, 1), corner(1, -1, 1), tile_m,
            material, label);  // +x
    addQuad(corner(-1, 1, -1), corner(-1, -1, -1), corner(-1, -1, 1), corner(-1, 1, 1), tile_m,
            material, label);  // -x
    addQuad(corner(1, 1, -1), corner(-1, 1, -1), corner(-1, 1, 1), corner(1, 1, 1), tile_m,
            material, label);  // +y
    addQuad(corner(-1, -1, -1), corner(1, -1, -1), corner(1, -1, 1), corner(-1, -1, 1), tile_m,
            material, label);  // -y
}

void SimScene::addCylinder(const Isometry3d& pose, float radius_m, float height_m, int segments,
                           float tile_m, std::uint32_t material, std::uint8_t label) {
    const float circumference = 2.0f * static_cast<float>(M_PI) * radius_m;
    const Eigen::Isometry3f T = pose.cast<float>();
    const Vec3f base = T.translation();
    const Vec3f top = T * Vec3f(0, 0, height_m);
    for (int i = 0; i < segments; ++i) {
        const float a0 = 2.0f * static_cast<float>(M_PI) * i / segments;
        const float a1 = 2.0f * static_cast<float>(M_PI) * (i + 1) / segments;
        const Vec3f r0 = T.linear() * Vec3f(radius_m * std::cos(a0), radius_m * std::sin(a0), 0.0f);
        const Vec3f r1 = T.linear() * Vec3f(radius_m * std::cos(a1), radius_m * std::sin(a1), 0.0f);
        const float u0 = circumference * i / segments / tile_m;
        const float u1 = circumference * (i + 1) / segments / tile_m;
        const float vt = height_m / tile_m;
        addTriangle(base + r0, base + r1, top + r1, {u0, 0}, {u1, 0}, {u1, vt}, material, label);
        addTriangle(base + r0, top + r1, top + r0, {u0, 0}, {u1, vt}, {u0, vt}, material, label);
        const Eigen::Vector2f c0(radius_m * std::cos(a0) / tile_m, radius_m * std::sin(a0) / tile_m);
        const Eigen::Vector2f c1(radius_m * std::cos(a1) / tile_m, radius_m * std::sin(a1) / tile_m);
        addTriangle(top, top + r0, top + r1, {0, 0}, c0, c1, material, label);
        addTriangle(base, base + r1, base + r0, {0, 0}, c1, c0, material, label);
    }
}

void SimScene::addBlob(const Vec3f& centre, float radius_m, float bumpiness, std::uint32_t seed,
                       float tile_m, std::uint32_t material, std::uint8_t label) {
    // A UV sphere whose radius is modulated by a few random low-frequency harmonics.
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> phase(0.0f, 2.0f * static_cast<float>(M_PI));
    const float p1 = phase(rng), p2 = phase(rng), p3 = phase(rng);
    const int n_lat = 12, n_lon = 24;
    auto point = [&](int i, int j) {
        const float th = static_cast<float>(M_PI) * i / n_lat;
        const float ph = 2.0f * static_cast<float>(M_PI) * j / n_lon;
        const float r = radius_m * (1.0f + bumpiness * (0.5f * std::sin(3 * ph + p1) *
                                                            std::sin(2 * th + p2) +
                                                        0.5f * std::cos(5 * ph + p3) *
                                                            std::sin(th)));
        return Vec3f(centre + r * Vec3f(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph),
                                        std::cos(th)));
    };
    const float circumference = 2.0f * static_cast<float>(M_PI) * radius_m;
    auto uv = [&](int i, int j) {
        return Eigen::Vector2f(circumference * j / n_lon / tile_m,
                               0.5f * circumference * (n_lat - i) / n_lat / tile_m);
    };
    for (int i = 0; i < n_lat; ++i) {
        for (int j = 0; j < n_lon; ++j) {
            // Outward orientation: (i,j) -> (i+1,j) -> (i+1,j+1) goes counter-clockwise seen
            // from outside for theta measured from +z.
            if (i > 0) {
                addTriangle(point(i, j), point(i + 1, j), point(i, j + 1), uv(i, j), uv(i + 1, j),
                            uv(i, j + 1), material, label);
            }
            if (i + 1 < n_lat) {
                addTriangle(point(i, j + 1), point(i + 1, j), point(i + 1, j + 1), uv(i, j + 1),
                            uv(i + 1, j), uv(i + 1, j + 1), material, label);
            }
        }
    }
}

void SimScene::append(const ObjMesh& other, const std::vector<cv::Mat>& other_textures,
                      const Isometry3d& pose, std::uint8_t label) {
    if (other_textures.size() != other.materials.size()) {
        throw InvalidInput("SimScene::append: " + std::to_string(other.materials.size()) +
                           " materials but " + std::to_string(other_textures.size()) +
                           " textures");
    }
    const auto v0 = static_cast<std::uint32_t>(mesh.positions.size());
    const auto t0 = static_cast<std::uint32_t>(mesh.uvs.size());
    const auto m0 = static_cast<std::uint32_t>(mesh.materials.size());
    const Eigen::Isometry3f T = pose.cast<float>();
    for (const auto& p : other.positions) mesh.positions.push_back(T * p);
    mesh.uvs.insert(mesh.uvs.end(), other.uvs.begin(), other.uvs.end());
    for (std::size_t m = 0; m < other.materials.size(); ++m) {
        mesh.materials.push_back(other.materials[m]);
        mesh.materials.back().texture.clear();
        textures.push_back(other_textures[m]);
    }
    const bool has_uv = !other.uvs.empty();
    for (const auto& tri : other.triangles) {
        ObjMesh::Triangle t = tri;
        for (int k = 0; k < 3; ++k) {
            t.v[k] += v0;
            t.vt[k] = has_uv ? t.vt[k] + t0 : 0;
        }
        if (!has_uv) {
            // Keep a valid UV index: one (0, 0) coordinate for meshes without UVs.
            if (mesh.uvs.size() == t0) mesh.uvs.emplace_back(0.0f, 0.0f);
            t.vt = {t0, t0, t0};
        }
        t.material = other.materials.empty() ? 0 : tri.material + m0;
        mesh.triangles.push_back(t);
        face_labels.push_back(label);
    }
}

void SimScene::transform(const Isometry3d& T_new_old) {
    const Eigen::Isometry3f T = T_new_old.cast<float>();
    for (auto& p : mesh.positions) p = T * p;
}

std::vector<std::array<std::uint32_t, 3>> SimScene::triangleIndices() const {
    std::vector<std::array<std::uint32_t, 3>> out;
    out.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) out.push_back(t.v);
    return out;
}

TriMesh SimScene::toTriMesh() const {
    TriMesh out;
    std::vector<TriMesh::VertexHandle> handles;
    handles.reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) {
        handles.push_back(out.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
    }
    // Every sim triangle has its own three vertices, so OpenMesh never rejects a face as
    // non-manifold and face index = triangle index.
    for (const auto& t : mesh.triangles) {
        out.add_face(handles[t.v[0]], handles[t.v[1]], handles[t.v[2]]);
    }
    return out;
}

void SimScene::writeTexturedObj(const std::filesystem::path& obj_path) const {
    ObjMesh out = mesh;
    const std::string stem = obj_path.stem().string();
    for (std::size_t m = 0; m < out.materials.size(); ++m) {
        const std::string png = stem + "_" + std::to_string(m) + ".png";
        out.materials[m].texture = png;
        out.materials[m].diffuse = {1.0f, 1.0f, 1.0f};
        writePng(obj_path.parent_path() / png, textures[m]);
    }
    writeObj(obj_path, out);
}

void loadTexturedObj(const std::filesystem::path& obj_path, ObjMesh& mesh,
                     std::vector<cv::Mat>& textures) {
    mesh = readObj(obj_path);
    textures.clear();
    for (const auto& material : mesh.materials) {
        if (!material.texture.empty()) {
            textures.push_back(readColorImage(obj_path.parent_path() / material.texture));
        } else {
            textures.emplace_back(1, 1, CV_8UC3,
                                  cv::Scalar(255.0 * material.diffuse[2], 255.0 * material.diffuse[1],
                                             255.0 * material.diffuse[0]));
        }
    }
    if (mesh.materials.empty()) {
        mesh.materials.push_back(ObjMaterial{});
        textures.emplace_back(1, 1, CV_8UC3, cv::Scalar(204, 204, 204));
    }
}

}  // namespace vdbmap
