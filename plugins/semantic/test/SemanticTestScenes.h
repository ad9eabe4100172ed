// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cmath>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/mesh/TriMesh.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::semantic::test {

/// Square grid of quads (two triangles each) in the plane z = height, normals +z, covering
/// [-half, half]^2 with `cell_m` cells; faces are added row by row (y), then x.
inline void addGrid(TriMesh& mesh, double half_size_m, double cell_m, double height) {
    const int n = static_cast<int>(std::lround(2.0 * half_size_m / cell_m));
    std::vector<TriMesh::VertexHandle> v;
    for (int y = 0; y <= n; ++y) {
        for (int x = 0; x <= n; ++x) {
            v.push_back(mesh.add_vertex(TriMesh::Point(float(-half_size_m + x * cell_m),
                                                       float(-half_size_m + y * cell_m),
                                                       float(height))));
        }
    }
    auto at = [&](int x, int y) { return v[static_cast<std::size_t>(y * (n + 1) + x)]; };
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            mesh.add_face(at(x, y), at(x + 1, y), at(x + 1, y + 1));
            mesh.add_face(at(x, y), at(x + 1, y + 1), at(x, y + 1));
        }
    }
}

/// A 640 x 480 camera, f = 500 px, at `centre_W` looking at `target_W`.
inline View lookAtView(const Vec3d& centre_W, const Vec3d& target_W) {
    View view;
    view.intrinsics.width = 640;
    view.intrinsics.height = 480;
    view.intrinsics.fx = view.intrinsics.fy = 500.0;
    view.intrinsics.cx = 319.5;
    view.intrinsics.cy = 239.5;
    const Vec3d z = (target_W - centre_W).normalized();
    Vec3d x = z.cross(Vec3d::UnitZ());
    if (x.norm() < 1e-6) x = Vec3d::UnitX();
    x.normalize();
    const Vec3d y = z.cross(x);
    Isometry3d T_W_C = Isometry3d::Identity();
    T_W_C.linear().col(0) = x;
    T_W_C.linear().col(1) = y;
    T_W_C.linear().col(2) = z;
    T_W_C.translation() = centre_W;
    view.T_C_W = T_W_C.inverse();
    return view;
}

inline Vec3f faceCentroid(const TriMesh& mesh, std::size_t f) {
    Vec3f c = Vec3f::Zero();
    for (const auto vh : mesh.fv_range(TriMesh::FaceHandle(static_cast<int>(f)))) {
        const auto& p = mesh.point(vh);
        c += Vec3f(p[0], p[1], p[2]) / 3.0f;
    }
    return c;
}

}  // namespace vdbmap::semantic::test
