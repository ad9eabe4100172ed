// SPDX-License-Identifier: Apache-2.0
#pragma once

namespace vdbmap {
class StageRegistry;
namespace detail {
/// Registers the built-in map stages (integrate.atsdf, mesh.marching_cubes, ...).
void registerTsdfStages(StageRegistry& registry);
}  // namespace detail
}  // namespace vdbmap
