// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace vdbmap::detail {

/// Decompresses an LZF stream (liblzf format, as in PCD "binary_compressed") into exactly
/// `out_size` bytes at `out`. Returns false on a corrupt stream (a back reference before the
/// start, a run past either end, or a size mismatch); never reads or writes out of bounds.
bool lzfDecompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                   std::size_t out_size);

/// Encodes `size` bytes as a valid LZF stream that lzfDecompress (and liblzf) decodes. Uses a
/// small hash table of 3-byte prefixes to find back references, as liblzf does.
std::string lzfCompress(const std::uint8_t* in, std::size_t size);

}  // namespace vdbmap::detail
