// SPDX-License-Identifier: Apache-2.0
// Issue 34's "every level's measured distance to the full mesh <= its geometricError" on a
// whole tileset (docs/benchmarks/tiles3d.md): for the first parent of each level, SAMPLES
// random points on its faces, each point's exact distance to the leaves below it (the grid's
// nearest-triangle query), the largest against the parent's geometricError. Tiles3dRunTest
// checks every parent of its test run the same way.
// Usage: tiles3d_error_check OUT/3dtiles [SAMPLES]   (exit 1 if a level exceeds its bound)
#include <cstdio>
#include <cstdlib>
#include <map>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <nlohmann/json.hpp>
#include "Glb.h"
#include "Lod.h"
#include "MeshDistance.h"
using namespace vdbmap::tiles3d;
using json = nlohmann::json;
static std::string readAll(const std::string& p) { std::ifstream in(p, std::ios::binary); std::stringstream ss; ss << in.rdbuf(); return ss.str(); }
int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: tiles3d_error_check OUT/3dtiles [SAMPLES]\n");
        return 2;
    }
    const std::string dir = argv[1];
    const int samples = argc > 2 ? std::atoi(argv[2]) : 20000;
    bool ok = true;
    json ts = json::parse(readAll(dir + "/tileset.json"));
    std::function<void(const json&, std::vector<std::string>&)> leaves = [&](const json& t, std::vector<std::string>& out) {
        if (!t.contains("children") || t["children"].empty()) { out.push_back(t["content"]["uri"]); return; }
        for (auto& c : t["children"]) leaves(c, out);
    };
    std::map<int, int> done;
    std::function<int(const json&)> visit = [&](const json& t) -> int {
        int h = 0;
        if (t.contains("children")) for (auto& c : t["children"]) h = std::max(h, visit(c) + 1);
        if (h > 0 && t.contains("content") && !done.count(h)) {
            done[h] = 1;
            std::vector<std::string> ls; leaves(t, ls);
            std::vector<Triangle> tris;
            for (auto& l : ls) { TileMesh m = readGlb(readAll(dir + "/" + l), l); for (auto& tr : trianglesW(m)) tris.push_back(tr); }
            TriangleGrid grid(std::move(tris));
            TileMesh p = readGlb(readAll(dir + "/" + t["content"]["uri"].get<std::string>()), "parent");
            auto pt = trianglesW(p);
            std::mt19937 rng(5); std::uniform_real_distribution<double> u(0, 1);
            double worst = 0;
            for (int s = 0; s < samples; ++s) {
                const Triangle& tr = pt[rng() % pt.size()];
                double a = u(rng), b = u(rng); if (a + b > 1) { a = 1 - a; b = 1 - b; }
                worst = std::max(worst, grid.distance(tr[0] + a * (tr[1] - tr[0]) + b * (tr[2] - tr[0])));
            }
            const double ge = t["geometricError"];
            std::printf("level %d %s: %zu leaves, %zu leaf faces, %zu parent faces, %d samples: max distance %.3f m, geometricError %.3f m: %s\n",
                   h, t["content"]["uri"].get<std::string>().c_str(), ls.size(), grid.size(), pt.size(), samples, worst, ge, worst <= ge ? "ok" : "EXCEEDED");
            ok = ok && worst <= ge;
            std::fflush(stdout);
        }
        return h;
    };
    visit(ts["root"]);
    return ok ? 0 : 1;
}
