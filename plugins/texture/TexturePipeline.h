// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "ExposureGains.h"
#include "PhotoConsistency.h"
#include "SeamLeveling.h"
#include "TextureTypes.h"
#include "Vignetting.h"
#include "vdbmap/render/Visibility.h"

namespace vdbmap::texture {

/// Everything the texturing of paper Sec. 5 can be told; each of the four steps can be off.
struct TextureOptions {
    bool use_mrf = true;               ///< view selection MRF; false = per-face best view
    double lambda = 1.0;               ///< Potts weight of the MRF
    std::size_t max_candidates = 0;    ///< views per face kept for the MRF (highest E_Q), 0 = all
    bool vignetting = false;           ///< correct vignetting with `vignetting_params`
    bool estimate_vignetting = false;  ///< estimate the parameters instead (needs vignetting)
    std::vector<VignettingParams> vignetting_params;  ///< per camera index (View::camera)
    /// Estimate one exposure gain per image from the overlaps (ExposureGains.h) and texture
    /// from the corrected images; the view selection and photo-consistency compare corrected
    /// colours.
    bool exposure_gains = true;
    ExposureOptions exposure;
    bool photo_consistency = true;
    PhotoConsistencyOptions photo;
    bool global_adjustment = true;
    SeamLevelingOptions leveling;
    int padding_px = 2;
    int atlas_max_size_px = 8192;
    /// Faces no view saw take the colour of the nearest textured face (true) or fill_bgr.
    bool fill_from_neighbours = true;
    /// With fill_from_neighbours: diffuse the colours from the textured border over the face
    /// graph (harmonic fill, SmoothFill.h) instead of copying the nearest textured face's.
    bool smooth_fill = true;
    std::array<std::uint8_t, 3> fill_bgr{128, 128, 128};  ///< colour when no neighbour has one
    bool quiet = true;                                    ///< no progress bars
};

/// Counts, energies, timings (s) and peak memory (bytes, process high-water mark after the
/// step) of one texturing run.
struct TextureStats {
    std::size_t faces = 0, views = 0, observations = 0;
    std::size_t faces_untextured = 0;
    std::size_t photo_rejected = 0;
    std::size_t patches = 0, charts = 0, pages = 0, seam_edges = 0;
    double energy_initial = 0, energy_final = 0;
    int mrf_sweeps = 0;
    SeamLevelingResult leveling_summary;                   ///< corner corrections cleared after use
    std::vector<VignettingEstimate> vignetting_estimates;  ///< per camera, if estimated
    std::vector<VignettingParams> vignetting_used;         ///< per camera
    std::vector<double> exposure_gains;                    ///< per view, if estimated
    std::size_t exposure_faces = 0;                        ///< faces the gains came from
    std::size_t exposure_views_without_overlap = 0;        ///< views kept at gain 1
    std::vector<std::pair<std::string, double>> timings_s;
    std::vector<std::pair<std::string, std::size_t>> peak_memory_bytes;
};

/// The textured mesh: atlas pages and a UV triangle + page per face.
struct TextureResult {
    std::vector<cv::Mat> pages;                            ///< CV_8UC3 BGR
    std::vector<std::array<Eigen::Vector2f, 3>> face_uvs;  ///< OBJ convention
    std::vector<std::uint32_t> face_page;
    std::vector<std::uint32_t> face_view;  ///< chosen view, kNoLabel = fill
    TextureStats stats;
};

/// Textures a mesh from the views that see it (paper Sec. 5): optional vignetting estimation
/// and correction, exposure gains per image (before view selection), data term E_Q and mean colours in one streaming pass over the images,
/// photo-consistency check, view-selection MRF, patches and atlas layout, a second pass over
/// the chosen views that cuts the charts and samples the seams, global colour adjustment, UVs.
/// Images are loaded one per task and never kept (memory: one image per thread + the atlas).
/// Faces no view saw get a colour diffused from the textured faces (smooth_fill), or that of the
/// nearest textured face (or fill_bgr) from a palette
/// block in the atlas, and are counted. Throws InvalidInput
/// on inconsistent inputs and whatever `load` throws.
TextureResult textureMesh(const MeshArrays& mesh, const std::vector<View>& views,
                          const Visibility& vis,
                          const std::vector<std::array<std::uint32_t, 2>>& adjacency,
                          const ImageLoader& load, const TextureOptions& options);

}  // namespace vdbmap::texture
