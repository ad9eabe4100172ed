// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace vdbmap::detail {

/// PLY scalar types (both the "char"/"uchar"... and "int8"/"uint8"... spellings map here).
enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// One property of a PLY element: a scalar, or a list with its own count type.
struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;  ///< value type (list items for a list)
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;  ///< lists only
};

/// One element ("vertex", "face", ...) with its instance count and properties.
struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> properties;

    /// Index of the property called `name`, or -1.
    int find(const std::string& name) const;
};

/// A parsed PLY header and where the data starts.
struct PlyHeader {
    enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };
    Format format = Format::Ascii;
    std::vector<PlyElement> elements;
    std::size_t data_offset = 0;  ///< first byte after "end_header\n"

    /// Index of the element called `name`, or -1.
    int find(const std::string& name) const;
};

/// Parses the header of a PLY file held in `bytes`. Throws IoError naming `path`, the header
/// line and the problem.
PlyHeader parsePlyHeader(const std::string& bytes, const std::filesystem::path& path);

/// Sequential reader of the element data that follows the header, in file order.
class PlyDataReader {
public:
    /// `bytes` and `header` must outlive the reader.
    PlyDataReader(const std::string& bytes, const PlyHeader& header,
                  const std::filesystem::path& path);

    /// Reads the next instance of `element`: one value per scalar property into `scalars`
    /// (property order, lists skipped) and each list property's items into `lists` (in the
    /// order of the list properties). Throws IoError naming the file on truncated or
    /// malformed data.
    void read(const PlyElement& element, std::vector<double>& scalars,
              std::vector<std::vector<double>>& lists);

private:
    double value(PlyType type);

    const std::string& bytes_;
    const PlyHeader& header_;
    std::filesystem::path path_;
    std::size_t pos_;
    std::size_t instances_read_ = 0;  // for error messages (1-based count over all elements)
};

}  // namespace vdbmap::detail
