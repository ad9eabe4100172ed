// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

namespace vdbmap {

/// Write-then-rename: the writer writes `tempPath()` (same folder, unique name) and calls
/// `commit()`, which renames it over `finalPath()`. If commit() is never reached (an
/// exception), the destructor deletes the temporary file, so a failed run never leaves a
/// half-written output. Creates the parent folder. Throws IoError.
class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path final_path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    const std::filesystem::path& tempPath() const { return temp_path_; }
    const std::filesystem::path& finalPath() const { return final_path_; }
    void commit();

private:
    std::filesystem::path final_path_;
    std::filesystem::path temp_path_;
    bool committed_ = false;
};

}  // namespace vdbmap
