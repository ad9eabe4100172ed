// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/io/AtomicFile.h"

#include <unistd.h>

#include <atomic>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"

namespace vdbmap {

AtomicFile::AtomicFile(std::filesystem::path final_path) : final_path_(std::move(final_path)) {
    if (final_path_.empty() || !final_path_.has_filename()) {
        throw InvalidInput("AtomicFile: output path '" + final_path_.string() +
                           "' has no file name");
    }
    const std::filesystem::path parent = final_path_.parent_path();
    if (!parent.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(parent, ec);
        if (ec) {
            throw IoError("cannot create folder " + parent.string() + " for " +
                          final_path_.string() + ": " + ec.message());
        }
    }
    // Unique per process and per object; same folder, so the final rename is atomic. The
    // extension is kept last so that writers which pick a format by extension still work.
    static std::atomic<unsigned> counter{0};
    const std::string unique = std::to_string(::getpid()) + "-" + std::to_string(counter++);
    temp_path_ = parent / ("." + final_path_.filename().string() + ".tmp" + unique +
                           final_path_.extension().string());
}

AtomicFile::~AtomicFile() {
    if (!committed_) {
        std::error_code ec;  // never throw from a destructor
        std::filesystem::remove(temp_path_, ec);
    }
}

void AtomicFile::commit() {
    if (committed_) return;
    std::error_code ec;
    if (!std::filesystem::exists(temp_path_, ec)) {
        throw IoError("nothing was written for " + final_path_.string() + " (temporary " +
                      temp_path_.string() + " missing)");
    }
    std::filesystem::rename(temp_path_, final_path_, ec);
    if (ec) {
        throw IoError("cannot rename " + temp_path_.string() + " to " + final_path_.string() +
                      ": " + ec.message());
    }
    committed_ = true;
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view content) {
    AtomicFile file(path);
    std::ofstream out = detail::openOutput(file.tempPath(), path);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    detail::closeOutput(out, path);
    file.commit();
}

}  // namespace vdbmap
