// SPDX-License-Identifier: Apache-2.0
#include "StagedDir.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <string>

#include "vdbmap/Error.h"

namespace fs = std::filesystem;

namespace vdbmap::sim {
namespace {

bool processAlive(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

/// Deletes `.<name>.partial-<pid>` / `.<name>.old-<pid>` siblings whose process is gone.
void removeStaleStaging(const fs::path& parent, const std::string& name) {
    std::error_code ec;
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string entry = it->path().filename().string();
        for (const std::string& prefix : {"." + name + ".partial-", "." + name + ".old-"}) {
            if (entry.rfind(prefix, 0) != 0) continue;
            const std::string pid_text = entry.substr(prefix.size());
            char* end_ptr = nullptr;
            const long pid = std::strtol(pid_text.c_str(), &end_ptr, 10);
            if (pid_text.empty() || *end_ptr != '\0' || processAlive(pid)) continue;
            std::error_code rm_ec;
            fs::remove_all(it->path(), rm_ec);
        }
    }
}

bool replaceable(const fs::path& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) return true;
    if (!fs::is_directory(dir, ec)) return false;
    return fs::is_empty(dir, ec) || fs::is_regular_file(dir / "gt" / "sim.json", ec);
}

}  // namespace

StagedDir::StagedDir(fs::path final_dir) : final_(std::move(final_dir)) {
    if (final_.filename().empty()) final_ = final_.parent_path();  // "out/seq/" -> "out/seq"
    if (final_.empty() || final_.filename() == "." || final_.filename() == "..") {
        throw IoError("output folder '" + final_.string() + "' has no name");
    }
    if (!replaceable(final_)) {
        throw IoError("output folder " + final_.string() +
                      " exists and is not a vdbmap-sim sequence (no gt/sim.json): refusing to "
                      "replace it; give an empty or new folder");
    }
    fs::path parent = final_.parent_path();
    if (parent.empty()) parent = ".";
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec) throw IoError("cannot create folder " + parent.string() + ": " + ec.message());
    const std::string name = final_.filename().string();
    removeStaleStaging(parent, name);
    staging_ = parent / ("." + name + ".partial-" + std::to_string(::getpid()));
    fs::remove_all(staging_, ec);
    fs::create_directory(staging_, ec);
    if (ec) throw IoError("cannot create folder " + staging_.string() + ": " + ec.message());
}

StagedDir::~StagedDir() {
    if (committed_) return;
    std::error_code ec;  // never throw from a destructor
    fs::remove_all(staging_, ec);
}

void StagedDir::commit() {
    if (committed_) return;
    std::error_code ec;
    fs::path old;
    if (fs::exists(final_, ec)) {
        old = staging_.parent_path() /
              ("." + final_.filename().string() + ".old-" + std::to_string(::getpid()));
        fs::remove_all(old, ec);
        fs::rename(final_, old, ec);
        if (ec) {
            throw IoError("cannot move the previous sequence " + final_.string() + " aside: " +
                          ec.message());
        }
    }
    fs::rename(staging_, final_, ec);
    if (ec) {
        const std::string why = ec.message();
        if (!old.empty()) fs::rename(old, final_, ec);  // put the previous one back
        throw IoError("cannot rename " + staging_.string() + " to " + final_.string() + ": " +
                      why);
    }
    committed_ = true;
    if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace vdbmap::sim
