// SPDX-License-Identifier: Apache-2.0
// readGlb: reads back what writeGlb wrote (tests, and the parents of the levels of detail).
#include <cstring>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "Glb.h"
#include "vdbmap/Error.h"

namespace vdbmap::tiles3d {
namespace {

using json = nlohmann::json;

std::uint32_t get32(const std::string& s, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}

class Reader {
public:
    Reader(const std::string& bytes, const std::string& what) : what_(what) {
        if (bytes.size() < 20 || get32(bytes, 0) != 0x46546C67u || get32(bytes, 4) != 2) {
            fail("not a glTF 2.0 binary (GLB)");
        }
        const std::uint32_t json_len = get32(bytes, 12);
        if (get32(bytes, 16) != 0x4E4F534Au || 20ull + json_len > bytes.size()) fail("bad JSON chunk");
        try {
            gltf = json::parse(bytes.substr(20, json_len));
        } catch (const std::exception& e) {
            fail(std::string("bad JSON: ") + e.what());
        }
        const std::size_t bin_at = 20 + json_len;
        if (bin_at + 8 <= bytes.size()) {
            const std::uint32_t bin_len = get32(bytes, bin_at);
            if (get32(bytes, bin_at + 4) != 0x004E4942u || bin_at + 8 + bin_len > bytes.size()) {
                fail("bad BIN chunk");
            }
            bin_ = bytes.substr(bin_at + 8, bin_len);
        }
    }

    [[noreturn]] void fail(const std::string& m) const {
        throw InvalidInput(what_ + ": " + m);
    }

    /// The bytes of bufferView `index` (decoded when meshopt-compressed).
    std::string view(std::size_t index) {
        const json& v = gltf.at("bufferViews").at(index);
        if (v.contains("extensions") && v["extensions"].contains("EXT_meshopt_compression")) {
            meshopt = true;
            const json& m = v["extensions"]["EXT_meshopt_compression"];
            const std::size_t count = m.at("count"), stride = m.at("byteStride");
            const std::size_t at = m.value("byteOffset", 0), len = m.at("byteLength");
            if (m.at("buffer").get<int>() != 0 || at + len > bin_.size()) fail("bad meshopt view");
            if (m.at("mode") != "ATTRIBUTES") fail("meshopt mode other than ATTRIBUTES");
            std::string out(count * stride, '\0');
            if (meshopt_decodeVertexBuffer(out.data(), count, stride,
                                           reinterpret_cast<const unsigned char*>(bin_.data()) + at,
                                           len) != 0) {
                fail("meshopt vertex data does not decode (bufferView " + std::to_string(index) + ")");
            }
            return out;
        }
        if (v.at("buffer").get<int>() != 0) fail("bufferView outside the binary chunk");
        const std::size_t at = v.value("byteOffset", 0), len = v.at("byteLength");
        if (at + len > bin_.size()) fail("bufferView past the binary chunk");
        return bin_.substr(at, len);
    }

    /// Accessor `index` as floats (FLOAT components only).
    std::vector<float> floats(std::size_t index, int components) {
        const json& a = gltf.at("accessors").at(index);
        if (a.at("componentType").get<int>() != 5126) fail("accessor " + std::to_string(index) + " is not FLOAT");
        const std::size_t count = a.at("count");
        const std::string data = view(a.at("bufferView"));
        const std::size_t need = count * static_cast<std::size_t>(components) * 4;
        if (data.size() < a.value("byteOffset", 0u) + need) fail("accessor " + std::to_string(index) + " too short");
        std::vector<float> out(count * static_cast<std::size_t>(components));
        std::memcpy(out.data(), data.data() + a.value("byteOffset", 0u), need);
        return out;
    }

    json gltf;
    bool meshopt = false;

private:
    std::string what_;
    std::string bin_;
};

}  // namespace

TileMesh readGlb(const std::string& bytes, const std::string& what, GlbInfo* info) {
    Reader r(bytes, what);
    const json& g = r.gltf;
    TileMesh mesh;
    try {
        const json& node = g.at("nodes").at(0);
        if (node.contains("translation")) {
            const auto t = node["translation"].get<std::vector<double>>();
            mesh.origin_W = wFromGltf({t.at(0), t.at(1), t.at(2)});
        }
        // Images -> pages; material -> page.
        std::vector<std::string> mimes;
        if (g.contains("images")) {
            for (const json& image : g["images"]) {
                const std::string data = r.view(image.at("bufferView"));
                cv::Mat page = cv::imdecode(cv::Mat(1, static_cast<int>(data.size()), CV_8UC1,
                                                    const_cast<char*>(data.data())),
                                            cv::IMREAD_COLOR);
                if (page.empty()) r.fail("an image does not decode");
                mesh.pages.push_back(page);
                mimes.push_back(image.value("mimeType", ""));
            }
        }
        const json& meta = g.at("extensions").at("EXT_structural_metadata");
        const json& tables = meta.at("propertyTables");
        const std::size_t n = tables.at(0).at("count");
        mesh.corners.resize(n);
        mesh.page.assign(n, kNoPage);
        std::vector<bool> seen(n, false);
        bool textured = false;
        for (const json& prim : g.at("meshes").at(0).at("primitives")) {
            const json& attr = prim.at("attributes");
            const std::vector<float> pos = r.floats(attr.at("POSITION"), 3);
            const std::vector<float> ids = r.floats(attr.at("_FEATURE_ID_0"), 1);
            std::vector<float> uv;
            std::uint32_t page = kNoPage;
            const json& material = g.at("materials").at(prim.at("material").get<std::size_t>());
            const json& pbr = material.at("pbrMetallicRoughness");
            if (pbr.contains("baseColorTexture")) {
                const std::size_t tex = pbr["baseColorTexture"].at("index");
                page = g.at("textures").at(tex).at("source");
                uv = r.floats(attr.at("TEXCOORD_0"), 2);
                if (!textured) mesh.uvs.resize(n);
                textured = true;
            }
            if (pos.size() % 9 != 0 || ids.size() * 3 != pos.size()) r.fail("primitive sizes disagree");
            for (std::size_t v = 0; v < ids.size(); v += 3) {
                const auto f = static_cast<std::size_t>(ids[v]);
                if (f >= n || ids[v + 1] != ids[v] || ids[v + 2] != ids[v] || seen[f]) {
                    r.fail("feature ids are not one new face per triangle");
                }
                seen[f] = true;
                mesh.page[f] = page;
                for (std::size_t k = 0; k < 3; ++k) {
                    const float* p = &pos[3 * (v + k)];
                    mesh.corners[f][k] = Eigen::Vector3f(p[0], -p[2], p[1]);
                    if (page != kNoPage) mesh.uvs[f][k] = Eigen::Vector2f(uv[2 * (v + k)], uv[2 * (v + k) + 1]);
                }
            }
        }
        for (std::size_t f = 0; f < n; ++f) {
            if (!seen[f]) r.fail("face " + std::to_string(f) + " of the property table has no triangle");
        }
        const json& fp = tables.at(0).at("properties");
        const std::string labels = r.view(fp.at("class_id").at("values"));
        const std::string conf = r.view(fp.at("confidence").at("values"));
        if (labels.size() != n || conf.size() != 4 * n) r.fail("property table sizes disagree");
        mesh.label.assign(labels.begin(), labels.end());
        mesh.confidence.resize(n);
        std::memcpy(mesh.confidence.data(), conf.data(), 4 * n);
        if (info) {
            const json& cp = tables.at(1).at("properties");
            const std::size_t m = tables.at(1).at("count");
            const std::string ids = r.view(cp.at("class_id").at("values"));
            const std::string colors = r.view(cp.at("color").at("values"));
            const std::string names = r.view(cp.at("name").at("values"));
            const std::string off = r.view(cp.at("name").at("stringOffsets"));
            if (ids.size() != m || colors.size() != 3 * m || off.size() != 4 * (m + 1)) {
                r.fail("class table sizes disagree");
            }
            info->classes.clear();
            for (std::size_t i = 0; i < m; ++i) {
                ClassInfo c;
                c.id = static_cast<std::uint8_t>(ids[i]);
                for (std::size_t k = 0; k < 3; ++k) c.rgb[k] = static_cast<std::uint8_t>(colors[3 * i + k]);
                const std::uint32_t a = get32(off, 4 * i), b = get32(off, 4 * i + 4);
                if (a > b || b > names.size()) r.fail("bad string offsets");
                c.name = names.substr(a, b - a);
                info->classes.push_back(c);
            }
            info->image_mime_types = mimes;
            info->meshopt = r.meshopt;
        }
    } catch (const nlohmann::json::exception& e) {
        r.fail(std::string("unexpected glTF layout: ") + e.what());
    }
    return mesh;
}

}  // namespace vdbmap::tiles3d
