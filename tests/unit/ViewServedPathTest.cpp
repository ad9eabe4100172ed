// SPDX-License-Identifier: Apache-2.0
// `vdbmap view`'s path resolver (apps/vdbmap/view/ServedPath.h): only regular files under the
// served root, whatever the spelling of "..", escapes or symbolic links.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "support/CliRun.h"
#include "view/ServedPath.h"

namespace fs = std::filesystem;
using vdbmap::view::contentTypeFor;
using vdbmap::view::percentDecode;
using vdbmap::view::resolveServedPath;

namespace {

void writeText(const fs::path& file, const std::string& text) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
}

}  // namespace

TEST_CASE("percentDecode decodes escapes once and rejects malformed ones", "[view]") {
    CHECK(percentDecode("a%2Fb") == std::optional<std::string>("a/b"));
    CHECK(percentDecode("%2e%2E") == std::optional<std::string>(".."));
    CHECK(percentDecode("%252e") == std::optional<std::string>("%2e"));
    CHECK(percentDecode("a+b") == std::optional<std::string>("a+b"));
    CHECK_FALSE(percentDecode("%"));
    CHECK_FALSE(percentDecode("%4"));
    CHECK_FALSE(percentDecode("%zz"));
    CHECK_FALSE(percentDecode("a%00b"));
}

TEST_CASE("resolveServedPath serves files under the root and nothing else", "[view]") {
    const fs::path dir = vdbmap::test::freshProcessDir("vdbmap_view_path");
    const vdbmap::test::RemoveAtExit cleanup{dir};
    const fs::path root = dir / "out";
    writeText(root / "3dtiles" / "tileset.json", "{}");
    writeText(root / "3dtiles" / "tiles" / "0_0.glb", "glb");
    writeText(dir / "secret.txt", "secret");
    fs::create_directory_symlink(dir, root / "escape");      // a link out of the root
    fs::create_symlink(dir / "secret.txt", root / "s.txt");  // a file link out of the root
    fs::create_symlink(root / "3dtiles" / "tileset.json", root / "inside.json");
    const fs::path tileset = fs::canonical(root / "3dtiles" / "tileset.json");

    SECTION("plain paths, '.' and repeated slashes") {
        CHECK(resolveServedPath(root, "3dtiles/tileset.json") == tileset);
        CHECK(resolveServedPath(root, "./3dtiles//tileset.json") == tileset);
        CHECK(resolveServedPath(root, "/3dtiles/tileset.json") == tileset);
        CHECK(resolveServedPath(root, "3dtiles/tiles/0_0.glb") ==
              fs::canonical(root / "3dtiles" / "tiles" / "0_0.glb"));
        CHECK(resolveServedPath(root, "inside.json") == tileset);  // a link that stays inside
    }
    SECTION("'..' in any spelling is refused, even when it would land inside") {
        for (const char* path :
             {"../secret.txt", "../../etc/passwd", "3dtiles/../../secret.txt",
              "3dtiles/../3dtiles/tileset.json", "%2e%2e/secret.txt", "%2E%2E%2Fsecret.txt",
              "%252e%252e/secret.txt", "..%2f..%2fetc%2fpasswd", "..\\secret.txt",
              "3dtiles\\..\\..\\secret.txt", "..", "%2e%2e"}) {
            INFO(path);
            CHECK_FALSE(resolveServedPath(root, path));
        }
    }
    SECTION("symbolic links that leave the root are refused") {
        CHECK_FALSE(resolveServedPath(root, "escape/secret.txt"));
        CHECK_FALSE(resolveServedPath(root, "s.txt"));
    }
    SECTION("folders, missing files, the root itself and absolute paths are refused") {
        CHECK_FALSE(resolveServedPath(root, "3dtiles"));
        CHECK_FALSE(resolveServedPath(root, "3dtiles/missing.glb"));
        CHECK_FALSE(resolveServedPath(root, ""));
        CHECK_FALSE(resolveServedPath(root, "/"));
        CHECK_FALSE(resolveServedPath(root, "/etc/passwd"));  // read as etc/passwd under root
        CHECK_FALSE(resolveServedPath(root, "a%00b"));
    }
}

TEST_CASE("contentTypeFor names the types the viewer fetches", "[view]") {
    CHECK(contentTypeFor("a/tileset.json") == "application/json");
    CHECK(contentTypeFor("a/0_0.GLB") == "model/gltf-binary");
    CHECK(contentTypeFor("viewer.js") == "text/javascript; charset=utf-8");
    CHECK(contentTypeFor("index.html") == "text/html; charset=utf-8");
    CHECK(contentTypeFor("atlas.png") == "image/png");
    CHECK(contentTypeFor("noext") == "application/octet-stream");
}
