// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <memory>
#include <string>

/// The HTTP server behind `vdbmap view OUT` (cpp-httplib, 127.0.0.1 only). It serves two
/// trees and nothing else: the viewer page (apps/viewer/dist) at "/", and the files under OUT
/// at "/out/". Every path goes through resolveServedPath (ServedPath.h): "..", escapes and
/// symbolic links that leave a tree get 404.

namespace httplib {
class Server;
}

namespace vdbmap::view {

class ViewServer {
public:
    /// Throws IoError when `out_dir` has no 3dtiles/tileset.json or `page_dir` no index.html.
    ViewServer(const std::filesystem::path& out_dir, const std::filesystem::path& page_dir);
    ~ViewServer();
    ViewServer(const ViewServer&) = delete;
    ViewServer& operator=(const ViewServer&) = delete;

    /// Binds 127.0.0.1:`port` (0: any free port) and returns the bound port. Throws IoError
    /// naming the port when it is busy.
    int bind(int port);
    /// Serves until stop() (blocking). Throws IoError if the server fails.
    void run();
    void stop();

    /// "http://127.0.0.1:PORT/" once bound.
    std::string address() const;

private:
    std::filesystem::path out_dir_;
    std::filesystem::path page_dir_;
    std::unique_ptr<httplib::Server> server_;
    int port_ = -1;
};

/// Where the viewer page is: $VDBMAP_VIEWER_DIR, else `<exe dir>/../share/vdbmap/viewer`
/// (an install), else the source tree's apps/viewer/dist (a build tree). Throws IoError
/// listing the places tried when none has index.html.
std::filesystem::path findViewerPage();

}  // namespace vdbmap::view
