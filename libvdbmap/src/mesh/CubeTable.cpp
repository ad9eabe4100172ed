// SPDX-License-Identifier: Apache-2.0
#include "mesh/CubeTable.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vdbmap::detail {
namespace {

Eigen::Vector3d cornerPos(int c) { return Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1); }

/// Builds the table face by face: the iso-contour crosses each cube face in 0, 1 or 2
/// segments; ambiguous faces (4 crossings) cut off their inside corners, a rule that depends
/// on the face alone, so two cubes sharing a face agree and the mesh is watertight. Each
/// segment is oriented so that its inside is on a fixed side (seen from outside the cube),
/// the segments chain into closed loops, and each loop is triangulated as a fan.
CubeTable buildTable() {
    CubeTable t;
    int edge_of[8][8];
    for (auto& row : edge_of)
        for (int& e : row) e = -1;
    int e = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (int c = 0; c < 8; ++c) {
            if (c & (1 << axis)) continue;
            t.edge_corner[static_cast<std::size_t>(e)] = static_cast<std::uint8_t>(c);
            t.edge_axis[static_cast<std::size_t>(e)] = static_cast<std::uint8_t>(axis);
            edge_of[c][c | (1 << axis)] = edge_of[c | (1 << axis)][c] = e;
            ++e;
        }
    auto edgeMid = [&](int edge) -> Eigen::Vector3d {
        const int c = t.edge_corner[static_cast<std::size_t>(edge)];
        return cornerPos(c) + 0.5 * Eigen::Vector3d::Unit(t.edge_axis[static_cast<std::size_t>(edge)]);
    };
    for (int mask = 1; mask < 255; ++mask) {
        auto inside = [&](int c) { return ((mask >> c) & 1) != 0; };
        std::array<int, 12> next;
        next.fill(-1);
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                const int base = side << axis;
                const int ring[4] = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
                const Eigen::Vector3d normal = (side ? 1.0 : -1.0) * Eigen::Vector3d::Unit(axis);
                int crossing[4];
                int n_cross = 0;
                for (int i = 0; i < 4; ++i) {
                    const int a = ring[i], b = ring[(i + 1) % 4];
                    crossing[i] = inside(a) != inside(b) ? edge_of[a][b] : -1;
                    if (crossing[i] >= 0) ++n_cross;
                }
                auto addSegment = [&](int ea, int eb, int inside_corner) {
                    const Eigen::Vector3d A = edgeMid(ea), B = edgeMid(eb);
                    const Eigen::Vector3d M = 0.5 * (A + B);
                    if ((B - A).cross(normal).dot(cornerPos(inside_corner) - M) < 0.0) std::swap(ea, eb);
                    next[static_cast<std::size_t>(ea)] = eb;
                };
                if (n_cross == 2) {
                    int ea = -1, eb = -1, inside_corner = -1;
                    for (int i = 0; i < 4; ++i)
                        if (crossing[i] >= 0) {
                            (ea < 0 ? ea : eb) = crossing[i];
                            if (ea == crossing[i])
                                inside_corner = inside(ring[i]) ? ring[i] : ring[(i + 1) % 4];
                        }
                    addSegment(ea, eb, inside_corner);
                } else if (n_cross == 4) {
                    for (int i = 0; i < 4; ++i)
                        if (inside(ring[i])) addSegment(crossing[(i + 3) % 4], crossing[i], ring[i]);
                }
            }
        // Chain the segments into loops and fan-triangulate them.
        std::array<bool, 12> used{};
        for (int start = 0; start < 12; ++start) {
            if (next[static_cast<std::size_t>(start)] < 0 || used[static_cast<std::size_t>(start)]) continue;
            std::vector<int> loop;
            int cur = start;
            while (cur >= 0 && !used[static_cast<std::size_t>(cur)]) {
                used[static_cast<std::size_t>(cur)] = true;
                loop.push_back(cur);
                cur = next[static_cast<std::size_t>(cur)];
            }
            for (std::size_t k = 1; k + 1 < loop.size(); ++k)
                t.triangles[static_cast<std::size_t>(mask)].push_back(
                    {static_cast<std::uint8_t>(loop[0]), static_cast<std::uint8_t>(loop[k]),
                     static_cast<std::uint8_t>(loop[k + 1])});
        }
    }
    return t;
}

}  // namespace

const CubeTable& cubeTable() {
    static const CubeTable table = buildTable();
    return table;
}

}  // namespace vdbmap::detail
