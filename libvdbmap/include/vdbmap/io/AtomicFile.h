// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>
#include <string_view>

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

    /// The temporary file to write: `.<name>.tmp<pid>-<n><ext>` beside the final file.
    const std::filesystem::path& tempPath() const { return temp_path_; }
    /// The file that commit() creates or replaces.
    const std::filesystem::path& finalPath() const { return final_path_; }
    /// Renames the temporary file over the final one. Throws IoError if nothing was written
    /// or the rename fails. A second call is a no-op.
    void commit();

private:
    std::filesystem::path final_path_;
    std::filesystem::path temp_path_;
    bool committed_ = false;
};

/// Writes `content` to `path` through an AtomicFile. Throws IoError.
void writeFileAtomically(const std::filesystem::path& path, std::string_view content);

}  // namespace vdbmap
