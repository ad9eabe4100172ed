// SPDX-License-Identifier: Apache-2.0
// Compiled against CGAL's GPL-3.0-or-later Surface_mesh_simplification; see README.md.
#include "MeshSimplify.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_distance_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_ratio_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>

#include <cmath>
#include <string>
#include <vector>

#include "vdbmap/Error.h"

namespace vdbmap::cgal {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace SMS = CGAL::Surface_mesh_simplification;

}  // namespace

SimplifyResult simplifyMesh(TriMesh& mesh, const SimplifyOptions& options) {
    if (!(options.target_ratio > 0.0 && options.target_ratio <= 1.0)) {
        throw InvalidInput("mesh.simplify: target_ratio must be in (0, 1], got " +
                           std::to_string(options.target_ratio));
    }
    if (!(options.max_error_m > 0.0) || !std::isfinite(options.max_error_m)) {
        throw InvalidInput("mesh.simplify: max_error_m must be > 0, got " +
                           std::to_string(options.max_error_m));
    }
    SimplifyResult result;
    result.faces_in = mesh.n_faces();
    if (mesh.n_faces() == 0) return result;

    SurfaceMesh sm;
    std::vector<SurfaceMesh::Vertex_index> vmap(mesh.n_vertices());
    for (const auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        vmap[vh.idx()] = sm.add_vertex(Point(p[0], p[1], p[2]));
    }
    for (const auto fh : mesh.faces()) {
        std::vector<SurfaceMesh::Vertex_index> corners;
        for (const auto vh : mesh.fv_range(fh)) corners.push_back(vmap[vh.idx()]);
        if (sm.add_face(corners) == SurfaceMesh::null_face()) ++result.faces_skipped;
    }

    // Garland & Heckbert (1997) plane quadrics decide the order and the position of each
    // collapse; Bounded_distance_placement rejects collapses that would leave the input's
    // max_error_m tube (CGAL builds an AABB tree of the input for that test).
    using GH = SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel>;
    GH gh(sm);
    SMS::Bounded_distance_placement<GH::Get_placement, Kernel> placement(options.max_error_m,
                                                                 gh.get_placement());
    SMS::Count_ratio_stop_predicate<SurfaceMesh> stop(options.target_ratio);
    result.collapsed_edges = static_cast<std::size_t>(SMS::edge_collapse(
        sm, stop, CGAL::parameters::get_cost(gh.get_cost()).get_placement(placement)));
    sm.collect_garbage();

    TriMesh out;
    std::vector<TriMesh::VertexHandle> back(sm.number_of_vertices());
    for (const auto v : sm.vertices()) {
        const Point& p = sm.point(v);
        back[v.idx()] = out.add_vertex(TriMesh::Point(static_cast<float>(p.x()),
                                                      static_cast<float>(p.y()),
                                                      static_cast<float>(p.z())));
    }
    for (const auto f : sm.faces()) {
        std::vector<TriMesh::VertexHandle> corners;
        for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
            corners.push_back(back[v.idx()]);
        }
        out.add_face(corners);
    }
    out.update_face_normals();
    out.update_vertex_normals();
    result.faces_out = out.n_faces();
    mesh = std::move(out);
    return result;
}

}  // namespace vdbmap::cgal
