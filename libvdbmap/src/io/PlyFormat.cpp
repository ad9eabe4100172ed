// SPDX-License-Identifier: Apache-2.0
#include "io/PlyFormat.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "io/FileUtil.h"
#include "vdbmap/Error.h"

namespace vdbmap::detail {
namespace {

bool parseType(const std::string& name, PlyType& type) {
    static const struct {
        const char* name;
        PlyType type;
    } kTypes[] = {
        {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
        {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
        {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
        {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
        {"float64", PlyType::Float64}};
    for (const auto& t : kTypes) {
        if (name == t.name) {
            type = t.type;
            return true;
        }
    }
    return false;
}

std::size_t typeSize(PlyType type) {
    switch (type) {
        case PlyType::Int8:
        case PlyType::UInt8:
            return 1;
        case PlyType::Int16:
        case PlyType::UInt16:
            return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32:
            return 4;
        case PlyType::Float64:
            return 8;
    }
    return 0;
}

template <typename T>
double load(const char* p, bool swap) {
    char buffer[sizeof(T)];
    std::memcpy(buffer, p, sizeof(T));
    if (swap) std::reverse(buffer, buffer + sizeof(T));
    T v;
    std::memcpy(&v, buffer, sizeof(T));
    return static_cast<double>(v);
}

}  // namespace

int PlyElement::find(const std::string& property_name) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
        if (properties[i].name == property_name) return static_cast<int>(i);
    }
    return -1;
}

int PlyHeader::find(const std::string& element_name) const {
    for (std::size_t i = 0; i < elements.size(); ++i) {
        if (elements[i].name == element_name) return static_cast<int>(i);
    }
    return -1;
}

PlyHeader parsePlyHeader(const std::string& bytes, const std::filesystem::path& path) {
    PlyHeader header;
    std::size_t pos = 0;
    std::size_t line_number = 0;
    bool have_format = false;
    while (true) {
        const std::size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) {
            throw IoError(path.string() + ": PLY header has no 'end_header' line");
        }
        const std::string line(trim(std::string_view(bytes).substr(pos, end - pos)));
        pos = end + 1;
        ++line_number;
        const auto fail = [&](const std::string& why) {
            return IoError(fileLine(path, line_number) + ": corrupt PLY header line '" + line +
                           "': " + why);
        };
        const std::vector<std::string> tok = splitWhitespace(line);
        if (line_number == 1) {
            if (line != "ply") throw fail("not a PLY file (first line must be 'ply')");
            continue;
        }
        if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
        if (tok[0] == "end_header") break;
        if (tok[0] == "format") {
            if (tok.size() != 3) throw fail("expected 'format <type> 1.0'");
            if (tok[1] == "ascii") {
                header.format = PlyHeader::Format::Ascii;
            } else if (tok[1] == "binary_little_endian") {
                header.format = PlyHeader::Format::BinaryLittleEndian;
            } else if (tok[1] == "binary_big_endian") {
                header.format = PlyHeader::Format::BinaryBigEndian;
            } else {
                throw fail("unknown format '" + tok[1] + "'");
            }
            have_format = true;
        } else if (tok[0] == "element") {
            double count = 0;
            // NaN and values past 2^50 are refused before the cast (UB otherwise).
            if (tok.size() != 3 || !parseDouble(tok[2], count) || !(count >= 0) ||
                count > 1e15 || count != std::floor(count)) {
                throw fail("expected 'element <name> <count>'");
            }
            PlyElement element;
            element.name = tok[1];
            element.count = static_cast<std::size_t>(count);
            header.elements.push_back(element);
        } else if (tok[0] == "property") {
            if (header.elements.empty()) throw fail("property before any element");
            PlyProperty property;
            if (tok.size() == 5 && tok[1] == "list") {
                property.is_list = true;
                if (!parseType(tok[2], property.count_type) || !parseType(tok[3], property.type)) {
                    throw fail("unknown list type");
                }
                property.name = tok[4];
            } else if (tok.size() == 3) {
                if (!parseType(tok[1], property.type)) throw fail("unknown type '" + tok[1] + "'");
                property.name = tok[2];
            } else {
                throw fail("expected 'property <type> <name>' or 'property list <t> <t> <name>'");
            }
            header.elements.back().properties.push_back(property);
        } else {
            throw fail("unknown keyword '" + tok[0] + "'");
        }
    }
    if (!have_format) throw IoError(path.string() + ": PLY header has no 'format' line");
    for (const PlyElement& element : header.elements) {
        // An instance without properties reads no bytes: a huge count would only spin.
        if (element.properties.empty() && element.count > 0) {
            throw IoError(path.string() + ": PLY element '" + element.name + "' has " +
                          std::to_string(element.count) + " instances but no properties");
        }
    }
    header.data_offset = pos;
    return header;
}

PlyDataReader::PlyDataReader(const std::string& bytes, const PlyHeader& header,
                             const std::filesystem::path& path)
    : bytes_(bytes), header_(header), path_(path), pos_(header.data_offset) {}

double PlyDataReader::value(PlyType type) {
    if (header_.format == PlyHeader::Format::Ascii) {
        while (pos_ < bytes_.size() && std::strchr(" \t\r\n", bytes_[pos_]) != nullptr) ++pos_;
        std::size_t end = pos_;
        while (end < bytes_.size() && std::strchr(" \t\r\n", bytes_[end]) == nullptr) ++end;
        double v = 0.0;
        if (end == pos_ || !parseDouble(std::string_view(bytes_).substr(pos_, end - pos_), v)) {
            throw IoError(path_.string() + ": PLY ascii data ends early or has a bad number at " +
                          "instance " + std::to_string(instances_read_));
        }
        pos_ = end;
        return v;
    }
    const std::size_t size = typeSize(type);
    if (pos_ + size > bytes_.size()) {
        throw IoError(path_.string() + ": PLY binary data is truncated (file has " +
                      std::to_string(bytes_.size()) + " bytes) at element instance " +
                      std::to_string(instances_read_));
    }
    const char* p = bytes_.data() + pos_;
    pos_ += size;
    const bool swap = header_.format == PlyHeader::Format::BinaryBigEndian;
    switch (type) {
        case PlyType::Int8:
            return load<std::int8_t>(p, swap);
        case PlyType::UInt8:
            return load<std::uint8_t>(p, swap);
        case PlyType::Int16:
            return load<std::int16_t>(p, swap);
        case PlyType::UInt16:
            return load<std::uint16_t>(p, swap);
        case PlyType::Int32:
            return load<std::int32_t>(p, swap);
        case PlyType::UInt32:
            return load<std::uint32_t>(p, swap);
        case PlyType::Float32:
            return load<float>(p, swap);
        case PlyType::Float64:
            return load<double>(p, swap);
    }
    return 0.0;
}

void PlyDataReader::read(const PlyElement& element, std::vector<double>& scalars,
                         std::vector<std::vector<double>>& lists) {
    scalars.clear();
    std::size_t list_index = 0;
    ++instances_read_;
    for (const PlyProperty& property : element.properties) {
        if (!property.is_list) {
            scalars.push_back(value(property.type));
            continue;
        }
        if (lists.size() <= list_index) lists.resize(list_index + 1);
        std::vector<double>& items = lists[list_index++];
        const double count = value(property.count_type);
        if (!(count >= 0 && count <= 1e6) || count != std::floor(count)) {
            throw IoError(path_.string() + ": PLY list '" + property.name + "' of element '" +
                          element.name + "' has an invalid length " + std::to_string(count));
        }
        items.resize(static_cast<std::size_t>(count));
        for (double& item : items) item = value(property.type);
    }
}

}  // namespace vdbmap::detail
