// SPDX-License-Identifier: Apache-2.0
// The LZF codec of PCD binary_compressed: arbitrary streams must be decoded or refused without
// reading or writing out of bounds, and every input must survive compress -> decompress.
#include <cstring>

#include "FuzzSupport.h"
#include "io/Lzf.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace vdbmap;
    if (size >= 2) {
        // The first two bytes are the claimed uncompressed size, the rest the stream.
        const std::size_t out_size = std::size_t{data[0]} | (std::size_t{data[1]} << 8);
        std::vector<std::uint8_t> out(out_size);
        detail::lzfDecompress(data + 2, size - 2, out.data(), out.size());
    }
    const std::string packed = detail::lzfCompress(data, size);
    std::vector<std::uint8_t> back(size);
    if (!detail::lzfDecompress(reinterpret_cast<const std::uint8_t*>(packed.data()),
                               packed.size(), back.data(), back.size())) {
        std::abort();
    }
    if (size > 0 && std::memcmp(back.data(), data, size) != 0) std::abort();
    return 0;
}
