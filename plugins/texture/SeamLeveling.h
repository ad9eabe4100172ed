// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "TextureTypes.h"

namespace vdbmap::texture {

/// A mesh edge between two faces of different patches: the seam that global colour
/// adjustment levels. Vertex v0 and v1 are the shared vertices.
struct SeamEdge {
    std::uint32_t face_a = 0, face_b = 0;
    std::uint32_t v0 = 0, v1 = 0;
};

/// Colours sampled along one seam edge, near each end, in the view of each side (0..255 BGR):
/// f_{v^l} and f_{v^r} of the paper's seam-levelling equation.
struct SeamSamples {
    Vec3f a_v0 = Vec3f::Zero(), a_v1 = Vec3f::Zero();  ///< in face_a's view
    Vec3f b_v0 = Vec3f::Zero(), b_v1 = Vec3f::Zero();  ///< in face_b's view
};

/// Every edge shared by two faces of different patches (both textured).
std::vector<SeamEdge> findSeamEdges(const MeshArrays& mesh,
                                    const std::vector<std::uint32_t>& face_patch,
                                    const std::vector<std::array<std::uint32_t, 2>>& adjacency);

/// The colour space the seams are levelled in.
enum class SeamSpace {
    /// Additive per-channel offsets on BGR (Lempitsky & Ivanov as published). An offset fitted
    /// on one colour and applied to another shifts its hue: a grey seam's +30 turns a dark red
    /// interior pink.
    kBgr,
    /// One additive offset per channel on log BGR, i.e. a per-channel gain: a pure exposure
    /// difference gives equal gains and keeps every hue; a white-balance difference is levelled
    /// as one.
    kLogBgr,
    /// One offset on log luminance, applied as the same gain to all three channels: hue and
    /// saturation of every pixel are those of its image, so no patch gets a cast no image
    /// shows (default).
    kLogLuminance,
};

/// Parses "bgr", "log_bgr", "log_luminance"; throws InvalidInput naming the value otherwise.
SeamSpace parseSeamSpace(const std::string& name);

/// Options of the global colour adjustment.
struct SeamLevelingOptions {
    SeamSpace space = SeamSpace::kLogLuminance;
    double smoothness = 0.1;    ///< weight of (g_i - g_j)^2 along edges inside a patch
    /// Log spaces: a seam vertex whose two sides differ by more than this in log luminance is
    /// left out of the seam term (0 = keep all). After the exposure gains, such a difference is
    /// not photometric (a misregistered edge, an object on one side only): levelling it would
    /// spread a false correction over both patches.
    double max_log_difference = 0.0;
    double regularizer = 1e-4;  ///< weight of g^2: picks the smallest correction
    int max_iterations = 2000;  ///< conjugate gradient
    double tolerance = 1e-6;    ///< conjugate gradient, relative residual
};

/// Result: a correction per face corner (0 for faces without a patch): additive in 0..255 units
/// (space kBgr) or a log gain per channel (log_gain: the pixel is multiplied by exp(g)).
struct SeamLevelingResult {
    std::vector<std::array<Vec3f, 3>> corner_correction;  ///< per face, BGR
    bool log_gain = false;                                ///< corrections are log gains
    std::size_t unknowns = 0;                             ///< (patch, vertex) pairs
    std::size_t seam_terms = 0;                           ///< seam vertex constraints
    std::size_t seam_terms_dropped = 0;                   ///< beyond max_log_difference
    int iterations = 0;                                   ///< CG iterations (max over channels)
    double max_abs_correction = 0;
};

/// Lempitsky & Ivanov's global colour adjustment (paper Eq. seam_levelling): vertices on seams
/// are split per patch, one additive correction g per (patch, vertex), and
///   sum_seam-vertices (f_l + g_l - f_r - g_r)^2 + smoothness * sum_patch-edges (g_i - g_j)^2
///   + regularizer * sum g^2
/// is minimised as sparse least squares (Eigen ConjugateGradient), one solve per channel, on
/// f = BGR, f = log BGR or f = log luminance (options.space; log of values below 1 is log 1).
/// `samples[k]` belongs to `seams[k]`. Throws InvalidInput on mismatched sizes.
SeamLevelingResult solveSeamLeveling(const MeshArrays& mesh,
                                     const std::vector<std::uint32_t>& face_patch,
                                     const std::vector<SeamEdge>& seams,
                                     const std::vector<SeamSamples>& samples,
                                     const SeamLevelingOptions& options);

}  // namespace vdbmap::texture
