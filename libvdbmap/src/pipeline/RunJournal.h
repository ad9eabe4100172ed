// SPDX-License-Identifier: Apache-2.0
// The journal of a tiled run (issue 36): what `vdbmap run --resume` reads to keep the tiles an
// interrupted run finished.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/TileStream.h"

namespace vdbmap {
struct Tile;
}

namespace vdbmap::detail {

/// FNV-1a, 64 bit (Fowler, Noll and Vo: offset basis 14695981039346656037, prime
/// 1099511628211), continued from `hash`. Not cryptographic: it catches a torn, truncated or
/// bit-flipped file, not a forged one.
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t hash = 14695981039346656037ULL);
/// FNV-1a 64 of a file's bytes. Throws IoError naming the file.
std::uint64_t fileFnv1a64(const std::filesystem::path& file);
/// 16 lower-case hex digits.
std::string hex64(std::uint64_t value);

/// The first line of a journal: what decided every tile of the run.
struct JournalHeader {
    std::string vdbmap;         ///< vdbmap version
    std::string config_hash;    ///< hex64 of `config`
    double voxel_size_m = 0.0;  ///< of the first stage with a voxel_size_m option (0: none)
    /// Pipeline::resolvedConfigJson without what does not change a tile (source, overrides,
    /// output.dir, output.write_report, output.write_map).
    nlohmann::json config;

    /// From the pipeline's resolved configuration (JSON text).
    static JournalHeader fromResolvedConfig(const std::string& resolved_config_json);
    nlohmann::json toJson() const;
};

/// One finished tile as the journal holds it.
struct JournalTile {
    struct File {
        std::string path;  ///< relative to the output folder ("tiles/3_-1/semantic/mesh.ply")
        std::uint64_t size = 0;
        std::string fnv1a64;  ///< hex64
    };
    std::string name;
    nlohmann::json inputs;  ///< tileInputs()
    bool empty = false;     ///< finished without a core face (nothing written)
    std::vector<File> files;
    TileOutcome outcome;  ///< index and report entries (empty: only name, ix, iy)
    std::string line;     ///< the line as read
};

/// A journal as read back.
struct JournalContents {
    std::optional<JournalHeader> header;       ///< nullopt: no readable header
    std::map<std::string, JournalTile> tiles;  ///< by name; a later entry replaces an earlier
    bool finished = false;      ///< the run wrote its "end" line (tiles.json was written)
    std::size_t bad_lines = 0;  ///< lines that are not JSON or not an entry (a torn last line)
};

/// The inputs that decide a tile's outputs: the configuration's hash, the tile's key and
/// bounds, the frames whose scans reach it (Tile::scan_frames) and its views (Tile::views),
/// each hashed, so that a resume can say which one changed.
nlohmann::json tileInputs(const std::string& config_hash, const Tile& tile);

/// The "scan_frames" hash of tileInputs() for these frames.
std::string scanFramesHash(const std::vector<std::size_t>& scan_frames);

/// The journal entry of a finished tile: its inputs, the size and FNV-1a of each file of its
/// index entry (read back from `output_dir`), and its index and report entries.
nlohmann::json tileEntry(const nlohmann::json& inputs, const TileOutcome& outcome,
                         const std::filesystem::path& output_dir);

/// Why `entry` cannot stand for the tile with `inputs` ("" when it can): "its scan frames
/// changed", "semantic/mesh.ply is missing", "textured/mesh.obj checksum differs", ...
/// File names are relative to the tile's folder.
std::string whyRedo(const JournalTile& entry, const nlohmann::json& inputs,
                    const std::filesystem::path& output_dir);

/// The options that differ between two header configs, as "stages[3] semantic.mrf
/// max_view_angle_deg: 88 -> 80" (at most `max_items`, then "...").
std::vector<std::string> configDifferences(const nlohmann::json& before, const nlohmann::json& now,
                                           std::size_t max_items = 8);

/// `<output>/journal.jsonl`: one JSON object per line, appended as tiles finish, each line one
/// write(2) on an O_APPEND descriptor followed by fsync(2) (the processes of an MPI run append
/// to the same file; a line is never split between them on a local file system). The first
/// line is the header; then {"tile": ...} entries; last {"end": true} once tiles.json is written.
class RunJournal {
public:
    static constexpr const char* kFileName = "journal.jsonl";

    /// Reads the journal of `output_dir`; nullopt when there is none. Lines that do not parse
    /// (a line torn by a kill) are counted and skipped.
    static std::optional<JournalContents> read(const std::filesystem::path& output_dir);
    /// Replaces the journal by `header` and `lines` (entries copied from an earlier journal):
    /// written to a temporary file, fsync'd, renamed over. Throws IoError.
    static void start(const std::filesystem::path& output_dir, const JournalHeader& header,
                      const std::vector<std::string>& lines);

    /// Opens the journal of `output_dir` for appending. Throws IoError.
    explicit RunJournal(const std::filesystem::path& output_dir);
    ~RunJournal();
    RunJournal(const RunJournal&) = delete;
    RunJournal& operator=(const RunJournal&) = delete;

    /// Appends `entry` as one line and fsyncs. Throws IoError (a full disk) naming the file.
    void append(const nlohmann::json& entry);
    /// Lines this object appended.
    std::size_t appended() const { return appended_; }

private:
    std::filesystem::path file_;
    int fd_ = -1;
    std::size_t appended_ = 0;
};

/// Test hook (docs/tiling.md, "Resume"): when the environment variable
/// VDBMAP_TEST_KILL_AFTER_TILES is N > 0, the process raises SIGKILL once it has journaled its
/// N-th tile, a deterministic "killed here" for the tests. Call after each append.
void testKillAfterTiles(std::size_t journaled_tiles);

}  // namespace vdbmap::detail
