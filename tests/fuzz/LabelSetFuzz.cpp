// SPDX-License-Identifier: Apache-2.0
// The label set file (class ids, names, colours).
#include "FuzzSupport.h"
#include "vdbmap/io/LabelSet.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    const auto path = fuzz::writeInput("labels.txt", fuzz::asText(data, size));
    fuzz::refusesOnlyWithTypedErrors([&] { LabelSet::fromFile(path); });
    return 0;
}
