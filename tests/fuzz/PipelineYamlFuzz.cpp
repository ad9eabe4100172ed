// SPDX-License-Identifier: Apache-2.0
// The YAML pipeline loader with `--set` overrides: the input is "<yaml>" followed by
// "\n#--SET--\n<path=value>" parts, one per override. Only built-in stages exist here (no
// plugin path), so a fuzzed `plugins:` list can only fail to load.
#include <cstdlib>

#include "FuzzSupport.h"
#include "vdbmap/pipeline/Pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    static const bool env = [] {
        ::setenv("VDBMAP_PLUGIN_PATH", fuzz::scratchDir().c_str(), 1);
        return true;
    }();
    (void)env;
    const auto parts = fuzz::splitInput(fuzz::asText(data, size), "\n#--SET--\n");
    std::vector<std::string> overrides;
    for (std::size_t i = 1; i < parts.size(); ++i) overrides.emplace_back(parts[i]);
    fuzz::refusesOnlyWithTypedErrors([&] {
        Pipeline::fromString(std::string(parts[0]), "fuzz.yaml", fuzz::scratchDir(), overrides);
    });
    return 0;
}
