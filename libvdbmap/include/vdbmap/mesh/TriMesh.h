// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace vdbmap {

/// OpenMesh traits of the vdbmap mesh: float positions in the world frame W (metres),
/// per-vertex normals, per-face normals and status (for deletion / garbage collection).
struct MeshTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3f;
    using Normal = OpenMesh::Vec3f;
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
    FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
    EdgeAttributes(OpenMesh::Attributes::Status);
    HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};

/// The triangle mesh shared by the stages (Context::mesh()). Named properties (e.g. the face
/// property kFaceLabelProperty) carry per-face layers.
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

}  // namespace vdbmap
