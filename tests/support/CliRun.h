// SPDX-License-Identifier: Apache-2.0
// Runs the built `vdbmap` / `vdbmap-sim` binaries as a user would: a child process with its
// stderr on a pipe (read line by line, so a test can act at a given log line), optional
// resource limits, and the exit status.
#pragma once

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vdbmap/sim/SimSequence.h"

namespace vdbmap::test {

inline const std::filesystem::path kVdbmapExe =
    std::filesystem::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap";
inline const std::filesystem::path kSimExe =
    std::filesystem::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap-sim";

struct ChildOptions {
    std::optional<rlim_t> file_size_limit;  ///< RLIMIT_FSIZE in bytes, SIGXFSZ ignored
    /// Environment variables set in the child only ("NAME", "value").
    std::vector<std::pair<std::string, std::string>> env;
};

/// A running child; stderr and stdout go to one pipe.
class Child {
public:
    Child(const std::filesystem::path& exe, const std::vector<std::string>& args,
          const ChildOptions& options = {}) {
        int fds[2];
        if (::pipe(fds) != 0) std::abort();
        pid_ = ::fork();
        if (pid_ < 0) std::abort();
        if (pid_ == 0) {
            ::dup2(fds[1], 1);
            ::dup2(fds[1], 2);
            ::close(fds[0]);
            ::close(fds[1]);
            if (options.file_size_limit) {
                ::signal(SIGXFSZ, SIG_IGN);  // write(2) then fails with EFBIG
                const rlimit limit{*options.file_size_limit, *options.file_size_limit};
                ::setrlimit(RLIMIT_FSIZE, &limit);
            }
            ::setenv("CI", "true", 1);  // no progress bars
            for (const auto& [name, value] : options.env) ::setenv(name.c_str(), value.c_str(), 1);
            std::vector<char*> argv;
            std::string exe_text = exe.string();
            argv.push_back(exe_text.data());
            std::vector<std::string> copy = args;
            for (auto& a : copy) argv.push_back(a.data());
            argv.push_back(nullptr);
            ::execv(exe_text.c_str(), argv.data());
            std::_Exit(127);
        }
        ::close(fds[1]);
        out_ = ::fdopen(fds[0], "r");
    }
    ~Child() {
        if (pid_ > 0 && !status_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
        if (out_ != nullptr) std::fclose(out_);
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    pid_t pid() const { return pid_; }
    /// Next line of output (without the newline), or nullopt at end of output.
    std::optional<std::string> readLine() {
        std::string line;
        int c;
        while ((c = std::fgetc(out_)) != EOF) {
            if (c == '\n') {
                log_ += line + "\n";
                return line;
            }
            line.push_back(static_cast<char>(c));
        }
        if (line.empty()) return std::nullopt;
        log_ += line + "\n";
        return line;
    }
    /// Reads to the end and waits; returns the raw wait status.
    int wait() {
        while (readLine()) {
        }
        if (!status_) {
            int status = 0;
            ::waitpid(pid_, &status, 0);
            status_ = status;
        }
        return *status_;
    }
    /// Exit code, or -signal when killed.
    int exitCode() {
        const int status = wait();
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }
    void kill(int signal) { ::kill(pid_, signal); }
    const std::string& log() const { return log_; }

private:
    pid_t pid_ = -1;
    std::FILE* out_ = nullptr;
    std::optional<int> status_;
    std::string log_;
};

/// A simulated KITTI street of `size_m` metres in `frames` frames (images, semantic images,
/// LiDAR labels, no held-out views) at `dir`, written once. Test cases of one file run as
/// parallel ctest processes and may share `dir`: the sequence is written into a folder of
/// this process and renamed onto `dir` in one step, so no process reads a half-written one.
/// The first rename wins; a later writer drops its copy.
inline void writeSimStreet(const std::filesystem::path& dir, std::size_t frames, double size_m) {
    namespace fs = std::filesystem;
    if (fs::exists(dir / "gt" / "sim.json")) return;
    const fs::path staging =
        dir.parent_path() / (dir.filename().string() + ".writing." + std::to_string(::getpid()));
    fs::remove_all(staging);
    SimOptions sim;
    sim.frames = frames;
    sim.size_m = size_m;
    sim.gt_views = 0;
    sim.quiet = true;
    writeSimSequence(sim, staging);
    std::error_code error;
    fs::rename(staging, dir, error);  // fails when another process's copy is already there
    if (error) {
        fs::remove_all(staging);
        if (!fs::exists(dir / "gt" / "sim.json")) {
            throw fs::filesystem_error("writeSimStreet: cannot rename", staging, dir, error);
        }
    }
}

/// A small simulated KITTI sequence (street, 3 frames, 20 m) at `dir`, written once.
inline void writeSmallSequence(const std::filesystem::path& dir, std::size_t frames = 3) {
    writeSimStreet(dir, frames, 20.0);
}

/// Removes a test process's work folder when the process ends (a static of the test file).
struct RemoveAtExit {
    std::filesystem::path dir;
    ~RemoveAtExit() {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
    }
};

/// `<tmp>/<prefix>_<pid>`, emptied and created.
inline std::filesystem::path freshProcessDir(const std::string& prefix) {
    const std::filesystem::path d =
        std::filesystem::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

}  // namespace vdbmap::test
