// SPDX-License-Identifier: Apache-2.0
#include "io/Lzf.h"

#include <vector>

namespace vdbmap::detail {

// LZF format (Marc Lehmann's liblzf): a sequence of runs, each introduced by a control byte c.
//   c < 32:   literal run of c + 1 bytes that follow.
//   c >= 32:  back reference; length L = c >> 5 (7 means "add the next byte"), then one more
//             byte of offset; copy L + 2 bytes from (out - ((c & 31) << 8) - offset_byte - 1).
bool lzfDecompress(const std::uint8_t* in, std::size_t in_size, std::uint8_t* out,
                   std::size_t out_size) {
    std::size_t ip = 0;
    std::size_t op = 0;
    while (ip < in_size) {
        const std::size_t ctrl = in[ip++];
        if (ctrl < 32) {
            const std::size_t len = ctrl + 1;
            if (ip + len > in_size || op + len > out_size) return false;
            for (std::size_t k = 0; k < len; ++k) out[op++] = in[ip++];
        } else {
            std::size_t len = ctrl >> 5;
            if (len == 7) {
                if (ip >= in_size) return false;
                len += in[ip++];
            }
            if (ip >= in_size) return false;
            const std::size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
            len += 2;
            if (back > op || op + len > out_size) return false;
            // Byte by byte: the source may overlap the bytes being written (run-length repeats).
            for (std::size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
        }
    }
    return op == out_size;
}

std::string lzfCompress(const std::uint8_t* in, std::size_t size) {
    constexpr std::size_t kMaxOffset = 1 << 13;  // 8192: 13 offset bits
    constexpr std::size_t kMaxLiteral = 32;
    constexpr std::size_t kMaxRef = (1 << 8) + (1 << 3);  // 264: 7 + 255 + 2
    constexpr std::size_t kHashBits = 16;
    std::vector<std::size_t> table(std::size_t{1} << kHashBits, static_cast<std::size_t>(-1));
    std::string out;
    out.reserve(size + size / 32 + 16);
    std::string literal;
    const auto flushLiteral = [&] {
        std::size_t pos = 0;
        while (pos < literal.size()) {
            const std::size_t n = std::min(kMaxLiteral, literal.size() - pos);
            out.push_back(static_cast<char>(n - 1));
            out.append(literal, pos, n);
            pos += n;
        }
        literal.clear();
    };
    std::size_t ip = 0;
    while (ip < size) {
        std::size_t match_len = 0;
        std::size_t match_pos = 0;
        if (ip + 2 < size) {
            const std::uint32_t key =
                (std::uint32_t{in[ip]} << 16) | (std::uint32_t{in[ip + 1]} << 8) | in[ip + 2];
            const std::size_t h = (key * 2654435761u) >> (32 - kHashBits);
            const std::size_t candidate = table[h];
            table[h] = ip;
            if (candidate != static_cast<std::size_t>(-1) && ip - candidate <= kMaxOffset) {
                const std::size_t max_len = std::min(kMaxRef, size - ip);
                while (match_len < max_len && in[candidate + match_len] == in[ip + match_len]) {
                    ++match_len;
                }
                match_pos = candidate;
            }
        }
        if (match_len >= 3) {
            flushLiteral();
            const std::size_t off = ip - match_pos - 1;
            const std::size_t len = match_len - 2;
            if (len < 7) {
                out.push_back(static_cast<char>((len << 5) | (off >> 8)));
            } else {
                out.push_back(static_cast<char>((7 << 5) | (off >> 8)));
                out.push_back(static_cast<char>(len - 7));
            }
            out.push_back(static_cast<char>(off & 0xff));
            ip += match_len;
        } else {
            literal.push_back(static_cast<char>(in[ip++]));
        }
    }
    flushLiteral();
    return out;
}

}  // namespace vdbmap::detail
