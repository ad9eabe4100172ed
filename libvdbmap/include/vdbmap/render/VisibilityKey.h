// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/mesh/TriMesh.h"
#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {

/// A stage's visibility after the scan occlusion test, as one stage hands it to the next
/// (Context::keepVisibility).
struct SharedVisibility {
    Visibility visibility;
    double max_view_angle_deg = 90.0;    ///< the angle it was computed with
    std::vector<float> scan_hidden_cos;  ///< cos_angle of each observation the scan test removed
};

/// Narrows `shared` to a smaller view angle: removes the observations, and the scan-hidden
/// ones, whose cos_angle is below cos(max_view_angle_deg) (computeVisibility's own test; no
/// other test of computeVisibility or removeScanOccluded depends on the angle), keeping the
/// order. The result is what the same computation with that angle gives. Throws InvalidInput if
/// the angle is outside (0, shared.max_view_angle_deg].
void narrowViewAngle(SharedVisibility& shared, double max_view_angle_deg);

/// What a stage's visibility (meshVisibility, then removeScanOccluded) is computed from, as a
/// string that a later stage compares with its own (Context::keepVisibility, takeVisibility):
/// a 64-bit FNV-1a fingerprint of the mesh's vertices and faces and of the occluder mesh's, the
/// views (frame, camera, intrinsics, pose: their bits), the visibility options but the view
/// angle (narrowViewAngle serves a smaller one), the scan
/// occlusion options (`scan` null: no scan test) and which moving returns hid (`moving`: their
/// address, null = none). Equal keys mean equal inputs, so equal visibility (computeVisibility
/// and removeScanOccluded are deterministic); a fingerprint collision is the one way two
/// different inputs could share a key (2^-64 per pair).
std::string visibilityKey(const MeshArrays& mesh, const TriMesh& occluders,
                          const std::vector<View>& views, const VisibilityOptions& options,
                          const ScanOcclusionOptions* scan, const void* moving);

}  // namespace vdbmap
