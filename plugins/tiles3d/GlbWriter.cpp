// SPDX-License-Identifier: Apache-2.0
// writeGlb: the tile as binary glTF with EXT_mesh_features, EXT_structural_metadata and
// (optionally) EXT_meshopt_compression, written directly with nlohmann-json (docs/tiles3d.md).
#include <algorithm>
#include <cstring>
#include <map>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "Glb.h"
#include "vdbmap/Error.h"

namespace vdbmap::tiles3d {
namespace {

using json = nlohmann::json;

constexpr int kFloat = 5126;
constexpr int kArrayBuffer = 34962;

/// The GLB's binary chunk and (with meshopt) the fallback buffer's layout.
class Buffers {
public:
    explicit Buffers(bool meshopt) : meshopt_(meshopt) {}

    /// A plain bufferView in the binary chunk (images, property tables), aligned to 8.
    int addRaw(const void* data, std::size_t bytes, json& views) {
        align(bin_, 8);
        json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
        append(bin_, data, bytes);
        views.push_back(v);
        return static_cast<int>(views.size()) - 1;
    }

    /// A vertex attribute bufferView (`count` elements of `stride` bytes): meshopt-encoded
    /// into the binary chunk, its uncompressed view in the fallback buffer; or plain.
    int addVertices(const void* data, std::size_t count, std::size_t stride, json& views) {
        if (!meshopt_) {
            const int index = addRaw(data, count * stride, views);
            views[static_cast<std::size_t>(index)]["byteStride"] = stride;
            views[static_cast<std::size_t>(index)]["target"] = kArrayBuffer;
            return index;
        }
        std::vector<unsigned char> encoded(meshopt_encodeVertexBufferBound(count, stride));
        encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), data, count, stride));
        align(bin_, 8);
        const std::size_t offset = bin_.size();
        append(bin_, encoded.data(), encoded.size());
        fallback_ = (fallback_ + 7) / 8 * 8;
        json v = {{"buffer", 1},
                  {"byteOffset", fallback_},
                  {"byteLength", count * stride},
                  {"byteStride", stride},
                  {"target", kArrayBuffer},
                  {"extensions",
                   {{"EXT_meshopt_compression",
                     {{"buffer", 0},
                      {"byteOffset", offset},
                      {"byteLength", encoded.size()},
                      {"byteStride", stride},
                      {"count", count},
                      {"mode", "ATTRIBUTES"}}}}}};
        fallback_ += count * stride;
        views.push_back(v);
        return static_cast<int>(views.size()) - 1;
    }

    json buffersJson() {
        align(bin_, 4);
        json buffers = json::array({{{"byteLength", bin_.size()}}});
        if (meshopt_) {
            buffers.push_back({{"byteLength", std::max<std::size_t>(fallback_, 4)},
                               {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
        }
        return buffers;
    }
    const std::vector<unsigned char>& bin() const { return bin_; }

private:
    static void align(std::vector<unsigned char>& b, std::size_t a) {
        while (b.size() % a != 0) b.push_back(0);
    }
    static void append(std::vector<unsigned char>& b, const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        b.insert(b.end(), p, p + bytes);
    }
    bool meshopt_;
    std::vector<unsigned char> bin_;
    std::size_t fallback_ = 0;
};

void put32(std::string& out, std::uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);
    out.append(b, 4);
}

}  // namespace

std::string writeGlb(const TileMesh& mesh, const std::vector<ClassInfo>& classes,
                     const GlbOptions& options) {
    mesh.check();
    const std::size_t n = mesh.faces();
    std::array<int, 256> class_row;
    class_row.fill(-1);
    for (std::size_t i = 0; i < classes.size(); ++i) class_row[classes[i].id] = static_cast<int>(i);
    for (std::size_t f = 0; f < n; ++f) {
        if (class_row[mesh.label[f]] < 0) {
            throw InvalidInput("GLB: face " + std::to_string(f) + " has class " +
                               std::to_string(mesh.label[f]) + ", which is not in the class table");
        }
    }

    Buffers buffers(options.meshopt);
    json views = json::array();
    json accessors = json::array();
    json gltf;
    gltf["asset"] = {{"version", "2.0"}, {"generator", "vdbmap export.3dtiles"}};
    json used = json::array({"EXT_mesh_features", "EXT_structural_metadata"});
    if (options.meshopt) {
        used.push_back("EXT_meshopt_compression");
        gltf["extensionsRequired"] = json::array({"EXT_meshopt_compression"});
    }
    gltf["extensionsUsed"] = used;

    // Images, textures, materials: one per atlas page, plus one untextured material.
    json images = json::array(), textures = json::array(), materials = json::array();
    for (std::size_t k = 0; k < mesh.pages.size(); ++k) {
        std::vector<unsigned char> encoded;
        const std::vector<int> params =
            options.jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality}
                         : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 6};
        if (!cv::imencode(options.jpeg ? ".jpg" : ".png", mesh.pages[k], encoded, params)) {
            throw Error("GLB: could not encode atlas page " + std::to_string(k));
        }
        const int view = buffers.addRaw(encoded.data(), encoded.size(), views);
        images.push_back({{"bufferView", view}, {"mimeType", options.jpeg ? "image/jpeg" : "image/png"}});
        textures.push_back({{"sampler", 0}, {"source", k}});
        materials.push_back({{"pbrMetallicRoughness",
                              {{"baseColorTexture", {{"index", k}}},
                               {"metallicFactor", 0.0},
                               {"roughnessFactor", 1.0}}},
                             {"doubleSided", true}});
    }
    const std::size_t untextured_material = materials.size();
    if (std::find(mesh.page.begin(), mesh.page.end(), kNoPage) != mesh.page.end()) {
        materials.push_back({{"pbrMetallicRoughness",
                          {{"baseColorFactor", {0.6, 0.6, 0.6, 1.0}},
                           {"metallicFactor", 0.0},
                               {"roughnessFactor", 1.0}}},
                             {"doubleSided", true}});
    }

    // Primitives: the faces of each page, in face order; untextured faces last.
    std::map<std::uint32_t, std::vector<std::uint32_t>> by_page;
    for (std::size_t f = 0; f < n; ++f) by_page[mesh.page[f]].push_back(static_cast<std::uint32_t>(f));
    json primitives = json::array();
    for (const auto& [page, faces] : by_page) {
        const std::size_t count = 3 * faces.size();
        std::vector<float> positions(3 * count), uvs, face_ids(count), class_ids(count);
        if (page != kNoPage) uvs.resize(2 * count);
        Eigen::Vector3f lo = Eigen::Vector3f::Constant(3e38f), hi = -lo;
        for (std::size_t i = 0; i < faces.size(); ++i) {
            const std::uint32_t f = faces[i];
            for (std::size_t k = 0; k < 3; ++k) {
                const Eigen::Vector3f& c = mesh.corners[f][k];
                const Eigen::Vector3f g(c.x(), c.z(), -c.y());
                const std::size_t v = 3 * i + k;
                for (int a = 0; a < 3; ++a) positions[3 * v + static_cast<std::size_t>(a)] = g[a];
                lo = lo.cwiseMin(g);
                hi = hi.cwiseMax(g);
                if (page != kNoPage) {
                    uvs[2 * v] = mesh.uvs[f][k].x();
                    uvs[2 * v + 1] = mesh.uvs[f][k].y();
                }
                face_ids[v] = static_cast<float>(f);
                class_ids[v] = static_cast<float>(class_row[mesh.label[f]]);
            }
        }
        json attributes;
        accessors.push_back({{"bufferView", buffers.addVertices(positions.data(), count, 12, views)},
                             {"componentType", kFloat},
                             {"count", count},
                             {"type", "VEC3"},
                             {"min", {lo.x(), lo.y(), lo.z()}},
                             {"max", {hi.x(), hi.y(), hi.z()}}});
        attributes["POSITION"] = accessors.size() - 1;
        if (page != kNoPage) {
            accessors.push_back({{"bufferView", buffers.addVertices(uvs.data(), count, 8, views)},
                                 {"componentType", kFloat},
                                 {"count", count},
                                 {"type", "VEC2"}});
            attributes["TEXCOORD_0"] = accessors.size() - 1;
        }
        accessors.push_back({{"bufferView", buffers.addVertices(face_ids.data(), count, 4, views)},
                             {"componentType", kFloat},
                             {"count", count},
                             {"type", "SCALAR"}});
        attributes["_FEATURE_ID_0"] = accessors.size() - 1;
        accessors.push_back({{"bufferView", buffers.addVertices(class_ids.data(), count, 4, views)},
                             {"componentType", kFloat},
                             {"count", count},
                             {"type", "SCALAR"}});
        attributes["_FEATURE_ID_1"] = accessors.size() - 1;
        std::vector<bool> seen(classes.size(), false);
        std::size_t distinct = 0;
        for (const std::uint32_t f : faces) {
            const auto row = static_cast<std::size_t>(class_row[mesh.label[f]]);
            if (!seen[row]) { seen[row] = true; ++distinct; }
        }
        primitives.push_back(
            {{"attributes", attributes},
             {"mode", 4},
             {"material", page == kNoPage ? untextured_material : page},
             {"extensions",
              {{"EXT_mesh_features",
                {{"featureIds",
                  {{{"featureCount", faces.size()}, {"attribute", 0}, {"propertyTable", 0},
                    {"label", "face"}},
                   {{"featureCount", distinct}, {"attribute", 1}, {"propertyTable", 1},
                    {"label", "semantic_class"}}}}}}}}});
    }

    // Property tables: per face (class id, confidence), per class (id, name, colour).
    std::vector<std::uint8_t> face_class(mesh.label);
    const int face_class_view = buffers.addRaw(face_class.data(), face_class.size(), views);
    const int confidence_view = buffers.addRaw(mesh.confidence.data(), 4 * n, views);
    std::vector<std::uint8_t> ids, colors;
    std::string names;
    std::vector<std::uint32_t> offsets{0};
    for (const ClassInfo& c : classes) {
        ids.push_back(c.id);
        colors.insert(colors.end(), c.rgb.begin(), c.rgb.end());
        names += c.name;
        offsets.push_back(static_cast<std::uint32_t>(names.size()));
    }
    const int ids_view = buffers.addRaw(ids.data(), ids.size(), views);
    const int colors_view = buffers.addRaw(colors.data(), colors.size(), views);
    const int names_view = buffers.addRaw(names.data(), names.size(), views);
    const int offsets_view = buffers.addRaw(offsets.data(), 4 * offsets.size(), views);
    json schema = {
        {"id", "vdbmap"},
        {"classes",
         {{"face",
           {{"description", "One face of the map: its semantic class and the confidence of it"},
            {"properties",
             {{"class_id", {{"type", "SCALAR"}, {"componentType", "UINT8"},
                            {"description", "Class id (docs/DATA.md label set); 255 = unknown"}}},
              {"confidence", {{"type", "SCALAR"}, {"componentType", "FLOAT32"},
                              {"description", "Confidence of the class in [0, 1]"}}}}}}},
          {"semantic_class",
           {{"description", "A semantic class of the label set"},
            {"properties",
             {{"class_id", {{"type", "SCALAR"}, {"componentType", "UINT8"}}},
              {"name", {{"type", "STRING"}}},
              {"color", {{"type", "VEC3"}, {"componentType", "UINT8"},
                         {"description", "sRGB colour of the class"}}}}}}}}}};
    json tables = json::array(
        {{{"class", "face"},
          {"count", n},
          {"properties",
           {{"class_id", {{"values", face_class_view}}},
            {"confidence", {{"values", confidence_view}}}}}},
         {{"class", "semantic_class"},
          {"count", classes.size()},
          {"properties",
           {{"class_id", {{"values", ids_view}}},
            {"name", {{"values", names_view}, {"stringOffsets", offsets_view},
                      {"stringOffsetType", "UINT32"}}},
            {"color", {{"values", colors_view}}}}}}});
    gltf["extensions"] = {{"EXT_structural_metadata", {{"schema", schema}, {"propertyTables", tables}}}};

    const Eigen::Vector3d t = gltfFromW(mesh.origin_W);
    gltf["scene"] = 0;
    gltf["scenes"] = json::array({{{"nodes", {0}}}});
    gltf["nodes"] = json::array({{{"mesh", 0}, {"translation", {t.x(), t.y(), t.z()}}}});
    gltf["meshes"] = json::array({{{"primitives", primitives}}});
    gltf["materials"] = materials;
    if (!images.empty()) {
        gltf["images"] = images;
        gltf["textures"] = textures;
        gltf["samplers"] = json::array({{{"magFilter", 9729}, {"minFilter", 9987},
                                         {"wrapS", 33071}, {"wrapT", 33071}}});
    }
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = views;
    gltf["buffers"] = buffers.buffersJson();

    std::string text = gltf.dump();
    while (text.size() % 4 != 0) text.push_back(' ');
    const std::vector<unsigned char>& bin = buffers.bin();
    std::string out;
    out.reserve(28 + text.size() + bin.size());
    put32(out, 0x46546C67u);  // "glTF"
    put32(out, 2);
    put32(out, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    put32(out, static_cast<std::uint32_t>(text.size()));
    put32(out, 0x4E4F534Au);  // "JSON"
    out += text;
    put32(out, static_cast<std::uint32_t>(bin.size()));
    put32(out, 0x004E4942u);  // "BIN\0"
    out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    return out;
}

}  // namespace vdbmap::tiles3d
