// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "SemanticVotes.h"
#include "vdbmap/core/Types.h"
#include "vdbmap/io/LabelSet.h"
#include "vdbmap/mesh/TriMesh.h"
#include "vdbmap/render/ScanOcclusion.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap {
class Context;
class Dataset;
}  // namespace vdbmap

namespace vdbmap::semantic {

/// The phases of `semantic.mrf` that gather the sources of the labels (paper Sec. 6): the
/// label set, the votes of the semantic images and the votes of the labelled LiDAR points.
/// Each throws Error "<stage>: ..." (exit 1) on bad data.

/// Throws Error "<stage>: <message>".
[[noreturn]] void failIn(const std::string& stage, const std::string& message);

/// A file option: as given if it exists, else relative to the dataset folder.
std::filesystem::path resolveFile(const std::string& file, const Dataset& dataset);

/// The mesh as arrays (vdbmap::meshArrays, every face slot kept so triangle i is face i) plus
/// the area of each triangle.
struct FaceArrays {
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<double> area_m2;
};
FaceArrays faceArrays(const TriMesh& mesh);

/// The label set: the stage's `labels_file`, else the dataset's, else docs/DATA.md's default.
/// Every id of `export_classes` must be in it.
LabelSet loadLabelSet(const std::string& stage, const std::string& labels_file,
                      const Dataset& dataset, const std::vector<int>& export_classes);

/// What the image phase produced.
struct ImageVotes {
    FaceVotes votes;
    std::size_t views = 0;
    std::size_t observations = 0;
    std::size_t scan_hidden = 0;  ///< observations the nearest-in-time scan hid (not voted)
    bool visibility_reused = false;  ///< taken from an earlier stage (Context::takeVisibility)
    std::size_t masked = 0;          ///< observations on masked pixels (image_masks)
    double visibility_s = 0, votes_s = 0;
};

/// Image votes: visibility of ctx.mesh() in ctx.views() (a tile's views in a tiled run; the
/// tile's occluder mesh hides faces), then area-weighted centre-pixel votes (paper Eq. 4),
/// `image_chunk` images in memory at once. With `scan` (non-null), a view does not vote for a
/// face that the LiDAR scan nearest in time to its image hides (removeScanOccluded). A semantic
/// image of another size than its camera is an error naming the file and both sizes. With
/// `image_masks` (a folder, directoryViewMasks), a view does not vote for a face that touches
/// its mask (removeMaskedObservations, `masks_dilate_px`).
ImageVotes imageVotes(const std::string& stage, Context& ctx, const VisibilityOptions& options,
                      const LabelSet& labels, int image_chunk,
                      const ScanOcclusionOptions* scan = nullptr,
                      const std::string& image_masks = "", int masks_dilate_px = 2);

/// What the LiDAR phase produced.
struct LidarVoteResult {
    FaceVotes votes;
    std::size_t scans = 0;
    std::size_t scans_without_labels = 0;
    std::size_t scans_out_of_reach = 0;  ///< tiled runs: scans that cannot reach the tile
    std::size_t points = 0;
    std::size_t points_dropped = 0;     ///< non-finite or outside the range limits
    std::size_t points_void = 0;        ///< mapped to 255
    std::size_t points_unknown_id = 0;  ///< mapped to an id outside the label set
    std::size_t points_without_face = 0;
    double seconds = 0;
};

/// LiDAR votes: each labelled scan is read as stored (the labels are per stored point),
/// checked against its label file, filtered as Dataset::loadScan filters, moved into the world
/// and splatted onto the faces within `radius_m` (LidarVoteAccumulator). In a tiled run only
/// the scans whose sensor lies within the dataset's max_range_m of the tile's halo box grown
/// by `radius_m` are read, and only their points inside that box vote: the others cannot
/// reach a face of the tile, so every tile gets the same votes whichever process runs it.
LidarVoteResult lidarVotes(const std::string& stage, Context& ctx, const FaceArrays& faces,
                           const LabelSet& labels, const std::string& label_map,
                           double radius_m);

}  // namespace vdbmap::semantic
