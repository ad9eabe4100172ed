// SPDX-License-Identifier: Apache-2.0
#include "io/OutputLock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <regex>
#include <string>

#include "vdbmap/Error.h"

namespace vdbmap {
namespace fs = std::filesystem;
namespace {

std::string readHolder(int fd) {
    char buffer[64] = {};
    const ssize_t n = ::pread(fd, buffer, sizeof(buffer) - 1, 0);
    std::string text = n > 0 ? std::string(buffer, static_cast<std::size_t>(n)) : std::string();
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return text;
}

/// AtomicFile's temporary names: ".<name>.tmp<pid>-<counter><ext>".
std::size_t removeStaleTemporaries(const fs::path& dir) {
    static const std::regex kTemp(R"(^\..+\.tmp[0-9]+-[0-9]+.*$)");
    std::size_t removed = 0;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code type_ec;
        if (!it->is_regular_file(type_ec)) continue;
        if (!std::regex_match(it->path().filename().string(), kTemp)) continue;
        std::error_code rm_ec;
        if (fs::remove(it->path(), rm_ec)) ++removed;
    }
    return removed;
}

}  // namespace

OutputLock::OutputLock(const fs::path& dir) : lock_file_(dir / ".vdbmap.lock") {
    fd_ = ::open(lock_file_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        throw IoError("cannot create the lock file " + lock_file_.string() + ": " +
                      std::strerror(errno));
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const int err = errno;
        const std::string holder = readHolder(fd_);
        ::close(fd_);
        fd_ = -1;
        if (err == EWOULDBLOCK) {
            throw IoError("output folder " + dir.string() + " is in use by another vdbmap run" +
                          (holder.empty() ? std::string() : " (pid " + holder + ")") +
                          ": lock file " + lock_file_.string() +
                          " is held; wait for it to finish or use another output folder (-o)");
        }
        throw IoError("cannot lock " + lock_file_.string() + ": " + std::strerror(err));
    }
    const std::string pid = std::to_string(::getpid()) + "\n";
    if (::ftruncate(fd_, 0) != 0 ||
        ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        // Only informational (the message of a refused second run); the lock itself holds.
    }
    stale_removed_ = removeStaleTemporaries(dir);
}

OutputLock::~OutputLock() {
    if (fd_ >= 0) ::close(fd_);  // releases the flock; the file stays (removing it would race)
}

}  // namespace vdbmap
