// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

namespace vdbmap::sim {

/// A sequence folder that appears whole or not at all. Everything is written into a hidden
/// sibling `.<name>.partial-<pid>`; commit() renames it to the final folder (replacing a
/// previous vdbmap-sim sequence there). If commit() is never reached (an error, an
/// exception) the destructor deletes the staging folder; staging folders left by killed runs
/// (their pid is gone) are deleted by the next run. Throws IoError.
class StagedDir {
public:
    /// Refuses (IoError) a `final_dir` that exists and is neither empty nor a vdbmap-sim
    /// sequence (no gt/sim.json): replacing it would delete someone's files.
    explicit StagedDir(std::filesystem::path final_dir);
    ~StagedDir();
    StagedDir(const StagedDir&) = delete;
    StagedDir& operator=(const StagedDir&) = delete;

    /// The folder to write into.
    const std::filesystem::path& path() const { return staging_; }
    /// Moves the staging folder to the final one (two renames when a previous sequence is
    /// replaced: old -> `.<name>.old-<pid>`, staging -> final, then the old one is deleted).
    void commit();

private:
    std::filesystem::path final_;
    std::filesystem::path staging_;
    bool committed_ = false;
};

}  // namespace vdbmap::sim
