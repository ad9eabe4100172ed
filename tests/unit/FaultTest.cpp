// SPDX-License-Identifier: Apache-2.0
// Faults during `vdbmap run` (built binary, small simulated sequence, texture pipeline):
//  - SIGKILL at many moments (at each stage's start and end log line, after each output is
//    written, and at fractions of the run's duration) leaves no partial output: every visible
//    file is byte-identical to the one of an uninterrupted run (report.json: complete JSON),
//    and the next run in the folder succeeds and removes the temporary files left behind;
//  - a write error (a file-size limit, the error path of a full disk) is exit 1 naming the
//    file, with no partial file;
//  - two runs on one output folder: the second is refused, the first is untouched.
#include <catch2/catch.hpp>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "support/CliRun.h"

using namespace vdbmap;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

fs::path workDir() {
    static const fs::path dir = [] {
        const fs::path d = test::freshProcessDir("vdbmap_fault");
        test::writeSmallSequence(d / "seq");
        std::ofstream(d / "run.yaml")
            << "dataset: {format: kitti, path: seq}\nplugins: [texture]\nstages:\n"
               "  - {stage: integrate.atsdf, voxel_size_m: 0.2}\n"
               "  - {stage: mesh.marching_cubes}\n"
               "  - {stage: texture.mrf, mrf: false, global_adjustment: false}\n";
        return d;
    }();
    static const test::RemoveAtExit cleanup{dir};
    return dir;
}

std::string readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Visible files (relative path -> bytes) and hidden ones (relative paths) under `dir`.
struct Listing {
    std::map<std::string, std::string> visible;
    std::vector<std::string> hidden;
};
Listing list(const fs::path& dir) {
    Listing l;
    if (!fs::exists(dir)) return l;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (!e.is_regular_file()) continue;
        const std::string rel = fs::relative(e.path(), dir).string();
        if (e.path().filename().string()[0] == '.') {
            l.hidden.push_back(rel);
        } else {
            l.visible[rel] = readAll(e.path());
        }
    }
    return l;
}

std::vector<std::string> runArgs(const fs::path& out) {
    return {"run", (workDir() / "run.yaml").string(), "-o", out.string(), "--threads", "2"};
}

/// The outputs of an uninterrupted run and its duration.
struct Reference {
    Listing files;
    double seconds = 0;
};
const Reference& reference() {
    static const Reference ref = [] {
        Reference r;
        const fs::path out = workDir() / "reference";
        const auto start = Clock::now();
        test::Child child(test::kVdbmapExe, runArgs(out));
        const int code = child.exitCode();
        UNSCOPED_INFO(child.log());
        REQUIRE(code == 0);
        r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
        r.files = list(out);
        return r;
    }();
    return ref;
}

/// Same content; for .vdb files apart from the random UUID OpenVDB writes into each file's
/// header (bytes 21..56: magic 8, file version 4, library version 8, offsets flag 1, UUID 36).
bool sameOutput(const std::string& rel, const std::string& a, const std::string& b) {
    if (fs::path(rel).extension() != ".vdb") return a == b;
    constexpr std::size_t kUuidBegin = 21, kUuidEnd = 57;
    return a.size() == b.size() && a.size() > kUuidEnd &&
           a.compare(0, kUuidBegin, b, 0, kUuidBegin) == 0 &&
           a.compare(kUuidEnd, std::string::npos, b, kUuidEnd, std::string::npos) == 0;
}

/// Every visible file is complete: identical to the reference, report.json parses.
void checkNoPartialOutput(const fs::path& out, const std::string& moment) {
    INFO("killed " << moment);
    const Listing got = list(out);
    for (const auto& [rel, bytes] : got.visible) {
        INFO(rel);
        if (rel == "report.json") {
            CHECK_NOTHROW(nlohmann::json::parse(bytes));
            continue;
        }
        REQUIRE(reference().files.visible.count(rel) == 1);
        CHECK(sameOutput(rel, bytes, reference().files.visible.at(rel)));
    }
    for (const std::string& rel : got.hidden) {  // only the lock and AtomicFile temporaries
        INFO(rel);
        CHECK(std::regex_match(fs::path(rel).filename().string(),
                               std::regex(R"(\.vdbmap\.lock|\..+\.tmp[0-9]+-[0-9]+.*)")));
    }
}

}  // namespace

TEST_CASE("fault: SIGKILL at any moment leaves no partial output", "[cli][hardening][fault]") {
    const Reference& ref = reference();
    REQUIRE(ref.files.visible.count("map.vdb") == 1);
    REQUIRE(ref.files.visible.count("mesh.ply") == 1);
    REQUIRE(ref.files.visible.count("textured/mesh.obj") == 1);
    REQUIRE(ref.files.visible.count("report.json") == 1);

    // Moments picked from the log: each stage's start and end, each output written.
    const std::vector<std::string> log_moments = {
        "[1/3] integrate.atsdf", "integrate.atsdf done", "[2/3] mesh.marching_cubes",
        "mesh.marching_cubes done", "[3/3] texture.mrf", "texture.mrf done", "map.vdb",
        "mesh.ply"};
    int index = 0;
    for (const std::string& moment : log_moments) {
        const fs::path out = workDir() / ("kill_log_" + std::to_string(index++));
        test::Child child(test::kVdbmapExe, runArgs(out));
        bool seen = false;
        while (const auto line = child.readLine()) {
            if (line->find(moment) != std::string::npos) {
                child.kill(SIGKILL);
                seen = true;
                break;
            }
        }
        INFO(child.log());
        CHECK(seen);
        CHECK(child.exitCode() == -SIGKILL);
        checkNoPartialOutput(out, "at log line '" + moment + "'");
    }
    // Moments in time: fractions of the uninterrupted run (catch writes in progress).
    for (const double fraction : {0.2, 0.5, 0.8, 0.9, 0.95, 0.98}) {
        const fs::path out = workDir() / ("kill_time_" + std::to_string(index++));
        test::Child child(test::kVdbmapExe, runArgs(out));
        std::this_thread::sleep_for(std::chrono::duration<double>(fraction * ref.seconds));
        child.kill(SIGKILL);
        child.wait();
        checkNoPartialOutput(out, "at " + std::to_string(fraction) + " of the run time");
        // The next run in the same folder succeeds and removes the temporaries.
        if (fraction == 0.95) {
            test::Child again(test::kVdbmapExe, runArgs(out));
            CHECK(again.exitCode() == 0);
            const Listing after = list(out);
            CHECK(after.hidden == std::vector<std::string>{".vdbmap.lock"});
            CHECK(after.visible.at("mesh.ply") == ref.files.visible.at("mesh.ply"));
        }
    }
}

TEST_CASE("fault: a file-size limit (as a full disk) is exit 1 naming the file, no partial file",
          "[cli][hardening][fault]") {
    const Reference& ref = reference();
    const std::size_t map_bytes = ref.files.visible.at("map.vdb").size();
    const std::size_t report_bytes = ref.files.visible.at("report.json").size();
    REQUIRE(map_bytes > report_bytes + 8192);
    const fs::path out = workDir() / "fsize";
    test::ChildOptions options;
    options.file_size_limit = static_cast<rlim_t>(report_bytes + 4096);  // report.json fits
    test::Child child(test::kVdbmapExe, runArgs(out), options);
    CHECK(child.exitCode() == 1);
    INFO(child.log());
    // The first output past the limit (the texture atlas PNG, written by its stage, or
    // map.vdb) is named, and it is not there, neither whole nor in part.
    std::smatch match;
    const std::string log = child.log();
    REQUIRE(std::regex_search(log, match, std::regex(R"(write error on (\S+): File too large)")));
    const fs::path failed = match[1].str();
    CHECK(failed.parent_path().string().rfind(out.string(), 0) == 0);
    CHECK_FALSE(fs::exists(failed));
    const Listing got = list(out);
    CHECK(got.hidden == std::vector<std::string>{".vdbmap.lock"});  // temporary deleted
    REQUIRE(got.visible.count("report.json") == 1);  // the failure is reported
    const auto report = nlohmann::json::parse(got.visible.at("report.json"));
    CHECK(report["status"]["exit_code"] == 1);
    CHECK_THAT(report["status"]["error"].get<std::string>(), Contains(failed.filename().string()));
    for (const auto& [rel, bytes] : got.visible) {  // whatever was written is complete
        INFO(rel);
        if (rel != "report.json") CHECK(sameOutput(rel, bytes, ref.files.visible.at(rel)));
    }
}

TEST_CASE("fault: a second run on a busy output folder is refused", "[cli][hardening][fault]") {
    const fs::path out = workDir() / "busy";
    test::Child first(test::kVdbmapExe, runArgs(out));
    while (const auto line = first.readLine()) {
        if (line->find("[1/3]") != std::string::npos) break;  // holds the lock now
    }
    // Paused while the second run tries, so that a loaded machine cannot let the short first
    // run finish (and release the lock) before the second one starts.
    REQUIRE(::kill(first.pid(), SIGSTOP) == 0);
    test::Child second(test::kVdbmapExe, runArgs(out));
    const int second_exit = second.exitCode();
    REQUIRE(::kill(first.pid(), SIGCONT) == 0);
    CHECK(second_exit == 1);
    CHECK_THAT(second.log(), Contains("in use by another vdbmap run") &&
                                 Contains("pid " + std::to_string(first.pid())) &&
                                 Contains(".vdbmap.lock"));
    REQUIRE(first.exitCode() == 0);
    const auto report = nlohmann::json::parse(readAll(out / "report.json"));
    CHECK(report["status"]["ok"] == true);
    CHECK(readAll(out / "mesh.ply") == reference().files.visible.at("mesh.ply"));
}
