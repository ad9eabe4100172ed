// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "SemanticVotes.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/mrf/PottsMrf.h"

namespace vdbmap::semantic {

/// Settings of the semantic MRF (paper Sec. 6).
struct FusionOptions {
    double lambda = 0.5;               ///< weight of the Potts term; 0 = naive per-face argmax
    double probability_floor = 1e-3;   ///< cost = -log(max(p, floor))
    /// Observed faces may take every class (unvoted ones at the floor cost) instead of only
    /// the classes they were voted for. Slower; the floor cost makes such a switch rare.
    bool all_classes = false;
    int max_sweeps = 5;
    /// Per-edge Potts weights w_ij (same order as the adjacency; geometricEdgeWeights), or
    /// null for the paper's uniform weights (all 1).
    const std::vector<float>* edge_weights = nullptr;
};

/// The MRF of paper Eq. (semantic_mrf_energy_function): one node per face; an observed face
/// has the candidates it was voted for with cost -log(max(p_c, floor)), p_c = the normalised
/// accumulated votes; a face without votes has the uniform cost -log(1/N) for every class, so
/// the Potts term over `adjacency` (face pairs, faceAdjacency) decides. Only the classes voted
/// on the border of its region of unobserved faces are listed for it: the Potts optimum
/// inside a region without data uses no other class, and this keeps the moves small.
/// Labels are class indices.
MrfProblem fusionProblem(const FaceVotes& votes,
                         const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                         const FusionOptions& options);

/// Face labels (class ids of `labels`, 255 = unknown) and what it took.
struct FusionResult {
    std::vector<std::uint8_t> face_labels;
    std::size_t observed_faces = 0;
    std::size_t filled_faces = 0;            ///< unobserved faces given a class by smoothness
    std::size_t unlabelled_faces = 0;        ///< written as 255
    std::size_t unlabelled_components = 0;   ///< connected components without any observed face
    /// Per face: the posterior margin of its label under the data term,
    /// max(0, p(l_i) - max_{c != l_i} p(c)) with p the normalised votes; 0 for a face without
    /// votes (filled or unknown). 1 = every vote agreed with the label.
    std::vector<float> confidence;
    double initial_energy = 0;
    double final_energy = 0;
    int sweeps = 0;
};

/// Solves the MRF with alpha-expansion (vdbmap/mrf/PottsMrf.h). Faces of a connected component
/// (over `adjacency`) with no observed face are written as 255 and counted. With lambda = 0
/// every observed face gets its per-face argmax class (ties: the smaller class index) and an
/// unobserved face 255, which is naive voting. Throws InvalidInput if `adjacency` refers to a
/// face out of range or the votes do not match `labels`.
FusionResult fuseLabels(const FaceVotes& votes,
                        const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                        const LabelSet& labels, const FusionOptions& options);

}  // namespace vdbmap::semantic
