// SPDX-License-Identifier: Apache-2.0
#include "io/FileUtil.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "vdbmap/Error.h"

namespace vdbmap::detail {

OpenFile openForReading(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        throw IoError("file not found: " + path.string());
    }
    if (std::filesystem::is_directory(path, ec)) {
        throw IoError("expected a file, found a folder: " + path.string());
    }
    OpenFile file;
    file.in.open(path, std::ios::binary);
    if (!file.in) {
        throw IoError("cannot open " + path.string() + ": " + std::strerror(errno));
    }
    // Other files (a pipe, /proc) have no size.
    if (std::filesystem::is_regular_file(path, ec)) {
        const std::uintmax_t size = std::filesystem::file_size(path, ec);
        if (!ec) file.size_bytes = size;
    }
    return file;
}

std::string readWholeFile(const std::filesystem::path& path) {
    OpenFile file = openForReading(path);
    return readAll(file, path);
}

std::string readAll(OpenFile& file, const std::filesystem::path& path) {
    std::ifstream& in = file.in;
    // A regular file: one read of its size (a 2 MB scan through a growing string buffer cost
    // several copies of it); anything else as a stream.
    if (file.size_bytes > 0) {
        std::string bytes(static_cast<std::size_t>(file.size_bytes), '\0');
        in.read(bytes.data(), static_cast<std::streamsize>(file.size_bytes));
        if (in.bad()) {
            throw IoError("read error in " + path.string());
        }
        bytes.resize(static_cast<std::size_t>(in.gcount()));  // the file shrank meanwhile
        return bytes;
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) {
        throw IoError("read error in " + path.string());
    }
    return buffer.str();
}

std::vector<std::string> splitWhitespace(std::string_view text) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (i < text.size()) {
        while (i < text.size() && is_space(text[i])) ++i;
        std::size_t j = i;
        while (j < text.size() && !is_space(text[j])) ++j;
        if (j > i) tokens.emplace_back(text.substr(i, j - i));
        i = j;
    }
    return tokens;
}

std::string_view trim(std::string_view text) {
    const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
    while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
    return text;
}

bool parseDouble(std::string_view token, double& value) {
    if (token.empty()) return false;
    const std::string copy(token);  // strtod needs a terminated string
    char* end = nullptr;
    errno = 0;
    value = std::strtod(copy.c_str(), &end);
    return end == copy.c_str() + copy.size() && errno != ERANGE;
}

bool parseDoubles(const std::vector<std::string>& tokens, std::size_t first,
                  std::vector<double>& values) {
    values.clear();
    for (std::size_t i = first; i < tokens.size(); ++i) {
        double v = 0.0;
        if (!parseDouble(tokens[i], v)) return false;
        values.push_back(v);
    }
    return true;
}

std::string fileLine(const std::filesystem::path& path, std::size_t line_number) {
    return path.string() + ":" + std::to_string(line_number);
}

void forEachLine(const std::filesystem::path& path, const std::function<void(const TextLine&)>& fn) {
    std::istringstream lines(readWholeFile(path));
    TextLine line;
    while (std::getline(lines, line.text)) {
        ++line.number;
        line.tokens = splitWhitespace(line.text);
        fn(line);
    }
}

std::string lineMessage(const std::filesystem::path& path, const TextLine& line,
                        const std::string& why) {
    return fileLine(path, line.number) + ": " + why + ": '" + line.text.substr(0, 120) + "'";
}

std::ofstream openOutput(const std::filesystem::path& temp_path,
                         const std::filesystem::path& final_path) {
    std::ofstream out(temp_path, std::ios::binary | std::ios::trunc);
    if (!out) {
        throw IoError("cannot write " + final_path.string() + " (temporary " +
                      temp_path.filename().string() + "): " + std::strerror(errno));
    }
    return out;
}

void closeOutput(std::ofstream& stream, const std::filesystem::path& final_path) {
    // errno of the failed write(2) (ENOSPC, EFBIG, EIO...): a write before this call, or
    // the final flush.
    int err = stream.fail() ? errno : 0;
    if (!stream.fail()) {
        errno = 0;
        stream.flush();
        if (stream.fail()) err = errno;
    }
    stream.close();
    if (stream.fail()) {
        if (err == 0) err = errno;
        throw IoError("write error on " + final_path.string() + ": " +
                      (err != 0 ? std::string(std::strerror(err)) : std::string("disk full?")) +
                      " (nothing was written there)");
    }
}

}  // namespace vdbmap::detail
