// SPDX-License-Identifier: Apache-2.0
#pragma once

#include "vdbmap/map/AtsdfIntegrator.h"

namespace vdbmap {
class Stage;
class StageRegistry;
namespace detail {

/// What an initialized integrate.atsdf stage integrates with: its voxel size and the
/// integrator settings from its options, as given (voxel counts; makeVoxelMap and
/// AtsdfIntegrator resolve them). The Python module's Map uses the stage's options and
/// defaults this way.
struct AtsdfStageSettings {
    double voxel_size_m = 0.0;
    AtsdfConfig config;
};
/// Throws InvalidInput if `stage` is not an integrate.atsdf stage.
AtsdfStageSettings atsdfStageSettings(const Stage& stage);

/// Registers the built-in map stages (integrate.atsdf, mesh.marching_cubes, ...).
void registerTsdfStages(StageRegistry& registry);
}  // namespace detail
}  // namespace vdbmap
