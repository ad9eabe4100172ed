// SPDX-License-Identifier: Apache-2.0
// Embree 3 backed ray casting and closest-point queries (Apache-2.0, no GPL code).
#include "vdbmap/render/Raycaster.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "vdbmap/Error.h"
#include "vdbmap/mesh/MeshArrays.h"

namespace vdbmap {

namespace {

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3f closestPointOnTriangle(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f ab = b - a;
    const Vec3f ac = c - a;
    const Vec3f ap = p - a;
    const float d1 = ab.dot(ap);
    const float d2 = ac.dot(ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return a;
    const Vec3f bp = p - b;
    const float d3 = ab.dot(bp);
    const float d4 = ac.dot(bp);
    if (d3 >= 0.0f && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
    const Vec3f cp = p - c;
    const float d5 = ab.dot(cp);
    const float d6 = ac.dot(cp);
    if (d6 >= 0.0f && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f) {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    const float denom = va + vb + vc;
    if (!(std::abs(denom) > 0.0f)) return a;  // degenerate triangle
    const float v = vb / denom;
    const float w = vc / denom;
    return a + ab * v + ac * w;
}

}  // namespace

struct Raycaster::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::vector<Vec3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;

    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    Vec3f geometricNormal(std::uint32_t face) const {
        const auto& t = triangles[face];
        const Vec3f n = (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
        const float len = n.norm();
        return len > 0.0f ? Vec3f(n / len) : Vec3f::Zero();
    }

    struct QueryState {
        const Impl* impl;
        Vec3f query;
        std::optional<ClosestPoint> best;
    };

    static bool pointQueryCallback(RTCPointQueryFunctionArguments* args) {
        auto* state = static_cast<QueryState*>(args->userPtr);
        const Impl& self = *state->impl;
        const auto& t = self.triangles[args->primID];
        const Vec3f q = closestPointOnTriangle(state->query, self.vertices[t[0]],
                                               self.vertices[t[1]], self.vertices[t[2]]);
        const float d = (q - state->query).norm();
        if (d < args->query->radius) {
            args->query->radius = d;
            state->best = ClosestPoint{d, args->primID, q};
            return true;
        }
        return false;
    }
};

Raycaster::Raycaster(const std::vector<Vec3f>& vertices,
                     const std::vector<std::array<std::uint32_t, 3>>& triangles)
    : impl_(std::make_unique<Impl>()) {
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        for (std::uint32_t idx : triangles[i]) {
            if (idx >= vertices.size()) {
                throw InvalidInput("Raycaster: triangle " + std::to_string(i) +
                                   " refers to vertex " + std::to_string(idx) + " but there are " +
                                   std::to_string(vertices.size()) + " vertices");
            }
        }
    }
    impl_->vertices = vertices;
    impl_->triangles = triangles;
    impl_->device = rtcNewDevice(nullptr);
    if (!impl_->device) {
        throw InvalidInput("Raycaster: could not create an Embree device (error " +
                           std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
    }
    impl_->scene = rtcNewScene(impl_->device);
    rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
    if (!triangles.empty()) {
        RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree reads vertex buffers with 16-byte loads: pad the last element.
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
            vertices.size() + 1));
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            vb[3 * i + 0] = vertices[i].x();
            vb[3 * i + 1] = vertices[i].y();
            vb[3 * i + 2] = vertices[i].z();
        }
        vb[3 * vertices.size() + 0] = vb[3 * vertices.size() + 1] = vb[3 * vertices.size() + 2] =
            0.0f;
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
            triangles.size()));
        for (std::size_t i = 0; i < triangles.size(); ++i) {
            ib[3 * i + 0] = triangles[i][0];
            ib[3 * i + 1] = triangles[i][1];
            ib[3 * i + 2] = triangles[i][2];
        }
        rtcCommitGeometry(geom);
        rtcAttachGeometry(impl_->scene, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(impl_->scene);
    const RTCError err = rtcGetDeviceError(impl_->device);
    if (err != RTC_ERROR_NONE) {
        throw InvalidInput("Raycaster: Embree failed to build the BVH (error " +
                           std::to_string(static_cast<int>(err)) + ")");
    }
}

Raycaster Raycaster::fromMesh(const TriMesh& mesh) {
    // Face index = triangle index, also for deleted faces (collapsed, so never hit).
    const MeshArrays arrays = meshArrays(mesh, DeletedFaces::Collapse);
    return Raycaster(arrays.vertices_W, arrays.faces);
}

Raycaster::~Raycaster() = default;
Raycaster::Raycaster(Raycaster&&) noexcept = default;
Raycaster& Raycaster::operator=(Raycaster&&) noexcept = default;

std::optional<Raycaster::Hit> Raycaster::intersect(const Vec3f& origin,
                                                   const Vec3f& direction_unit, float t_min,
                                                   float t_max) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = origin.x();
    rh.ray.org_y = origin.y();
    rh.ray.org_z = origin.z();
    rh.ray.dir_x = direction_unit.x();
    rh.ray.dir_y = direction_unit.y();
    rh.ray.dir_z = direction_unit.z();
    rh.ray.tnear = t_min;
    rh.ray.tfar = t_max;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    Hit hit;
    hit.distance = rh.ray.tfar;
    hit.face = rh.hit.primID;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.normal_unit = impl_->geometricNormal(rh.hit.primID);
    return hit;
}

bool Raycaster::occluded(const Vec3f& origin, const Vec3f& direction_unit, float t_min,
                         float t_max) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    ray.org_x = origin.x();
    ray.org_y = origin.y();
    ray.org_z = origin.z();
    ray.dir_x = direction_unit.x();
    ray.dir_y = direction_unit.y();
    ray.dir_z = direction_unit.z();
    ray.tnear = t_min;
    ray.tfar = t_max;
    ray.mask = 0xFFFFFFFFu;
    ray.flags = 0;
    ray.time = 0.0f;
    rtcOccluded1(impl_->scene, &context, &ray);
    // Embree sets tfar to -inf when the ray is occluded.
    return ray.tfar < 0.0f && std::isinf(ray.tfar);
}

void Raycaster::intersect(const std::vector<Vec3f>& origins,
                          const std::vector<Vec3f>& directions_unit, float t_max,
                          std::vector<std::optional<Hit>>& hits) const {
    if (origins.size() != directions_unit.size() && origins.size() != 1) {
        throw InvalidInput("Raycaster::intersect: " + std::to_string(origins.size()) +
                           " origins but " + std::to_string(directions_unit.size()) +
                           " directions (expected equal counts, or one shared origin)");
    }
    hits.assign(directions_unit.size(), std::nullopt);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, directions_unit.size(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              const Vec3f& o = origins.size() == 1 ? origins[0] : origins[i];
                              hits[i] = intersect(o, directions_unit[i], 0.0f, t_max);
                          }
                      });
}

std::optional<Raycaster::ClosestPoint> Raycaster::closestPoint(const Vec3f& query,
                                                               float max_distance) const {
    if (impl_->triangles.empty()) return std::nullopt;
    RTCPointQuery pq;
    pq.x = query.x();
    pq.y = query.y();
    pq.z = query.z();
    pq.time = 0.0f;
    // Embree needs a finite radius for its traversal bound.
    pq.radius = std::isfinite(max_distance) ? max_distance : 1e30f;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    Impl::QueryState state{impl_.get(), query, std::nullopt};
    rtcPointQuery(impl_->scene, &pq, &context, &Impl::pointQueryCallback, &state);
    return state.best;
}

std::size_t Raycaster::numTriangles() const { return impl_->triangles.size(); }

}  // namespace vdbmap
