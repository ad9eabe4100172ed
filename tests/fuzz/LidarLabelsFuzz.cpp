// SPDX-License-Identifier: Apache-2.0
// SemanticKITTI .label files (readLidarLabels) and label map files (LabelMap::fromFile), and
// the mapping of one through the other: the input is "<.label bytes>\n#--MAP--\n<map text>";
// without the separator the built-in SemanticKITTI map is used.
#include "FuzzSupport.h"
#include "vdbmap/io/LidarLabels.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto parts = fuzz::splitInput(fuzz::asText(data, size), "\n#--MAP--\n");
    const auto labels_path = fuzz::writeInput("scan.label", parts[0]);
    const auto map_path = fuzz::writeInput("map.txt", parts.size() > 1 ? parts[1] : "");
    fuzz::refusesOnlyWithTypedErrors([&] {
        const LidarLabels labels = readLidarLabels(labels_path);
        if (labels.size() * 4 != parts[0].size()) std::abort();  // every entry, no more
        const LabelMap map = parts.size() > 1 ? LabelMap::fromFile(map_path) : LabelMap::semanticKitti();
        const std::vector<std::uint8_t> ids = mapLidarLabels(labels, labels_path, map);
        if (ids.size() != labels.size()) std::abort();
        for (std::size_t i = 0; i < ids.size(); ++i) {  // the map's own target, or a throw
            const std::uint16_t cls = LidarLabels::classOf(labels.raw[i]);
            if (!map.contains(cls) || ids[i] != map(cls)) std::abort();
        }
    });
    return 0;
}
