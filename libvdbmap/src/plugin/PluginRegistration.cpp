// SPDX-License-Identifier: Apache-2.0
#include "plugin/PluginRegistry.h"

namespace vdbmap::detail {

void registerPluginStage(vdbmap_registry* reg, PluginStageFactory factory) {
    if (reg == nullptr) throw InvalidInput("registerPluginStage: null registry handle");
    if (factory == nullptr) throw InvalidInput("registerPluginStage: null stage factory");
    reg->factories.push_back(factory);
}

void setPluginRegistrationError(vdbmap_registry* reg, const char* message) noexcept {
    if (reg == nullptr) return;
    try {
        reg->error = message != nullptr ? message : "unknown error";
    } catch (...) {
        // Out of memory while recording the message: the loader still sees the failure code.
    }
}

}  // namespace vdbmap::detail
