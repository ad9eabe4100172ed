// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "SemanticFusion.h"

namespace vdbmap {
class Context;
}

namespace vdbmap::semantic {

/// What fillFromWiderTile did.
struct TileFillWidening {
    std::size_t regions = 0;           ///< cut unlabelled regions found
    std::size_t faces_relabelled = 0;  ///< of their faces, labelled from the wider tile
    double seconds = 0.0;
};

/// The fill of a tile's unobserved faces (issue 13). The MRF fills an unobserved region from
/// the observed faces around it; in a tile, a region whose observed border lies beyond the
/// halo has none and stays unlabelled although the untiled run labels it (e.g. the road
/// behind the start of a drive, which a forward camera never sees). Such regions (connected
/// faces without a label, holding a core face and a face with a mesh-boundary edge on the
/// outer edge of the tile's mesh region, where the surface goes on) are labelled from the tile
/// grown by its occluder margin: a context below ctx whose mesh is ctx.occluderMesh() (faces
/// outside the core marked halo) and whose views are those of the grown box; `label(wide)`
/// runs the sources and the MRF there and returns its face labels (empty: nothing labelled).
/// Faces are matched by their corners (both meshes come from the same marching cubes). Only
/// the cut regions' faces change: `result` (labels, counts) is updated, `sources` stays (they
/// are filled faces). No-op when ctx is not a tile, no region is cut, or the occluder margin
/// is not wider than the halo.
TileFillWidening fillFromWiderTile(
    Context& ctx, FusionResult& result,
    const std::function<std::vector<std::uint8_t>(Context&)>& label);

}  // namespace vdbmap::semantic
