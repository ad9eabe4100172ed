// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "GeometricSmoothness.h"
#include "SemanticFusion.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/Layers.h"
#include "vdbmap/mesh/MeshAdjacency.h"

using namespace vdbmap;
using namespace vdbmap::semantic;

namespace {

// Two planes meeting at a right angle along y = kRows * s: the ground (z = 0, rows 0..kRows-1
// of squares) and a wall (y = kRows * s, rows kRows..2 kRows-1 going up). One vertex grid, so
// the crease vertices are shared and faceAdjacency links the planes.
constexpr int kCols = 24, kRows = 12;
constexpr float kCell = 0.1f;

struct TwoPlanes {
    TriMesh mesh;
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<int> row;  // square row of each face: < kRows ground, >= kRows wall
    std::vector<int> col;
};

TwoPlanes twoPlanes() {
    TwoPlanes s;
    std::vector<TriMesh::VertexHandle> vh;
    for (int y = 0; y <= 2 * kRows; ++y) {
        for (int x = 0; x <= kCols; ++x) {
            const Vec3f p = y <= kRows ? Vec3f(x * kCell, y * kCell, 0.0f)
                                       : Vec3f(x * kCell, kRows * kCell, (y - kRows) * kCell);
            s.vertices.push_back(p);
            vh.push_back(s.mesh.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
        }
    }
    const auto at = [&](int x, int y) { return static_cast<std::uint32_t>(y * (kCols + 1) + x); };
    for (int y = 0; y < 2 * kRows; ++y) {
        for (int x = 0; x < kCols; ++x) {
            for (const auto& t : {std::array<std::uint32_t, 3>{at(x, y), at(x + 1, y), at(x + 1, y + 1)},
                                  std::array<std::uint32_t, 3>{at(x, y), at(x + 1, y + 1), at(x, y + 1)}}) {
                s.mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]);
                s.triangles.push_back(t);
                s.row.push_back(y);
                s.col.push_back(x);
            }
        }
    }
    return s;
}

// Votes: `ground` on every ground face; `wall` on the faces of the wall's top row whose
// column is in [first_col, last_col]; nothing elsewhere.
FaceVotes planeVotes(const TwoPlanes& s, std::uint32_t ground, std::uint32_t wall, int first_col,
                     int last_col, std::size_t classes) {
    FaceVotes v;
    v.num_classes = classes;
    v.offsets.push_back(0);
    for (std::size_t f = 0; f < s.row.size(); ++f) {
        if (s.row[f] < kRows) {
            v.classes.push_back(ground);
            v.weights.push_back(1.0f);
        } else if (s.row[f] == 2 * kRows - 1 && s.col[f] >= first_col && s.col[f] <= last_col) {
            v.classes.push_back(wall);
            v.weights.push_back(1.0f);
        }
        v.offsets.push_back(v.classes.size());
    }
    return v;
}

}  // namespace

TEST_CASE("geometric edge weights: 1 on a plane, falling across the crease", "[semantic][fill]") {
    const TwoPlanes s = twoPlanes();
    const auto adjacency = faceAdjacency(s.mesh);
    GeometricSmoothnessOptions o;  // 20 deg, 0.03 m, floor 0.01
    const auto w = geometricEdgeWeights(s.vertices, s.triangles, adjacency, Vec3f::UnitZ(), o);
    REQUIRE(w.size() == adjacency.size());
    std::size_t crease = 0;
    for (std::size_t e = 0; e < adjacency.size(); ++e) {
        const bool a_wall = s.row[adjacency[e][0]] >= kRows, b_wall = s.row[adjacency[e][1]] >= kRows;
        if (a_wall != b_wall) {
            ++crease;
            // 90 deg: exp(-(pi/2)^2 / (2 (20 deg)^2)) = 2.6e-7, floored at 0.01.
            CHECK(w[e] == Approx(0.01f));
        } else {
            // Coplanar neighbours: no angle; on the wall the height term is off (not level).
            CHECK(w[e] == Approx(1.0f));
        }
    }
    CHECK(crease == kCols);
    CHECK_THROWS_AS(geometricEdgeWeights(s.vertices, s.triangles, adjacency, Vec3f::UnitZ(),
                                         GeometricSmoothnessOptions{0.0, 0.03, 0.01}),
                    InvalidInput);
}

TEST_CASE("a height step between level faces lowers the weight as exp(-h^2 / 2 sigma^2)",
          "[semantic][fill]") {
    // Two triangles sharing the edge (0,0,0)-(0,1,0): the first level at z = 0, the second
    // tilted up to z = 0.09 at x = 1, so their centroids differ in height by 0.03 m.
    const std::vector<Vec3f> v{{0, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0.09f}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}, {0, 1, 3}};
    const std::vector<std::array<std::uint32_t, 2>> adj{{0, 1}};
    GeometricSmoothnessOptions o;
    const float w = geometricEdgeWeights(v, t, adj, Vec3f::UnitZ(), o)[0];
    const Vec3f n1 = (v[1] - v[0]).cross(v[3] - v[0]).normalized();
    // Both normals point down (the winding of the triangles); the first is (0, 0, -1).
    REQUIRE(n1.z() < 0.0f);
    const double theta = std::acos(std::clamp<double>(-n1.z(), -1.0, 1.0));
    const double h = 0.03 * std::abs(n1.z());  // centroid heights 0 and 0.03
    const double sn = 20.0 * M_PI / 180.0;
    CHECK(w == Approx(std::exp(-theta * theta / (2 * sn * sn) - h * h / (2 * 0.03 * 0.03))));
}

TEST_CASE("fill on two planes, only the ground seen: the wall is filled, nothing unlabelled",
          "[semantic][fill]") {
    const TwoPlanes s = twoPlanes();
    const auto adjacency = faceAdjacency(s.mesh);
    const LabelSet labels = LabelSet::defaults();
    const FaceVotes votes = planeVotes(s, 0, 0, 1, 0, labels.size());  // ground road, wall unseen
    for (const bool geometric : {false, true}) {
        const auto w = geometricEdgeWeights(s.vertices, s.triangles, adjacency, Vec3f::UnitZ(), {});
        FusionOptions o;
        if (geometric) o.edge_weights = &w;
        const FusionResult r = fuseLabels(votes, adjacency, labels, o);
        CHECK(r.unlabelled_faces == 0);
        CHECK(r.observed_faces == s.row.size() / 2);
        CHECK(r.filled_faces == s.row.size() / 2);
        for (std::size_t f = 0; f < s.row.size(); ++f) {
            REQUIRE(r.face_labels[f] == 0);
            // Confidence: 1 where the only votes agree, 0 where no source saw the face.
            REQUIRE(r.confidence[f] == (s.row[f] < kRows ? 1.0f : 0.0f));
        }
    }
}

TEST_CASE("fill on two planes: the geometric weights stop the ground class at the crease",
          "[semantic][fill]") {
    // Ground: road (0). Wall: unseen but for a building (2) strip of 8 faces' columns on its
    // top row. The paper's uniform Potts fill cuts around the short strip (8 + 2 edges) rather
    // than along the crease (24 edges), so road climbs the wall; with the geometric weights
    // the crease costs 24 x 0.01 and the wall becomes building.
    const TwoPlanes s = twoPlanes();
    const auto adjacency = faceAdjacency(s.mesh);
    const LabelSet labels = LabelSet::defaults();
    const FaceVotes votes = planeVotes(s, 0, 2, 8, 15, labels.size());
    auto w = geometricEdgeWeights(s.vertices, s.triangles, adjacency, Vec3f::UnitZ(), {});
    // As the stage does: uniform between observed faces; the crease touches the unseen wall.
    uniformBetweenObserved(w, adjacency, votes);
    for (std::size_t e = 0; e < adjacency.size(); ++e) {
        const bool a_wall = s.row[adjacency[e][0]] >= kRows, b_wall = s.row[adjacency[e][1]] >= kRows;
        if (a_wall != b_wall) REQUIRE(w[e] == Approx(0.01f));
    }
    CHECK_THROWS_AS(uniformBetweenObserved(w, {}, votes), InvalidInput);
    FusionOptions uniform, geometric;
    geometric.edge_weights = &w;
    const FusionResult u = fuseLabels(votes, adjacency, labels, uniform);
    const FusionResult g = fuseLabels(votes, adjacency, labels, geometric);
    std::size_t wall = 0, wall_road_u = 0, wall_building_g = 0, ground_road_g = 0;
    for (std::size_t f = 0; f < s.row.size(); ++f) {
        if (s.row[f] >= kRows) {
            ++wall;
            wall_road_u += u.face_labels[f] == 0;
            wall_building_g += g.face_labels[f] == 2;
        } else {
            ground_road_g += g.face_labels[f] == 0;
        }
    }
    CHECK(wall_road_u > wall / 2);       // the uniform fill spreads road up the wall
    CHECK(wall_building_g == wall);      // the geometric fill: the whole wall is building
    CHECK(ground_road_g == s.row.size() - wall);
    CHECK(g.unlabelled_faces == 0);
    CHECK(u.unlabelled_faces == 0);
    CHECK_THROWS_AS(fuseLabels(votes, adjacency, labels,
                               [] {
                                   static const std::vector<float> bad(3, 1.0f);
                                   FusionOptions o;
                                   o.edge_weights = &bad;
                                   return o;
                               }()),
                    InvalidInput);
}
