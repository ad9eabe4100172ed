// SPDX-License-Identifier: Apache-2.0
#include "vdbmap/render/VisibilityKey.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "vdbmap/Error.h"

namespace vdbmap {
namespace {

/// 64-bit FNV-1a over byte ranges.
class Fnv1a {
public:
    void add(const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i) {
            hash_ = (hash_ ^ p[i]) * 1099511628211ULL;
        }
    }
    template <typename T>
    void add(const T& value) {
        add(&value, sizeof(T));
    }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = 14695981039346656037ULL;
};

std::string hex(std::uint64_t v) {
    char buffer[20];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(v));
    return buffer;
}

std::uint64_t fingerprint(const MeshArrays& mesh) {
    Fnv1a h;
    h.add(mesh.vertices_W.size());
    h.add(mesh.vertices_W.data(), mesh.vertices_W.size() * sizeof(mesh.vertices_W[0]));
    h.add(mesh.faces.size());
    h.add(mesh.faces.data(), mesh.faces.size() * sizeof(mesh.faces[0]));
    return h.value();
}

std::uint64_t fingerprint(const TriMesh& mesh) {
    Fnv1a h;
    h.add(mesh.n_vertices());
    for (const auto& v : mesh.vertices()) h.add(mesh.point(v));
    std::size_t faces = 0;
    for (const auto& f : mesh.faces()) {  // skips deleted faces
        for (const auto& v : mesh.fv_range(f)) h.add(v.idx());
        ++faces;
    }
    h.add(faces);
    return h.value();
}

std::uint64_t fingerprint(const std::vector<View>& views) {
    Fnv1a h;
    h.add(views.size());
    for (const View& v : views) {
        h.add(v.frame);
        h.add(v.camera);
        const CameraIntrinsics& k = v.intrinsics;
        h.add(k.width);
        h.add(k.height);
        for (const double x : {k.fx, k.fy, k.cx, k.cy}) h.add(x);
        h.add(k.distortion);
        h.add(v.T_C_W.matrix().data(), 16 * sizeof(double));
    }
    return h.value();
}

}  // namespace

void narrowViewAngle(SharedVisibility& shared, double max_view_angle_deg) {
    if (!(max_view_angle_deg > 0.0 && max_view_angle_deg <= shared.max_view_angle_deg)) {
        throw InvalidInput("narrowViewAngle: the angle must be in (0, " +
                           std::to_string(shared.max_view_angle_deg) + "], got " +
                           std::to_string(max_view_angle_deg));
    }
    if (max_view_angle_deg == shared.max_view_angle_deg) return;
    // The same comparison as computeVisibility (a float cos_angle against a double cosine).
    const double cos_max = std::cos(max_view_angle_deg * M_PI / 180.0);
    std::vector<char> drop(shared.visibility.obs.size());
    for (std::size_t i = 0; i < drop.size(); ++i) {
        drop[i] = shared.visibility.obs[i].cos_angle < cos_max;
    }
    dropObservations(shared.visibility, drop);
    auto& hidden = shared.scan_hidden_cos;
    hidden.erase(std::remove_if(hidden.begin(), hidden.end(),
                                [&](float c) { return c < cos_max; }),
                 hidden.end());
    shared.max_view_angle_deg = max_view_angle_deg;
}

std::string visibilityKey(const MeshArrays& mesh, const TriMesh& occluders,
                          const std::vector<View>& views, const VisibilityOptions& options,
                          const ScanOcclusionOptions* scan, const void* moving) {
    std::ostringstream key;
    key.precision(17);
    key << "mesh " << hex(fingerprint(mesh)) << " occluders " << hex(fingerprint(occluders))
        << " views " << hex(fingerprint(views)) << " depth " << options.min_depth_m << ' ' << options.max_depth_m << " occlusion "
        << options.occlusion_test << ' ' << options.occlusion_tolerance_m;
    if (scan) {
        key << " scan " << scan->row_dilate_px << ' ' << scan->gap_px << ' ' << scan->margin_m
            << ' ' << scan->margin_rel << ' ' << scan->moving_margin_m << ' '
            << scan->moving_dilate_px << ' ' << scan->min_hidden_fraction << " moving " << moving;
    } else {
        key << " no scan";
    }
    return key.str();
}

}  // namespace vdbmap
