// SPDX-License-Identifier: Apache-2.0
// The 3D Tiles writer's formats (issue 34): a GLB reads back to exactly the faces, classes,
// confidences, texture coordinates and (PNG) pixels written, with and without meshopt; a known
// point of W lands where it belongs through glTF's y-up and the tileset's z-up (the 3D Tiles
// rule, applied here independently of the reader); a parent's corners are its children's, and
// its measured error bounds its distance to the full mesh (dense brute-force oracle); the
// geo-reference puts W's origin on the WGS84 ellipsoid; the bake's charts partition the faces
// (a box is its six sides), its rasterization finds overlaps, and its page costs about the
// surface's texels, the same bytes for any thread count.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include <tbb/task_arena.h>

#include "Bake.h"
#include "Charts.h"
#include "Glb.h"
#include "Lod.h"
#include "MeshDistance.h"
#include "Tileset.h"

using namespace vdbmap::tiles3d;
using json = nlohmann::json;

namespace {

std::vector<ClassInfo> classTable() {
    return {{0, "road", {128, 64, 128}}, {1, "sidewalk", {244, 35, 232}}, {255, "unknown", {0, 0, 0}}};
}

/// A height field z = h(x, y) over [x0, x0 + size] x [y0, y0 + size], step `step`, each
/// triangle textured from a 64x64 page, classes by position.
TileMesh terrain(double x0, double y0, double size, double step, int pages, double height_amp = 0.3) {
    TileMesh m;
    m.origin_W = Eigen::Vector3d(std::round(x0 + size / 2), std::round(y0 + size / 2), 0);
    const int n = static_cast<int>(std::round(size / step));
    auto h = [&](double x, double y) { return height_amp * std::sin(0.7 * x) * std::cos(0.5 * y); };
    for (int p = 0; p < pages; ++p) {
        cv::Mat page(64, 64, CV_8UC3);
        for (int r = 0; r < 64; ++r)
            for (int c = 0; c < 64; ++c) page.at<cv::Vec3b>(r, c) = cv::Vec3b(uchar(r * 4), uchar(c * 4), uchar(p * 60));
        m.pages.push_back(page);
    }
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double xa = x0 + i * step, xb = xa + step, ya = y0 + j * step, yb = ya + step;
            const Eigen::Vector3d q[4] = {{xa, ya, h(xa, ya)}, {xb, ya, h(xb, ya)}, {xb, yb, h(xb, yb)}, {xa, yb, h(xa, yb)}};
            const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (const auto& t : tri) {
                std::array<Eigen::Vector3f, 3> c;
                std::array<Eigen::Vector2f, 3> uv;
                for (int k = 0; k < 3; ++k) {
                    c[static_cast<std::size_t>(k)] = (q[t[k]] - m.origin_W).cast<float>();
                    uv[static_cast<std::size_t>(k)] = Eigen::Vector2f(float((q[t[k]].x() - x0) / size), float((q[t[k]].y() - y0) / size));
                }
                m.corners.push_back(c);
                m.uvs.push_back(uv);
                const std::size_t f = m.corners.size() - 1;
                m.page.push_back(pages == 0 ? kNoPage : static_cast<std::uint32_t>(f % static_cast<std::size_t>(pages)));
                m.label.push_back(i < n / 2 ? 0 : (j < n / 3 ? 1 : 255));
                m.confidence.push_back(float(f % 97) / 97.0f);
            }
        }
    }
    if (pages == 0) m.uvs.clear();
    return m;
}

void requireSame(const TileMesh& a, const TileMesh& b, bool pixels) {
    REQUIRE(a.faces() == b.faces());
    REQUIRE(a.origin_W == b.origin_W);
    REQUIRE(a.pages.size() == b.pages.size());
    for (std::size_t f = 0; f < a.faces(); ++f) {
        for (std::size_t k = 0; k < 3; ++k) {
            REQUIRE(a.corners[f][k] == b.corners[f][k]);
            if (!a.uvs.empty() && a.page[f] != kNoPage) REQUIRE(a.uvs[f][k] == b.uvs[f][k]);
        }
        REQUIRE(a.label[f] == b.label[f]);
        REQUIRE(a.confidence[f] == b.confidence[f]);
        REQUIRE(a.page[f] == b.page[f]);
    }
    if (pixels) {
        for (std::size_t p = 0; p < a.pages.size(); ++p) REQUIRE(cv::norm(a.pages[p], b.pages[p], cv::NORM_INF) == 0);
    }
}

std::uint32_t u32(const std::string& s, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, s.data() + at, 4);
    return v;
}

}  // namespace

TEST_CASE("A GLB reads back to exactly what was written", "[tiles3d]") {
    TileMesh m = terrain(100, -50, 4, 0.25, 2);
    m.page[3] = kNoPage;  // one untextured face: a primitive of its own
    for (const bool meshopt : {true, false}) {
        GlbOptions o;
        o.jpeg = false;
        o.meshopt = meshopt;
        const std::string glb = writeGlb(m, classTable(), o);
        GlbInfo info;
        const TileMesh back = readGlb(glb, "test.glb", &info);
        requireSame(m, back, true);
        CHECK(info.meshopt == meshopt);
        REQUIRE(info.classes.size() == 3);
        CHECK(info.classes[1].name == "sidewalk");
        CHECK(info.classes[1].rgb == std::array<std::uint8_t, 3>{244, 35, 232});
        CHECK(writeGlb(m, classTable(), o) == glb);  // deterministic
    }
    // JPEG: the geometry exact, the pixels close.
    GlbOptions jpeg;
    const TileMesh back = readGlb(writeGlb(m, classTable(), jpeg), "jpeg.glb");
    requireSame(m, back, false);
    CHECK(cv::norm(m.pages[0], back.pages[0], cv::NORM_L1) / double(m.pages[0].total() * 3) < 4.0);
    // A class outside the table is an error naming the face.
    m.label[5] = 7;
    CHECK_THROWS_WITH(writeGlb(m, classTable(), jpeg), Catch::Contains("face 5 has class 7"));
}

TEST_CASE("A known point of W lands where it belongs (glTF y-up, tileset z-up)", "[tiles3d]") {
    TileMesh m;
    const Eigen::Vector3d p_W(1234.25, -2345.5, 31.125);
    m.origin_W = Eigen::Vector3d(1230, -2340, 30);
    m.corners.push_back({(p_W - m.origin_W).cast<float>(), Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 0)});
    m.label = {0};
    m.confidence = {1.0f};
    m.page = {kNoPage};
    GlbOptions o;
    o.meshopt = false;
    const std::string glb = writeGlb(m, classTable(), o);
    // Read the raw glTF: node translation + first POSITION, in glTF axes.
    const json g = json::parse(glb.substr(20, u32(glb, 12)));
    const std::string bin = glb.substr(20 + u32(glb, 12) + 8);
    const json& acc = g["accessors"][g["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
    const json& view = g["bufferViews"][acc["bufferView"].get<int>()];
    float pos[3];
    std::memcpy(pos, bin.data() + view.value("byteOffset", 0) + acc.value("byteOffset", 0), 12);
    const auto t = g["nodes"][0]["translation"].get<std::vector<double>>();
    const Eigen::Vector3d gltf(t[0] + pos[0], t[1] + pos[1], t[2] + pos[2]);
    // 3D Tiles: glTF y-up -> z-up by the fixed rotation (x, y, z) -> (x, -z, y).
    Eigen::Matrix3d y_up_to_z_up;
    y_up_to_z_up << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    const Eigen::Vector3d tileset_frame = y_up_to_z_up * gltf;
    // Root transform of a z-up W without geo-reference: identity.
    const Eigen::Matrix4d root = rootTransform(Georef{}, 2);
    CHECK(root.isIdentity(0));
    CHECK((tileset_frame - p_W).norm() < 1e-4);
    // Other up directions (KITTI's camera frame: -y): the root transform is a rotation that
    // turns W's up into the tileset's z.
    for (int axis = 0; axis < 3; ++axis) {
        for (const int sign : {1, -1}) {
            const Eigen::Matrix3d R = rootTransform(Georef{}, axis, sign).topLeftCorner<3, 3>();
            CHECK((R * (sign * Eigen::Vector3d::Unit(axis)) - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
            CHECK((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
            CHECK(std::abs(R.determinant() - 1) < 1e-12);
        }
    }
}

TEST_CASE("The geo-reference puts W's origin on the ellipsoid, W's axes east/north/up", "[tiles3d]") {
    // Closed forms: the equator at longitude 0 is (a, 0, 0); the north pole is (0, 0, b).
    CHECK((ecefFromGeodetic(0, 0, 0) - Eigen::Vector3d(6378137.0, 0, 0)).norm() < 1e-6);
    CHECK((ecefFromGeodetic(90, 0, 0) - Eigen::Vector3d(0, 0, 6356752.314245)).norm() < 1e-3);
    CHECK((ecefFromGeodetic(0, 90, 100) - Eigen::Vector3d(0, 6378237.0, 0)).norm() < 1e-6);
    Georef g;
    g.enabled = true;
    g.latitude_deg = 48.0;
    g.longitude_deg = 11.0;
    g.altitude_m = 500;
    const Eigen::Matrix4d T = rootTransform(g, 2);
    const Eigen::Vector3d origin = T.topRightCorner<3, 1>();
    CHECK((origin - ecefFromGeodetic(48, 11, 500)).norm() < 1e-6);
    // W's z is the ellipsoid normal; 10 m up along z is 10 m higher.
    const Eigen::Vector3d up = (T * Eigen::Vector4d(0, 0, 10, 1)).head<3>();
    CHECK((up - ecefFromGeodetic(48, 11, 510)).norm() < 1e-6);
    // Heading 90: W's y points east, so W's x points south.
    g.heading_deg = 90;
    const Eigen::Matrix4d H = rootTransform(g, 2);
    const Eigen::Vector3d east(-std::sin(11 * M_PI / 180), std::cos(11 * M_PI / 180), 0);
    CHECK((H.topLeftCorner<3, 3>() * Eigen::Vector3d::UnitY() - east).norm() < 1e-12);
}

TEST_CASE("A parent's corners are its children's; its measured error bounds its distance to them",
          "[tiles3d]") {
    const TileMesh a = terrain(0, 0, 4, 0.1, 1, 0.5), b = terrain(4, 0, 4, 0.1, 1, 0.5);
    ParentOptions po;
    po.level = 1;
    po.voxel_size_m = 0.1;
    ParentFigures fig;
    const TileMesh p = buildParent({&a, &b}, po, &fig);
    CHECK(fig.merged_faces == a.faces() + b.faces());
    CHECK(p.faces() < fig.merged_faces / 2);
    CHECK(p.faces() > 0);
    REQUIRE(p.pages.size() == 1);
    CHECK(fig.child_texel_m == Approx(4.0 / 64).epsilon(0.03));  // a 64-px page over 4 m (not flat)
    CHECK(fig.texel_m >= 2 * fig.child_texel_m * 0.999);          // the resolution halves
    std::set<std::array<long long, 3>> child_corners;
    auto key = [](const Eigen::Vector3d& v) {
        return std::array<long long, 3>{std::llround(v.x() * 1e4), std::llround(v.y() * 1e4), std::llround(v.z() * 1e4)};
    };
    for (const TileMesh* c : {&a, &b})
        for (std::size_t f = 0; f < c->faces(); ++f)
            for (int k = 0; k < 3; ++k) child_corners.insert(key(c->cornerW(f, k)));
    for (std::size_t f = 0; f < p.faces(); ++f)
        for (int k = 0; k < 3; ++k) REQUIRE(child_corners.count(key(p.cornerW(f, k))) == 1);

    std::vector<Triangle> full;
    for (const TileMesh* c : {&a, &b})
        for (const auto& t : trianglesW(*c)) full.push_back(t);
    const TriangleGrid grid(full);
    const double bound = hausdorffBound(trianglesW(p), grid, 0.01);
    // Oracle: dense random points on the parent, brute force over every full-res triangle.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0;
    const auto parent = trianglesW(p);
    for (int s = 0; s < 4000; ++s) {
        const Triangle& t = parent[rng() % parent.size()];
        double r1 = u(rng), r2 = u(rng);
        if (r1 + r2 > 1) { r1 = 1 - r1; r2 = 1 - r2; }
        const Eigen::Vector3d q = t[0] + r1 * (t[1] - t[0]) + r2 * (t[2] - t[0]);
        double best = 1e300;
        for (const Triangle& f : full) best = std::min(best, pointTriangleDistance(q, f));
        CHECK(std::abs(grid.distance(q) - best) < 1e-9);  // the grid query is exact
        worst = std::max(worst, best);
    }
    CHECK(worst <= bound);
    CHECK(bound < worst + 0.05);  // and not loose
    CHECK(bound > 0);
    // The bake's texel distances are distances from the parent: below the bound; starting
    // from the largest, the bound still holds.
    CHECK(fig.max_texel_distance_m > 0);
    CHECK(fig.max_texel_distance_m <= bound + 1e-12);
    const double from_known = hausdorffBound(trianglesW(p), grid, 0.01, nullptr, fig.max_texel_distance_m);
    CHECK(worst <= from_known);
    CHECK(from_known < worst + 0.05);
}

namespace {

/// A closed form for the bake test: the colour (BGR) of the point (x, y) of an 8 m x 4 m
/// plane: red = 255 x / 8, green = 255 y / 4, blue 100.
cv::Vec3d gradient(double x, double y) { return {100.0, 255.0 * y / 4.0, 255.0 * x / 8.0}; }

/// A flat 4 x 4 m square at z = 0 from x0, `step` grid, its 256 x 256 page the gradient
/// (texel centres rounded), class 0 left of x = 4, 1 right of it.
TileMesh flatSquare(double x0, double step) {
    TileMesh m = terrain(x0, 0, 4, step, 1, 0.0);
    cv::Mat page(256, 256, CV_8UC3);
    for (int r = 0; r < 256; ++r)
        for (int c = 0; c < 256; ++c) {
            const cv::Vec3d g = gradient(x0 + 4.0 * (c + 0.5) / 256, 4.0 * (r + 0.5) / 256);
            page.at<cv::Vec3b>(r, c) = cv::Vec3b(uchar(std::lround(g[0])), uchar(std::lround(g[1])), uchar(std::lround(g[2])));
        }
    m.pages[0] = page;
    for (std::size_t f = 0; f < m.faces(); ++f) {
        m.label[f] = x0 < 4 ? 0 : 1;
        m.confidence[f] = x0 < 4 ? 0.25f : 0.75f;
    }
    return m;
}

/// The page sampled bilinearly at glTF texture coordinates (texel centres at (i + 0.5) / size).
cv::Vec3d sampleBilinear(const cv::Mat& page, const Eigen::Vector2d& uv) {
    const double x = std::clamp(uv.x() * page.cols - 0.5, 0.0, page.cols - 1.0);
    const double y = std::clamp(uv.y() * page.rows - 0.5, 0.0, page.rows - 1.0);
    const int x0 = int(x), y0 = int(y), x1 = std::min(x0 + 1, page.cols - 1), y1 = std::min(y0 + 1, page.rows - 1);
    const double fx = x - x0, fy = y - y0;
    cv::Vec3d out;
    for (int ch = 0; ch < 3; ++ch) {
        out[ch] = (1 - fy) * ((1 - fx) * page.at<cv::Vec3b>(y0, x0)[ch] + fx * page.at<cv::Vec3b>(y0, x1)[ch]) +
                  fy * ((1 - fx) * page.at<cv::Vec3b>(y1, x0)[ch] + fx * page.at<cv::Vec3b>(y1, x1)[ch]);
    }
    return out;
}

}  // namespace

TEST_CASE("A parent's texture is baked from its children's at half the resolution", "[tiles3d]") {
    // Two flat squares side by side: the parent simplifies to about a quarter (the plane
    // costs no error), and its fresh atlas, sampled anywhere on a face, gives the gradient's
    // closed form at that point: bilinear sampling of a linear function is exact up to the
    // rounding of the texels, and the face margins repeat the face's border colours.
    const TileMesh a = flatSquare(0, 0.1), b = flatSquare(4, 0.1);
    ParentOptions po;
    po.level = 1;
    po.voxel_size_m = 0.1;
    ParentFigures fig;
    const TileMesh p = buildParent({&a, &b}, po, &fig);
    CHECK(p.faces() <= fig.merged_faces / 4 + 8);
    CHECK(fig.child_texel_m == Approx(4.0 / 256).epsilon(0.01));
    CHECK(fig.texel_m == Approx(2 * fig.child_texel_m).epsilon(0.01));
    REQUIRE(p.pages.size() == 1);
    // The charts cover the plane with its texels and their margins: an 8 x 4 m plane at
    // texel_m is 32 / texel_m^2 texels (one rectangle per face took about 8x that).
    const double surface_texels = 32.0 / (fig.texel_m * fig.texel_m);
    INFO("charts " << fig.charts << ", texels " << fig.texels << ", surface texels " << surface_texels);
    CHECK(double(fig.texels) <= 1.3 * surface_texels);
    CHECK(double(fig.texels) >= surface_texels);
    CHECK(texelSizeM(p) == Approx(fig.texel_m).epsilon(0.01));
    GlbOptions jpeg;  // and through the GLB, as JPEG (quality 90)
    const TileMesh back = readGlb(writeGlb(p, classTable(), jpeg), "parent.glb");
    REQUIRE(back.faces() == p.faces());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    double worst = 0, worst_jpeg = 0, sum_jpeg = 0;
    int samples = 0;
    for (std::size_t f = 0; f < p.faces(); ++f) {
        REQUIRE(p.page[f] == 0);
        for (int s = 0; s < 8; ++s) {
            double r1 = u(rng), r2 = u(rng);
            if (r1 + r2 > 1) { r1 = 1 - r1; r2 = 1 - r2; }
            const double w[3] = {1 - r1 - r2, r1, r2};
            Eigen::Vector3d q = Eigen::Vector3d::Zero();
            Eigen::Vector2d uv = Eigen::Vector2d::Zero();
            for (int k = 0; k < 3; ++k) {
                q += w[k] * p.cornerW(f, k);
                uv += w[k] * p.uvs[f][static_cast<std::size_t>(k)].cast<double>();
            }
            const cv::Vec3d want = gradient(q.x(), q.y());
            worst = std::max(worst, cv::norm(sampleBilinear(p.pages[0], uv) - want, cv::NORM_INF));
            const double e = cv::norm(sampleBilinear(back.pages[0], uv) - want, cv::NORM_INF);
            worst_jpeg = std::max(worst_jpeg, e);
            sum_jpeg += e;
            ++samples;
        }
        // The class: that of the children's faces nearest to the face's texels (a face across
        // the border at x = 4 takes either).
        const double lo = std::min({p.cornerW(f, 0).x(), p.cornerW(f, 1).x(), p.cornerW(f, 2).x()});
        const double hi = std::max({p.cornerW(f, 0).x(), p.cornerW(f, 1).x(), p.cornerW(f, 2).x()});
        if (hi < 4) {
            CHECK(int(p.label[f]) == 0);
            CHECK(p.confidence[f] == 0.25f);
        } else if (lo > 4) {
            CHECK(int(p.label[f]) == 1);
            CHECK(p.confidence[f] == 0.75f);
        }
    }
    INFO("worst " << worst << ", JPEG worst " << worst_jpeg << ", mean " << sum_jpeg / samples);
    // The page's rounding (0.5) twice, the margin's clamp (one texel of the gradient, about 2);
    // JPEG (quality 90) adds its ringing where a face's rectangle meets an unrelated one.
    CHECK(worst <= 3.5);
    CHECK(sum_jpeg / samples <= 3.0);
    CHECK(worst_jpeg <= 20.0);
}

TEST_CASE("Point-triangle distance: closed forms", "[tiles3d]") {
    const Triangle t{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)};
    CHECK(pointTriangleDistance({0.2, 0.2, 3}, t) == Approx(3));
    CHECK(pointTriangleDistance({-1, 0, 0}, t) == Approx(1));
    CHECK(pointTriangleDistance({1, 1, 0}, t) == Approx(std::sqrt(0.5)));
    CHECK(pointTriangleDistance({0.5, -2, 0}, t) == Approx(2));
}

TEST_CASE("The grid's nearest triangle is the brute-force one, whatever the hint", "[tiles3d]") {
    // A bumpy sheet of 2,000 small triangles and 1,000 query points around it: the ring search
    // must give the brute-force oracle's triangle (ties: the smaller index) and point.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 20.0), h(-0.3, 0.3), d(-0.4, 0.4);
    std::vector<vdbmap::tiles3d::Triangle> tris;
    for (int i = 0; i < 2000; ++i) {
        const Eigen::Vector3d a(u(rng), u(rng), h(rng));
        tris.push_back({a, a + Eigen::Vector3d(d(rng), d(rng), h(rng)), a + Eigen::Vector3d(d(rng), d(rng), h(rng))});
    }
    const vdbmap::tiles3d::TriangleGrid grid(tris);
    std::uniform_real_distribution<double> z(-3.0, 3.0), far(-10.0, 30.0);
    for (int k = 0; k < 1000; ++k) {
        const Eigen::Vector3d p = k % 10 == 0 ? Eigen::Vector3d(far(rng), far(rng), far(rng))
                                              : Eigen::Vector3d(u(rng), u(rng), z(rng));
        int brute = -1;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t t = 0; t < tris.size(); ++t) {
            const double dist = vdbmap::tiles3d::pointTriangleDistance(p, tris[t]);
            if (dist < best) {
                best = dist;
                brute = static_cast<int>(t);
            }
        }
        for (const int hint : {-1, 0, static_cast<int>(k % 2000)}) {
            Eigen::Vector3d q;
            const int found = grid.nearest(p, q, hint);
            CHECK(found == brute);
            CHECK((p - q).norm() == Approx(best).margin(1e-12));
        }
    }
}

namespace {

/// The surface of the box [0, 2] x [0, 1] x [0, 1] in a `step` grid of triangles per side,
/// corners computed once per grid point (welded: equal floats on shared edges).
TileMesh boxSurface(double step) {
    TileMesh m;
    const Eigen::Vector3d size(2, 1, 1);
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        const int nu = int(std::lround(size[u] / step)), nv = int(std::lround(size[v] / step));
        for (const double side : {0.0, size[axis]}) {
            auto at = [&](int i, int j) {
                Eigen::Vector3f p;
                p[axis] = float(side);
                p[u] = float(i * step);
                p[v] = float(j * step);
                return p;
            };
            for (int i = 0; i < nu; ++i) {
                for (int j = 0; j < nv; ++j) {
                    const Eigen::Vector3f q[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
                    // Outward normals: (u x v) = +axis, so flip on the low side.
                    if (side > 0) {
                        m.corners.push_back({q[0], q[1], q[2]});
                        m.corners.push_back({q[0], q[2], q[3]});
                    } else {
                        m.corners.push_back({q[0], q[2], q[1]});
                        m.corners.push_back({q[0], q[3], q[2]});
                    }
                }
            }
        }
    }
    m.page.assign(m.faces(), kNoPage);
    m.label.assign(m.faces(), 0);
    m.confidence.assign(m.faces(), 1.0f);
    return m;
}

}  // namespace

TEST_CASE("Charts: a box's surface is its six sides; the box limit splits a side", "[tiles3d]") {
    const TileMesh box = boxSurface(0.25);
    auto partition = [&](const std::vector<Chart>& charts) {
        std::vector<int> seen(box.faces(), 0);
        for (const Chart& c : charts)
            for (const std::uint32_t f : c.faces) ++seen[f];
        return std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; });
    };
    const std::vector<Chart> sides = buildCharts(box, 10.0);
    REQUIRE(sides.size() == 6);
    CHECK(partition(sides));
    for (const Chart& c : sides) {
        // A side is flat on its plane: projected area = area; its box is the side's.
        CHECK(c.projected_m2 == Approx(c.area_m2));
        const Eigen::Vector2d extent = c.max_m - c.min_m;
        CHECK(c.area_m2 == Approx(extent.x() * extent.y()));
        for (const std::uint32_t f : c.faces) {
            const Eigen::Vector3f n = (box.corners[f][1] - box.corners[f][0]).cross(box.corners[f][2] - box.corners[f][0]);
            CHECK(std::abs(n[c.axis]) == Approx(n.norm()));
        }
    }
    const std::vector<Chart> small = buildCharts(box, 0.5);
    CHECK(partition(small));
    CHECK(small.size() >= 2 * 4 + 4 * 8);  // 1 x 1 sides in four 0.5 m pieces at least, 2 x 1 in eight
    for (const Chart& c : small) CHECK((c.max_m - c.min_m).maxCoeff() <= 0.5 + 1e-9);
}

TEST_CASE("Charts: the rasterization gives each texel its face and finds overlaps", "[tiles3d]") {
    // A 10 x 6 texel square in two triangles, 2 texels of margin: every texel centre inside
    // the square shows the triangle that contains it; margin texels show the nearer one.
    const Eigen::Vector2d a(2, 2), b(12, 2), c(12, 8), d(2, 8);
    std::vector<std::int32_t> owner;
    REQUIRE(rasterizeChart({{a, b, c}, {a, c, d}}, 14, 10, 3.0, owner).empty());
    for (int r = 0; r < 10; ++r) {
        for (int col = 0; col < 14; ++col) {
            const Eigen::Vector2d q(col + 0.5, r + 0.5);
            const std::int32_t o = owner[std::size_t(r) * 14 + std::size_t(col)];
            REQUIRE(o >= 0);  // the whole rectangle is within 3 texels of the square
            const Nearest2 lower = nearestOnTriangle2(q, {a, b, c}), upper = nearestOnTriangle2(q, {a, c, d});
            CHECK(o == (upper.distance2 < lower.distance2 ? 1 : 0));
            if (lower.strictly_inside) CHECK(o == 0);
            if (upper.strictly_inside) CHECK(o == 1);
        }
    }
    // Two triangles over the same texels, and one beside them: the overlap's two faces.
    const Eigen::Vector2d e(13, 2), f(13.9, 2), h(13, 9);
    CHECK(rasterizeChart({{a, b, c}, {e, f, h}, {a, b, d}}, 14, 10, 2.0, owner) == std::vector<std::uint32_t>{0, 2});
    // The nearest point's weights rebuild it; outside, it is on the border.
    const Nearest2 out = nearestOnTriangle2({20, 5}, {a, b, c});
    CHECK(out.distance2 == Approx(64));
    const Eigen::Vector2d on = out.weights[0] * a + out.weights[1] * b + out.weights[2] * c;
    CHECK((on - Eigen::Vector2d(12, 5)).norm() < 1e-12);
}

TEST_CASE("A parent's bake is the same for any thread count", "[tiles3d]") {
    const TileMesh a = terrain(0, 0, 4, 0.1, 2, 0.5), b = terrain(4, 0, 4, 0.1, 1, 0.5);
    ParentOptions po;
    po.level = 1;
    po.voxel_size_m = 0.1;
    auto build = [&](int threads) {
        tbb::task_arena arena(threads);
        TileMesh p;
        arena.execute([&] { p = buildParent({&a, &b}, po); });
        return p;
    };
    const TileMesh one = build(1), four = build(4);
    REQUIRE(one.pages.size() == 1);
    requireSame(one, four, true);
}
