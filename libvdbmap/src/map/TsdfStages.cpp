// SPDX-License-Identifier: Apache-2.0
#include "map/TsdfStages.h"

#include "vdbmap/pipeline/StageRegistry.h"

namespace vdbmap::detail {

void registerTsdfStages(StageRegistry& registry) { (void)registry; }

}  // namespace vdbmap::detail
