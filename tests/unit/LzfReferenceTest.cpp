// SPDX-License-Identifier: Apache-2.0
// Our LZF codec (PCD binary_compressed) against the reference implementation, Marc Lehmann's
// liblzf 3.6 (Debian liblzf-dev, test-only): a fixed vector that liblzf's lzf_compress wrote,
// and streams that each side writes and the other decodes.
#include <liblzf/lzf.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "io/Lzf.h"

using namespace vdbmap;

namespace {

/// 223 bytes like a small PCD field-major buffer: text, 32 floats with repeats, 40 bytes
/// without repeats (literal runs).
std::vector<std::uint8_t> vectorPlainText() {
    const std::string text = "PCD binary_compressed: x x x x x x x x y y y y y y y y ";
    std::vector<std::uint8_t> in(text.begin(), text.end());
    for (int i = 0; i < 32; ++i) {
        const float f = 0.25f * static_cast<float>(i % 8);
        std::uint8_t b[4];
        std::memcpy(b, &f, 4);
        in.insert(in.end(), b, b + 4);
    }
    for (int i = 0; i < 40; ++i) in.push_back(static_cast<std::uint8_t>(i * 37 + 11));
    return in;
}

/// lzf_compress(vectorPlainText()) from liblzf 3.6 (generated once; kept fixed so the decoder
/// is checked against the reference's bytes even where liblzf changes its encoder).
const std::vector<std::uint8_t> kLiblzfBytes = {
    0x17, 0x50, 0x43, 0x44, 0x20, 0x62, 0x69, 0x6e, 0x61, 0x72, 0x79, 0x5f, 0x63, 0x6f, 0x6d,
    0x70, 0x72, 0x65, 0x73, 0x73, 0x65, 0x64, 0x3a, 0x20, 0x78, 0xe0, 0x06, 0x01, 0x00, 0x79,
    0xe0, 0x06, 0x01, 0x00, 0x00, 0x60, 0x00, 0x01, 0x80, 0x3e, 0x20, 0x06, 0x03, 0x3f, 0x00,
    0x00, 0x40, 0x20, 0x03, 0x00, 0x80, 0x20, 0x03, 0x00, 0xa0, 0x20, 0x03, 0x00, 0xc0, 0x20,
    0x03, 0x00, 0xe0, 0x20, 0x03, 0x40, 0x00, 0xe0, 0x51, 0x1f, 0x1f, 0x0b, 0x30, 0x55, 0x7a,
    0x9f, 0xc4, 0xe9, 0x0e, 0x33, 0x58, 0x7d, 0xa2, 0xc7, 0xec, 0x11, 0x36, 0x5b, 0x80, 0xa5,
    0xca, 0xef, 0x14, 0x39, 0x5e, 0x83, 0xa8, 0xcd, 0xf2, 0x17, 0x3c, 0x61, 0x86, 0x07, 0xab,
    0xd0, 0xf5, 0x1a, 0x3f, 0x64, 0x89, 0xae};

std::vector<std::uint8_t> ourDecode(const std::vector<std::uint8_t>& packed, std::size_t size,
                                    bool* ok) {
    std::vector<std::uint8_t> out(size);
    *ok = detail::lzfDecompress(packed.data(), packed.size(), out.data(), out.size());
    return out;
}

std::vector<std::uint8_t> referenceDecode(const std::string& packed, std::size_t size) {
    std::vector<std::uint8_t> out(size + 1);  // +1: a size mismatch shows as a wrong length
    const unsigned n = lzf_decompress(packed.data(), static_cast<unsigned>(packed.size()),
                                      out.data(), static_cast<unsigned>(out.size()));
    out.resize(n);
    return out;
}

}  // namespace

TEST_CASE("LZF: the fixed liblzf vector decodes to its plain text", "[io][pcd][lzf]") {
    const std::vector<std::uint8_t> plain = vectorPlainText();
    REQUIRE(plain.size() == 223);
    bool ok = false;
    CHECK(ourDecode(kLiblzfBytes, plain.size(), &ok) == plain);
    CHECK(ok);
    // The installed liblzf still writes the same bytes (else the vector documents the old ones).
    std::vector<std::uint8_t> again(512);
    const unsigned n = lzf_compress(plain.data(), static_cast<unsigned>(plain.size()),
                                    again.data(), static_cast<unsigned>(again.size()));
    again.resize(n);
    CHECK(again == kLiblzfBytes);
    // A wrong expected size, a cut stream and a back reference before the start are refused.
    ourDecode(kLiblzfBytes, plain.size() + 1, &ok);
    CHECK_FALSE(ok);
    ourDecode(std::vector<std::uint8_t>(kLiblzfBytes.begin(), kLiblzfBytes.end() - 3),
              plain.size(), &ok);
    CHECK_FALSE(ok);
    ourDecode({0x20, 0x05}, 3, &ok);  // copy 3 bytes from 6 before the start
    CHECK_FALSE(ok);
}

TEST_CASE("LZF: our encoder's streams decode with liblzf, liblzf's with ours", "[io][pcd][lzf]") {
    std::mt19937 rng(11);
    std::vector<std::vector<std::uint8_t>> inputs = {vectorPlainText(),
                                                     std::vector<std::uint8_t>(70000, 0x42)};
    for (const int alphabet : {2, 7, 256}) {
        std::vector<std::uint8_t> v(30000);
        for (auto& b : v) b = static_cast<std::uint8_t>(rng() % alphabet);
        inputs.push_back(v);
    }
    for (const auto& in : inputs) {
        CAPTURE(in.size());
        const std::string ours = detail::lzfCompress(in.data(), in.size());
        CHECK(referenceDecode(ours, in.size()) == in);

        std::vector<std::uint8_t> ref(in.size() + in.size() / 16 + 64);
        const unsigned n = lzf_compress(in.data(), static_cast<unsigned>(in.size()), ref.data(),
                                        static_cast<unsigned>(ref.size()));
        REQUIRE(n > 0);
        ref.resize(n);
        bool ok = false;
        CHECK(ourDecode(ref, in.size(), &ok) == in);
        CHECK(ok);
    }
}
