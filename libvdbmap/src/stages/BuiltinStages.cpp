// SPDX-License-Identifier: Apache-2.0
// The built-in stages sit above map/, mesh/ and pipeline/: they adapt the algorithms to the
// Stage interface and register themselves here, so that pipeline/ never includes stages/.
#include "vdbmap/map/VdbTrees.h"

#include <mutex>

#include "stages/TsdfStages.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace vdbmap {

void registerBuiltinStages() {
    // One-time set-up of the library: the OpenVDB type registry lives in this shared library,
    // so plugins and apps never call openvdb::initialize() themselves.
    static std::once_flag once;
    std::call_once(once, [] {
        openvdb::initialize();
        detail::registerTsdfStages(StageRegistry::instance());
    });
}

}  // namespace vdbmap
