// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <filesystem>

namespace vdbmap {

/// An exclusive lock on an output folder for the life of the object: `<dir>/.vdbmap.lock`,
/// held with flock(2), so the kernel releases it when the process ends in any way (also
/// SIGKILL: no stale lock). A second run on the same folder is refused with IoError naming
/// the folder, the lock file and the pid that holds it. While it holds the lock, the owner
/// is the only writer in the folder, so the constructor also deletes the temporary files
/// (`.<name>.tmp<pid>-<n>...`, see AtomicFile) that a killed run left behind.
class OutputLock {
public:
    explicit OutputLock(const std::filesystem::path& dir);
    ~OutputLock();
    OutputLock(const OutputLock&) = delete;
    OutputLock& operator=(const OutputLock&) = delete;

    const std::filesystem::path& lockFile() const { return lock_file_; }
    /// Number of stale temporary files the constructor deleted.
    std::size_t staleFilesRemoved() const { return stale_removed_; }

private:
    std::filesystem::path lock_file_;
    int fd_ = -1;
    std::size_t stale_removed_ = 0;
};

}  // namespace vdbmap
