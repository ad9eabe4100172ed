// SPDX-License-Identifier: Apache-2.0
// `vdbmap view OUT [--port N] [--no-open]`: serves the 3D Tiles viewer page and OUT's files
// on 127.0.0.1 (view/ViewServer.h) and prints the address; docs/viewer.md.
#include <spawn.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "Commands.h"
#include "view/ViewServer.h"

extern char** environ;

namespace {

/// Opens `address` in the desktop's browser (xdg-open) when there is a display; silent
/// when there is none or xdg-open is missing: the printed address is the interface.
void openBrowser(const std::string& address) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((display == nullptr || *display == '\0') && (wayland == nullptr || *wayland == '\0')) {
        return;
    }
    std::string program = "xdg-open";
    std::string arg = address;
    char* argv[] = {program.data(), arg.data(), nullptr};
    pid_t pid = 0;
    if (::posix_spawnp(&pid, "xdg-open", nullptr, nullptr, argv, environ) != 0) return;
    // Not waited for here: xdg-open returns quickly; the zombie is reaped at exit.
}

}  // namespace

void addViewCommand(CLI::App& app, int& exit_code) {
    struct Options {
        std::string out_dir;
        int port = 8123;
        bool no_open = false;
    };
    auto options = std::make_shared<Options>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Serve a run's 3D Tiles (OUT/3dtiles) with the web viewer on 127.0.0.1");
    cmd->add_option("OUT", options->out_dir, "a run's output folder (with 3dtiles/tileset.json)")
        ->required();
    cmd->add_option("--port", options->port, "TCP port on 127.0.0.1 (0: any free port)")
        ->capture_default_str();
    cmd->add_flag("--no-open", options->no_open, "do not open a browser, only print the address");
    cmd->callback([options, &exit_code]() {
        vdbmap::view::ViewServer server(options->out_dir, vdbmap::view::findViewerPage());
        server.bind(options->port);
        std::cout << "vdbmap view: serving " << options->out_dir << " at " << server.address()
                  << "  (Ctrl-C stops)" << std::endl;
        if (!options->no_open) openBrowser(server.address());
        server.run();
        exit_code = 0;
    });
}
