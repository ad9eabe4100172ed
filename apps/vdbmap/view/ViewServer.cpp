// SPDX-License-Identifier: Apache-2.0
#include "ViewServer.h"

#include <httplib.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "ServedPath.h"
#include "vdbmap/Error.h"

namespace fs = std::filesystem;

namespace vdbmap::view {
namespace {

constexpr const char* kHost = "127.0.0.1";

bool readFile(const fs::path& file, std::string& bytes) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return false;
    std::ostringstream buffer;
    buffer << in.rdbuf();
    bytes = buffer.str();
    return static_cast<bool>(in) || in.eof();
}

/// Serves `url_path` below `root`, or 404.
void serveFrom(const fs::path& root, const std::string& url_path, httplib::Response& res) {
    const std::optional<fs::path> file = resolveServedPath(root, url_path);
    std::string bytes;
    if (!file || !readFile(*file, bytes)) {
        res.status = 404;
        res.set_content("not found\n", "text/plain; charset=utf-8");
        return;
    }
    res.status = 200;
    res.set_header("Cache-Control", "no-cache");
    res.set_content(bytes, contentTypeFor(*file).c_str());
}

fs::path executableDir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path() : exe.parent_path();
}

}  // namespace

ViewServer::ViewServer(const fs::path& out_dir, const fs::path& page_dir)
    : server_(std::make_unique<httplib::Server>()) {
    std::error_code ec;
    if (!fs::is_directory(out_dir, ec)) {
        throw IoError(out_dir.string() + ": not a folder (vdbmap view OUT needs a run's output folder)");
    }
    out_dir_ = fs::canonical(out_dir);
    if (!fs::is_regular_file(out_dir_ / "3dtiles" / "tileset.json", ec)) {
        throw IoError(out_dir.string() +
                      ": no 3dtiles/tileset.json in this folder; run a pipeline with the "
                      "export.3dtiles stage (docs/viewer.md) and view its output folder");
    }
    if (!fs::is_regular_file(page_dir / "index.html", ec)) {
        throw IoError(page_dir.string() + ": the viewer page (index.html) is missing");
    }
    page_dir_ = fs::canonical(page_dir);

    server_->Get(R"(/out/(.*))", [this](const httplib::Request& req, httplib::Response& res) {
        serveFrom(out_dir_, req.matches[1].str(), res);
    });
    server_->Get(R"(/(.*))", [this](const httplib::Request& req, httplib::Response& res) {
        const std::string path = req.matches[1].str();
        serveFrom(page_dir_, path.empty() ? std::string("index.html") : path, res);
    });
}

ViewServer::~ViewServer() = default;

int ViewServer::bind(int port) {
    if (port < 0 || port > 65535) {
        throw IoError("--port " + std::to_string(port) + ": not a TCP port (0..65535)");
    }
    if (port == 0) {
        port_ = server_->bind_to_any_port(kHost);
        if (port_ < 0) throw IoError(std::string("cannot bind any port on ") + kHost);
    } else {
        if (!server_->bind_to_port(kHost, port)) {
            throw IoError("port " + std::to_string(port) + " on " + kHost +
                          " is in use (or not allowed); choose another with --port N");
        }
        port_ = port;
    }
    return port_;
}

void ViewServer::run() {
    if (port_ < 0) throw IoError("vdbmap view: the server was not bound to a port");
    if (!server_->listen_after_bind()) {
        throw IoError("the server on " + address() + " stopped with an error");
    }
}

void ViewServer::stop() { server_->stop(); }

std::string ViewServer::address() const {
    return std::string("http://") + kHost + ":" + std::to_string(port_) + "/";
}

fs::path findViewerPage() {
    std::vector<fs::path> tried;
    if (const char* env = std::getenv("VDBMAP_VIEWER_DIR"); env != nullptr && *env != '\0') {
        tried.emplace_back(env);
    }
    const fs::path exe_dir = executableDir();
    if (!exe_dir.empty()) tried.push_back(exe_dir / ".." / "share" / "vdbmap" / "viewer");
#ifdef VDBMAP_VIEWER_SOURCE_DIST
    tried.emplace_back(VDBMAP_VIEWER_SOURCE_DIST);
#endif
    std::string list;
    for (const fs::path& dir : tried) {
        std::error_code ec;
        if (fs::is_regular_file(dir / "index.html", ec)) return dir.lexically_normal();
        list += " " + dir.string();
    }
    throw IoError("the viewer page (index.html) was not found in:" + list +
                  " (set VDBMAP_VIEWER_DIR to apps/viewer/dist)");
}

}  // namespace vdbmap::view
