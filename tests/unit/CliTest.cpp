// SPDX-License-Identifier: Apache-2.0
// The built `vdbmap` binary: exit codes 0 (success), 2 (usage / config), 1 (runtime / input).
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

using namespace std::string_literals;
namespace fs = std::filesystem;

namespace {

const fs::path kExe = fs::path(VDBMAP_BINARY_DIR) / "bin" / "vdbmap";
const fs::path kPluginDir = fs::path(VDBMAP_BINARY_DIR) / "tests" / "plugins-bin";

fs::path workDir() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("vdbmap_cli_test_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

fs::path writeFile(const std::string& name, const std::string& text) {
    const fs::path path = workDir() / name;
    std::ofstream(path) << text;
    return path;
}

/// Runs `vdbmap <args>` (stdout/stderr to a log file) and returns its exit status. `env`:
/// further NAME=value assignments for the child only.
int vdbmap(const std::string& args, std::string* output = nullptr, const std::string& env = "") {
    const fs::path log = workDir() / "log.txt";
    const std::string cmd = env + " VDBMAP_PLUGIN_PATH='" + kPluginDir.string() + "' '" +
                            kExe.string() + "' " + args + " > '" + log.string() + "' 2>&1 < /dev/null";
    const int status = std::system(cmd.c_str());
    std::ifstream in(log);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (output) *output = text;
    UNSCOPED_INFO("$ vdbmap " << args << "\n" << text);
    REQUIRE(WIFEXITED(status));
    return WEXITSTATUS(status);
}

const char* kGood = "plugins: [testgood]\nstages:\n  - stage: testgood.echo\n    repeat: 2\n";

}  // namespace

TEST_CASE("cli: help, version and describe succeed", "[cli]") {
    REQUIRE(fs::exists(kExe));
    std::string out;
    CHECK(vdbmap("--help", &out) == 0);
    CHECK(out.find("run") != std::string::npos);
    CHECK(vdbmap("--version") == 0);
    CHECK(vdbmap("describe", &out) == 0);
    CHECK(out.find("integrate.atsdf") != std::string::npos);
    CHECK(out.find("testgood.echo") != std::string::npos);  // found on VDBMAP_PLUGIN_PATH
    CHECK(vdbmap("describe testgood.echo", &out) == 0);
    CHECK(out.find("width_m") != std::string::npos);
    CHECK(out.find("double") != std::string::npos);
    CHECK(vdbmap("describe dataset", &out) == 0);
    CHECK(out.find("path") != std::string::npos);
    // The generic layout's camera maps are documented with their own keys.
    CHECK(out.find("cameras (generic layout)") != std::string::npos);
    CHECK(out.find("(required)") != std::string::npos);  // image_dir of a camera map
    CHECK(vdbmap("describe output", &out) == 0);
    CHECK(out.find("write_map") != std::string::npos);
}

TEST_CASE("cli: usage and configuration errors exit with 2", "[cli]") {
    std::string out;
    CHECK(vdbmap("") == 2);
    CHECK(vdbmap("frobnicate") == 2);
    CHECK(vdbmap("run") == 2);
    CHECK(vdbmap("run '" + (workDir() / "missing.yaml").string() + "'", &out) == 2);
    CHECK(out.find("config file not found") != std::string::npos);
    const fs::path bad = writeFile("bad.yaml", "plugins: [testgood]\nstages:\n"
                                               "  - stage: testgood.echo\n    repat: 2\n");
    CHECK(vdbmap("run '" + bad.string() + "' -o '" + (workDir() / "bad").string() + "'", &out) == 2);
    CHECK(out.find("bad.yaml:4:5") != std::string::npos);
    CHECK(out.find("valid keys: message, repeat, width_m") != std::string::npos);
    CHECK_FALSE(fs::exists(workDir() / "bad"));  // nothing ran, nothing written
    const fs::path good = writeFile("good.yaml", kGood);
    CHECK(vdbmap("run '" + good.string() + "' --set testgood.echo.repeat=x") == 2);
    CHECK(vdbmap("run '" + good.string() + "' --threads 0") == 2);
    CHECK(vdbmap("describe no.such_stage") == 2);
    // A built-in stage's enumerated option names the key and the value.
    const fs::path merge = writeFile("merge.yaml", "stages:\n  - stage: integrate.atsdf\n"
                                                   "    merge_points: half\n");
    CHECK(vdbmap("run --check '" + merge.string() + "'", &out) == 2);
    CHECK(out.find("merge.yaml:2:5") != std::string::npos);
    CHECK(out.find("'merge_points' must be auto, none, voxel or half_voxel, got 'half'") != std::string::npos);
    const fs::path abi = writeFile("abi.yaml", "plugins: ['" +
                                                   (kPluginDir / "vdbmap_plugin_badabi.so").string() +
                                                   "']\nstages:\n  - stage: x.y\n");
    CHECK(vdbmap("run '" + abi.string() + "'", &out) == 2);
    CHECK(out.find("found 9999") != std::string::npos);
}

TEST_CASE("cli: a good run exits 0 and writes report.json", "[cli]") {
    const fs::path good = writeFile("good.yaml", kGood);
    const fs::path out_dir = workDir() / "good";
    CHECK(vdbmap("run '" + good.string() + "' -o '" + out_dir.string() +
                 "' --threads 1 --quiet --set testgood.echo.message=yo") == 0);
    std::ifstream in(out_dir / "report.json");
    REQUIRE(in.good());
    const auto json = nlohmann::json::parse(in);
    CHECK(json["status"]["exit_code"] == 0);
    CHECK(json["config"]["stages"][0]["options"]["message"] == "yo");
    CHECK(json["stages"]["testgood.echo"]["lines"] == 2);
    CHECK(vdbmap("run --check '" + good.string() + "'") == 0);
}

TEST_CASE("cli: runtime and input errors exit with 1", "[cli]") {
    std::string out;
    const fs::path text = writeFile("not_a.vdb", "hello");
    CHECK(vdbmap("info '" + text.string() + "'", &out) == 1);
    CHECK(out.find("not_a.vdb") != std::string::npos);
    CHECK(vdbmap("info '" + (workDir() / "missing.vdb").string() + "'") == 1);
    // The dataset folder does not exist: an input error found when the run starts.
    const fs::path cfg = writeFile(
        "nodata.yaml", "dataset:\n  path: /nonexistent/vdbmap_seq\n" + std::string(kGood));
    const fs::path out_dir = workDir() / "nodata";
    CHECK(vdbmap("run '" + cfg.string() + "' -o '" + out_dir.string() + "'", &out) == 1);
    std::ifstream in(out_dir / "report.json");
    REQUIRE(in.good());
    CHECK(nlohmann::json::parse(in)["status"]["exit_code"] == 1);
}

TEST_CASE("cli: vdbmap run started by mpirun with more than one rank stops at once", "[cli][mpi]") {
    // mpirun -np 2 sets OMPI_COMM_WORLD_SIZE (Open MPI) or PMI_SIZE (MPICH) in every rank: two
    // full runs would collide on one output folder. Set here in the child only.
    const fs::path good = writeFile("mpi_good.yaml", kGood);
    for (const std::string var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
        INFO(var);
        const fs::path out = workDir() / ("mpi_out_" + var);
        fs::remove_all(out);
        std::string log;
        CHECK(vdbmap("run '" + good.string() + "' -o '" + out.string() + "'", &log, var + "=2") == 2);
        CHECK(log.find("vdbmap-mpi run") != std::string::npos);
        CHECK(log.find(var + "=2") != std::string::npos);
        CHECK_FALSE(fs::exists(out));  // nothing ran, not even the output lock
    }
    // One rank (mpirun -np 1) is an ordinary run.
    const fs::path one = workDir() / "mpi_out_one";
    fs::remove_all(one);
    CHECK(vdbmap("run '" + good.string() + "' -o '" + one.string() + "' -q", nullptr,
                 "OMPI_COMM_WORLD_SIZE=1") == 0);
    CHECK(fs::exists(one / "report.json"));
}
