// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace vdbmap::detail {

/// Whole file as bytes. Throws IoError naming the file if it is missing or unreadable.
std::string readWholeFile(const std::filesystem::path& path);

/// A file opened for binary reading with readWholeFile's checks and errors. `size_bytes` is
/// its size if it is a regular file with a non-zero size (else 0: read it as a stream).
struct OpenFile {
    std::ifstream in;
    std::uintmax_t size_bytes = 0;
};
OpenFile openForReading(const std::filesystem::path& path);
/// The rest of an open file (readWholeFile's reading). `path` names it in errors.
std::string readAll(OpenFile& file, const std::filesystem::path& path);

/// Splits on spaces, tabs and carriage returns (CRLF files).
std::vector<std::string> splitWhitespace(std::string_view text);

/// Strips leading and trailing whitespace.
std::string_view trim(std::string_view text);

/// Parses a complete token as a double ("nan" and "inf" accepted). False if any character is
/// left over or the token is empty.
bool parseDouble(std::string_view token, double& value);

/// Parses every token as a double. False on the first token that is not a number.
bool parseDoubles(const std::vector<std::string>& tokens, std::size_t first,
                  std::vector<double>& values);

/// "path:line": the prefix of every line-level error message.
std::string fileLine(const std::filesystem::path& path, std::size_t line_number);

/// One line of a text file being parsed: its 1-based number, its text, its tokens
/// (splitWhitespace).
struct TextLine {
    std::size_t number = 0;
    std::string text;
    std::vector<std::string> tokens;
};

/// Calls `fn` for every line of the file (read whole: IoError naming it if missing).
void forEachLine(const std::filesystem::path& path, const std::function<void(const TextLine&)>& fn);

/// "path:line: why: '<line text, at most 120 characters>'", the message of a line-level
/// IoError.
std::string lineMessage(const std::filesystem::path& path, const TextLine& line,
                        const std::string& why);

/// Opens a binary output stream on an AtomicFile's temporary path. Throws IoError.
std::ofstream openOutput(const std::filesystem::path& temp_path,
                         const std::filesystem::path& final_path);

/// Flushes and closes a stream written by openOutput. Throws IoError on a write error (disk full).
void closeOutput(std::ofstream& stream, const std::filesystem::path& final_path);

}  // namespace vdbmap::detail
