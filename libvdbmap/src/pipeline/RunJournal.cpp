// SPDX-License-Identifier: Apache-2.0
#include "pipeline/RunJournal.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "vdbmap/Error.h"
#include "vdbmap/Version.h"
#include "vdbmap/pipeline/Tiling.h"

namespace vdbmap::detail {
namespace fs = std::filesystem;
namespace {

constexpr std::uint64_t kFnvPrime = 1099511628211ULL;

std::string errnoText() { return std::strerror(errno); }

/// Writes all of `text` to `fd` in one write(2) when the kernel takes it whole (a regular
/// file on a local file system does), else in pieces. Throws IoError naming `file`.
void writeAll(int fd, std::string_view text, const fs::path& file) {
    while (!text.empty()) {
        const ssize_t n = ::write(fd, text.data(), text.size());
        if (n < 0) {
            if (errno == EINTR) continue;
            throw IoError(file.string() + ": cannot write the journal: " + errnoText());
        }
        text.remove_prefix(static_cast<std::size_t>(n));
    }
}

/// hex64 of the FNV-1a of a value's JSON text (nlohmann dumps object keys sorted).
std::string hashOf(const nlohmann::json& value) { return hex64(fnv1a64(value.dump())); }

std::string valueText(const nlohmann::json* value) {
    if (value == nullptr) return "(none)";
    return value->dump();
}

/// Flattens `value` into path -> leaf value ("stages[3].options.max_view_angle_deg").
void flatten(const nlohmann::json& value, const std::string& path,
             std::map<std::string, const nlohmann::json*>& out) {
    if (value.is_object() && !value.empty()) {
        for (const auto& [key, child] : value.items()) {
            flatten(child, path.empty() ? key : path + "." + key, out);
        }
    } else if (value.is_array() && !value.empty() && value.front().is_object()) {
        for (std::size_t i = 0; i < value.size(); ++i) {
            flatten(value[i], path + "[" + std::to_string(i) + "]", out);
        }
    } else {
        out[path] = &value;
    }
}

}  // namespace

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t hash) {
    for (const char c : bytes) {
        hash ^= static_cast<std::uint8_t>(c);
        hash *= kFnvPrime;
    }
    return hash;
}

std::uint64_t fileFnv1a64(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(file.string() + ": cannot open: " + errnoText());
    std::uint64_t hash = 14695981039346656037ULL;
    std::string buffer(1 << 16, '\0');
    while (in) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        const std::streamsize n = in.gcount();
        if (n <= 0) break;
        hash = fnv1a64(std::string_view(buffer.data(), static_cast<std::size_t>(n)), hash);
    }
    if (in.bad()) throw IoError(file.string() + ": read error");
    return hash;
}

std::string hex64(std::uint64_t value) {
    char text[17];
    std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(value));
    return text;
}

JournalHeader JournalHeader::fromResolvedConfig(const std::string& resolved_config_json) {
    JournalHeader h;
    h.vdbmap = versionString();
    h.config = nlohmann::json::parse(resolved_config_json);
    // Neither where the outputs go nor how the pipeline was spelled changes a tile; the
    // resolved values (with the overrides applied) do.
    h.config.erase("source");
    h.config.erase("overrides");
    if (h.config.contains("output") && h.config["output"].is_object()) {
        for (const char* key : {"dir", "write_report", "write_map"}) h.config["output"].erase(key);
    }
    // How many tiles run at once changes no tile (issue 37).
    if (h.config.contains("tiling") && h.config["tiling"].is_object()) {
        for (const char* key : {"max_tiles_in_flight", "memory_budget_gb"}) h.config["tiling"].erase(key);
    }
    for (const auto& stage : h.config.value("stages", nlohmann::json::array())) {
        const nlohmann::json options = stage.value("options", nlohmann::json::object());
        if (options.contains("voxel_size_m") && options["voxel_size_m"].is_number()) {
            h.voxel_size_m = options["voxel_size_m"].get<double>();
            break;
        }
    }
    h.config_hash = hex64(fnv1a64(h.vdbmap + "\n" + h.config.dump()));
    return h;
}

nlohmann::json JournalHeader::toJson() const {
    return {{"journal", "vdbmap-tiles"},
            {"version", 1},
            {"vdbmap", vdbmap},
            {"config_hash", config_hash},
            {"voxel_size_m", voxel_size_m},
            {"config", config}};
}

nlohmann::json tileInputs(const std::string& config_hash, const Tile& tile) {
    nlohmann::json views = nlohmann::json::array();
    for (const auto& [frame, camera] : tile.views) views.push_back({frame, camera});
    const nlohmann::json bounds = {
        {"voxel_size_m", tile.voxel_size_m},
        {"core_W",
         {tile.core_W.min_W.x(), tile.core_W.min_W.y(), tile.core_W.min_W.z(),
          tile.core_W.max_W.x(), tile.core_W.max_W.y(), tile.core_W.max_W.z()}},
        {"halo_W",
         {tile.halo_W.min_W.x(), tile.halo_W.min_W.y(), tile.halo_W.min_W.z(),
          tile.halo_W.max_W.x(), tile.halo_W.max_W.y(), tile.halo_W.max_W.z()}}};
    return {{"config", config_hash},
            {"bounds", hashOf(bounds)},
            {"scan_frames", scanFramesHash(tile.scan_frames)},
            {"views", hashOf(views)}};
}

std::string scanFramesHash(const std::vector<std::size_t>& scan_frames) {
    return hashOf(nlohmann::json(scan_frames));
}

nlohmann::json tileEntry(const nlohmann::json& inputs, const TileOutcome& outcome,
                         const fs::path& output_dir) {
    nlohmann::json tile = {{"name", outcome.name},
                           {"ix", outcome.ix},
                           {"iy", outcome.iy},
                           {"inputs", inputs},
                           {"empty", outcome.empty}};
    nlohmann::json files = nlohmann::json::array();
    if (!outcome.empty) {
        const nlohmann::json index = nlohmann::json::parse(outcome.index_json);
        for (const auto& file : index["files"]) {
            const std::string rel = file.get<std::string>();
            const fs::path path = output_dir / rel;
            std::error_code ec;
            const std::uintmax_t size = fs::file_size(path, ec);
            if (ec) throw IoError(path.string() + ": cannot read the size: " + ec.message());
            files.push_back({{"path", rel}, {"size", size}, {"fnv1a64", hex64(fileFnv1a64(path))}});
        }
        tile["faces"] = outcome.faces;
        tile["halo_faces"] = outcome.halo_faces;
        // Kept as JSON text: tiles.json and report.json are rebuilt from exactly these bytes.
        tile["index"] = outcome.index_json;
        tile["report"] = outcome.report_json;
    }
    tile["files"] = files;
    return {{"tile", tile}};
}

std::string whyRedo(const JournalTile& entry, const nlohmann::json& inputs,
                    const fs::path& output_dir) {
    static const std::pair<const char*, const char*> kInputs[] = {
        {"config", "the configuration changed"},
        {"bounds", "its bounds changed (the map around it)"},
        {"scan_frames", "the scans that reach it changed"},
        {"views", "the views that see it changed"}};
    for (const auto& [key, why] : kInputs) {
        if (!entry.inputs.contains(key) ||
            entry.inputs[key] != inputs.value(key, nlohmann::json())) {
            return why;
        }
    }
    const std::string prefix = "tiles/" + entry.name + "/";
    for (const JournalTile::File& file : entry.files) {
        const std::string shown =
            file.path.rfind(prefix, 0) == 0 ? file.path.substr(prefix.size()) : file.path;
        const fs::path path = output_dir / file.path;
        std::error_code ec;
        const std::uintmax_t size = fs::file_size(path, ec);
        if (ec) return shown + " is missing";
        if (size != file.size) {
            return shown + " has " + std::to_string(size) + " bytes, not " +
                   std::to_string(file.size);
        }
        try {
            if (hex64(fileFnv1a64(path)) != file.fnv1a64) return shown + " checksum differs";
        } catch (const IoError&) {
            return shown + " cannot be read";
        }
    }
    return {};
}

std::vector<std::string> configDifferences(const nlohmann::json& before, const nlohmann::json& now,
                                           std::size_t max_items) {
    std::map<std::string, const nlohmann::json*> a, b;
    flatten(before, "", a);
    flatten(now, "", b);
    std::vector<std::string> out;
    auto add = [&](const std::string& path, const nlohmann::json* x, const nlohmann::json* y) {
        if (out.size() == max_items) out.emplace_back("...");
        if (out.size() > max_items) return;
        // Name the stage with its index: "stages[3].options.x" -> "stages[3] semantic.mrf x".
        std::string shown = path;
        const std::size_t close = path.find(']');
        if (path.rfind("stages[", 0) == 0 && close != std::string::npos) {
            const std::size_t i = std::stoul(path.substr(7, close - 7));
            const nlohmann::json& stages =
                now.contains("stages") ? now["stages"] : before["stages"];
            std::string rest = path.substr(close + 1);
            if (rest.rfind(".options.", 0) == 0) rest = rest.substr(9);
            if (i < stages.size()) {
                shown = path.substr(0, close + 1) + " " + stages[i].value("stage", "") + " " + rest;
            }
        }
        out.push_back(shown + ": " + valueText(x) + " -> " + valueText(y));
    };
    for (const auto& [path, value] : a) {
        const auto it = b.find(path);
        if (it == b.end()) {
            add(path, value, nullptr);
        } else if (*it->second != *value) {
            add(path, value, it->second);
        }
    }
    for (const auto& [path, value] : b) {
        if (a.count(path) == 0) add(path, nullptr, value);
    }
    return out;
}

std::optional<JournalContents> RunJournal::read(const fs::path& output_dir) {
    const fs::path file = output_dir / kFileName;
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    JournalContents contents;
    std::string line;
    bool first = true;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
        const bool is_first = first;
        first = false;
        if (j.is_discarded() || !j.is_object()) {
            ++contents.bad_lines;
            continue;
        }
        try {
            if (is_first && j.contains("journal")) {
                JournalHeader h;
                h.vdbmap = j.at("vdbmap").get<std::string>();
                h.config_hash = j.at("config_hash").get<std::string>();
                h.voxel_size_m = j.at("voxel_size_m").get<double>();
                h.config = j.at("config");
                contents.header = std::move(h);
            } else if (j.contains("tile")) {
                const nlohmann::json& t = j["tile"];
                JournalTile tile;
                tile.name = t.at("name").get<std::string>();
                tile.inputs = t.at("inputs");
                tile.empty = t.at("empty").get<bool>();
                for (const auto& f : t.at("files")) {
                    tile.files.push_back({f.at("path").get<std::string>(),
                                          f.at("size").get<std::uint64_t>(),
                                          f.at("fnv1a64").get<std::string>()});
                }
                TileOutcome& o = tile.outcome;
                o.name = tile.name;
                o.ix = t.at("ix").get<int>();
                o.iy = t.at("iy").get<int>();
                o.empty = tile.empty;
                if (!tile.empty) {
                    o.faces = t.at("faces").get<std::size_t>();
                    o.halo_faces = t.at("halo_faces").get<std::size_t>();
                    o.index_json = t.at("index").get<std::string>();
                    o.report_json = t.at("report").get<std::string>();
                }
                tile.line = line;
                contents.tiles[tile.name] = std::move(tile);
            } else if (j.contains("end")) {
                contents.finished = true;
            } else {
                ++contents.bad_lines;
            }
        } catch (const nlohmann::json::exception&) {
            ++contents.bad_lines;
        }
    }
    return contents;
}

void RunJournal::start(const fs::path& output_dir, const JournalHeader& header,
                       const std::vector<std::string>& lines) {
    const fs::path file = output_dir / kFileName;
    const fs::path temp =
        output_dir / ("." + std::string(kFileName) + ".tmp" + std::to_string(::getpid()) + "-0");
    std::string text = header.toJson().dump() + "\n";
    for (const std::string& line : lines) text += line + "\n";
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(temp.string() + ": cannot create the journal: " + errnoText());
    try {
        writeAll(fd, text, temp);
        if (::fsync(fd) != 0) throw IoError(temp.string() + ": fsync failed: " + errnoText());
    } catch (...) {
        ::close(fd);
        std::error_code ec;
        fs::remove(temp, ec);
        throw;
    }
    ::close(fd);
    std::error_code ec;
    fs::rename(temp, file, ec);
    if (ec) {
        fs::remove(temp, ec);
        throw IoError(file.string() + ": cannot replace the journal: " + ec.message());
    }
}

RunJournal::RunJournal(const fs::path& output_dir) : file_(output_dir / kFileName) {
    fd_ = ::open(file_.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw IoError(file_.string() + ": cannot open the journal: " + errnoText());
}

RunJournal::~RunJournal() {
    if (fd_ >= 0) ::close(fd_);
}

void RunJournal::append(const nlohmann::json& entry) {
    writeAll(fd_, entry.dump() + "\n", file_);
    if (::fsync(fd_) != 0) throw IoError(file_.string() + ": fsync failed: " + errnoText());
    ++appended_;
}

void testKillAfterTiles(std::size_t journaled_tiles) {
    static const long kill_after = [] {
        const char* text = std::getenv("VDBMAP_TEST_KILL_AFTER_TILES");
        return text != nullptr ? std::strtol(text, nullptr, 10) : 0L;
    }();
    if (kill_after > 0 && journaled_tiles == static_cast<std::size_t>(kill_after)) {
        ::raise(SIGKILL);
    }
}

}  // namespace vdbmap::detail
