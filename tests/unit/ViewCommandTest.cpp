// SPDX-License-Identifier: Apache-2.0
// `vdbmap view OUT` as a user runs it: the printed address serves the page and OUT's files,
// never a file outside OUT (raw requests, so no client normalises "..": the server must),
// and a folder without a tileset or a busy port is a clear error, exit 1.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "support/CliRun.h"

namespace fs = std::filesystem;
using vdbmap::test::Child;
using vdbmap::test::kVdbmapExe;

namespace {

struct HttpReply {
    int status = 0;
    std::string body;
};

/// One GET with the request target sent byte for byte as given.
HttpReply rawGet(int port, const std::string& target) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    const std::string request =
        "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    REQUIRE(::send(fd, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size()));
    std::string reply;
    char buffer[4096];
    ssize_t n = 0;
    while ((n = ::recv(fd, buffer, sizeof buffer, 0)) > 0) reply.append(buffer, static_cast<std::size_t>(n));
    ::close(fd);
    HttpReply out;
    std::smatch m;
    if (std::regex_search(reply, m, std::regex(R"(^HTTP/1\.[01] (\d{3}))"))) out.status = std::stoi(m[1]);
    const std::size_t header_end = reply.find("\r\n\r\n");
    if (header_end != std::string::npos) out.body = reply.substr(header_end + 4);
    return out;
}

void writeText(const fs::path& file, const std::string& text) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
}

/// Starts `vdbmap view OUT --port 0 --no-open` and returns the port it prints.
int startServer(Child& child) {
    const std::optional<std::string> line = child.readLine();
    REQUIRE(line);
    INFO(*line);
    std::smatch m;
    REQUIRE(std::regex_search(*line, m, std::regex(R"(http://127\.0\.0\.1:(\d+)/)")));
    return std::stoi(m[1]);
}

}  // namespace

TEST_CASE("vdbmap view serves the page and OUT's files, and nothing outside OUT", "[view][cli]") {
    const fs::path dir = vdbmap::test::freshProcessDir("vdbmap_view_cli");
    const vdbmap::test::RemoveAtExit cleanup{dir};
    const fs::path out = dir / "run";
    const std::string tileset = R"({"asset":{"version":"1.1"},"geometricError":1})";
    writeText(out / "3dtiles" / "tileset.json", tileset);
    writeText(dir / "secret.txt", "SECRET-OUTSIDE-OUT");

    Child child(kVdbmapExe, {"view", out.string(), "--port", "0", "--no-open"});
    const int port = startServer(child);

    const HttpReply page = rawGet(port, "/");
    CHECK(page.status == 200);
    CHECK(page.body.find("<html") != std::string::npos);
    CHECK(rawGet(port, "/viewer.js").status == 200);
    const HttpReply json = rawGet(port, "/out/3dtiles/tileset.json");
    CHECK(json.status == 200);
    CHECK(json.body == tileset);
    CHECK(rawGet(port, "/out/3dtiles/missing.glb").status == 404);

    for (const char* target :
         {"/out/../../etc/passwd", "/../../etc/passwd", "/out/../secret.txt", "/../secret.txt",
          "/out/%2e%2e/%2e%2e/etc/passwd", "/out/%2E%2E/secret.txt", "/%2e%2e/%2e%2e/etc/passwd",
          "/out/..%2f..%2f..%2fetc%2fpasswd", "/out%2f..%2f..%2fetc%2fpasswd",
          "/out/%252e%252e/%252e%252e/etc/passwd", "/out/..%5c..%5csecret.txt",
          "/etc/passwd", "/out//etc/passwd", "/out/%2fetc%2fpasswd"}) {
        INFO(target);
        const HttpReply reply = rawGet(port, target);
        CHECK(reply.status == 404);
        CHECK(reply.body.find("root:") == std::string::npos);
        CHECK(reply.body.find("SECRET-OUTSIDE-OUT") == std::string::npos);
    }
    child.kill(SIGTERM);
}

TEST_CASE("vdbmap view: a folder without a tileset and a busy port are clear errors", "[view][cli]") {
    const fs::path dir = vdbmap::test::freshProcessDir("vdbmap_view_cli_errors");
    const vdbmap::test::RemoveAtExit cleanup{dir};
    fs::create_directories(dir / "run_without_tiles" / "semantic");

    SECTION("no 3dtiles/tileset.json") {
        Child child(kVdbmapExe, {"view", (dir / "run_without_tiles").string(), "--no-open"});
        CHECK(child.exitCode() == 1);
        CHECK(child.log().find("run_without_tiles") != std::string::npos);
        CHECK(child.log().find("no 3dtiles/tileset.json") != std::string::npos);
    }
    SECTION("a missing folder") {
        Child child(kVdbmapExe, {"view", (dir / "missing").string(), "--no-open"});
        CHECK(child.exitCode() == 1);
        CHECK(child.log().find("missing: not a folder") != std::string::npos);
    }
    SECTION("a busy port") {
        writeText(dir / "run" / "3dtiles" / "tileset.json", "{}");
        const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        REQUIRE(fd >= 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_port = 0;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
        REQUIRE(::listen(fd, 1) == 0);
        socklen_t len = sizeof addr;
        REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0);
        const std::string port = std::to_string(ntohs(addr.sin_port));
        Child child(kVdbmapExe, {"view", (dir / "run").string(), "--port", port, "--no-open"});
        CHECK(child.exitCode() == 1);
        CHECK(child.log().find("port " + port + " on 127.0.0.1 is in use") != std::string::npos);
        ::close(fd);
    }
}
