// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include <limits>
#include <string>

#include "support/PlainAtsdfConfig.h"
#include "vdbmap/Error.h"
#include "vdbmap/map/Truncation.h"

using namespace vdbmap;
using vdbmap::test::plainTruncationParams;

namespace {
PlaneEstimate plane(double flatness) {
    PlaneEstimate p;
    p.valid = true;
    p.normal = Vec3d::UnitZ();
    p.flatness = flatness;
    return p;
}
}  // namespace

TEST_CASE("Adaptive eps: a sparse flat block gets a larger eps than a dense or non-flat one",
          "[tsdf][truncation]") {
    TruncationParams t = plainTruncationParams();  // [0.10, 0.30] m, k = 1, n_ref = 100
    const double sparse_flat = truncationFor(t, plane(0.98), 60);
    const double dense_flat = truncationFor(t, plane(0.98), 600);
    const double sparse_curved = truncationFor(t, plane(0.30), 60);
    CHECK(sparse_flat > dense_flat);
    CHECK(sparse_flat > sparse_curved);
    // Closed form of Eq. (4) with n / n_ref.
    CHECK(sparse_flat == Approx(0.30));  // 0.98 * 100/60 * 0.3 = 0.49 -> clamped to eps_max
    CHECK(dense_flat == Approx(std::max(0.10, 0.98 * 100.0 / 600.0 * 0.30)));
    CHECK(sparse_curved == Approx(0.30 * 100.0 / 60.0 * 0.30));
    CHECK(truncationFor(t, plane(0.0), 60) == Approx(0.10));  // eps_min floor
}

TEST_CASE("Eps stays within [eps_min, eps_max]", "[tsdf][truncation]") {
    TruncationParams t = plainTruncationParams();
    for (double n : {1.0, 5.0, 50.0, 1e3, 1e6})
        for (double f : {0.0, 0.3, 1.0}) {
            const double e = truncationFor(t, plane(f), n);
            CHECK(e >= t.min_m);
            CHECK(e <= t.max_m);
        }
}

TEST_CASE("Degenerate blocks and fixed mode use eps_max", "[tsdf][truncation]") {
    TruncationParams t = plainTruncationParams();
    CHECK(truncationFor(t, PlaneEstimate{}, 3) == Approx(t.max_m));
    t.mode = TruncationMode::Fixed;
    CHECK(truncationFor(t, plane(0.0), 1e6) == Approx(t.max_m));
}

TEST_CASE("Truncation parameters are validated", "[tsdf][truncation]") {
    TruncationParams t = plainTruncationParams();
    t.min_m = 0.4;
    CHECK_THROWS_AS(validateTruncation(t, "integrate.atsdf"), ConfigError);
    t = plainTruncationParams();
    t.reference_points = 0.0;
    CHECK_THROWS_WITH(validateTruncation(t, "integrate.atsdf"),
                      Catch::Contains("reference_points") && Catch::Contains("integrate.atsdf"));
    CHECK_THROWS_AS(parseTruncationMode("adaptiv"), ConfigError);
    CHECK(parseTruncationMode("fixed") == TruncationMode::Fixed);
}

TEST_CASE("n_ref follows from a surface density and the block size", "[tsdf][truncation]") {
    // 156.25 points per m^2 across an 8^3 block: 100 at 0.10 m voxels (0.8 m blocks), 6.25 at
    // 0.025 m (0.2 m blocks), so the same density gives the same eps at any voxel size.
    CHECK(referencePointsForDensity(156.25, 0.10) == Approx(100.0));
    CHECK(referencePointsForDensity(156.25, 0.025) == Approx(6.25));
    TruncationParams coarse = plainTruncationParams(), fine = plainTruncationParams();
    coarse.reference_points = referencePointsForDensity(156.25, 0.10);
    fine.reference_points = referencePointsForDensity(156.25, 0.025);
    // A flat surface sampled at 1000 points per m^2 in both grids.
    const double n_coarse = 1000.0 * 0.8 * 0.8, n_fine = 1000.0 * 0.2 * 0.2;
    CHECK(truncationFor(coarse, plane(0.9), n_coarse) == Approx(truncationFor(fine, plane(0.9), n_fine)));
}

TEST_CASE("Adaptive band: at least b across a grazing surface, widened only in front",
          "[tsdf][truncation]") {
    TruncationParams t = plainTruncationParams();
    t.min_m = 0.4;
    t.max_m = 0.8;
    t.grazing_band_m = 0.2;  // 2 voxels of 0.1 m; L_max = eps_max = 0.8 m
    // Frontal (c = 1): the paper's eps in front, b behind.
    RayBand r = rayBandFor(t, 0.5, 1.0);
    CHECK(r.front_m == Approx(0.5));
    CHECK(r.back_m == Approx(0.2));
    // A small eps (1 voxel) still gets b behind the surface.
    CHECK(rayBandFor(t, 0.1, 1.0).back_m == Approx(0.2));
    CHECK(rayBandFor(t, 0.1, 1.0).front_m == Approx(0.2));
    // 30 deg from the surface (c = 0.5): b / c = 0.4 < eps: front eps, back 0.4.
    r = rayBandFor(t, 0.5, 0.5);
    CHECK(r.front_m == Approx(0.5));
    CHECK(r.back_m == Approx(0.4));
    // Grazing (c = 0.1): the ray band would span 0.05 m across the surface; the adaptive band
    // spans b = 0.2 m in front (2 m along the ray, capped at L_max = 0.8 m) and eps behind.
    r = rayBandFor(t, 0.5, 0.1);
    CHECK(r.front_m == Approx(0.8));
    CHECK(r.back_m == Approx(0.5));
    CHECK(r.front_m * 0.1 > 0.5 * 0.1);
    // Parallel to the surface: the cap.
    CHECK(rayBandFor(t, 0.5, 0.0).front_m == Approx(0.8));
    t.max_along_ray_m = 1.0;
    CHECK(rayBandFor(t, 0.5, 0.1).front_m == Approx(1.0));
    CHECK(maxHalfLength(t) == Approx(1.0));
    // Both sides: behind the point too the band reaches b across the surface (b / c along the
    // ray, up to L_max); frontal points keep b behind, as without.
    t.max_along_ray_m = 0.0;
    t.grazing_band_both_sides = true;
    CHECK(rayBandFor(t, 0.5, 1.0).back_m == Approx(0.2));
    CHECK(rayBandFor(t, 0.5, 0.5).back_m == Approx(0.4));
    r = rayBandFor(t, 0.5, 0.1);
    CHECK(r.back_m == Approx(0.8));
    CHECK(r.front_m == Approx(0.8));
    CHECK(maxHalfLength(t) == Approx(0.8));
    t.grazing_band_both_sides = false;
    // A gap g to the next ring: behind, the band reaches g, but no further than b across the
    // surface (b / c) or L_max; a gap shorter than the band changes nothing.
    CHECK(rayBandFor(t, 0.3, 0.1, 0.6).back_m == Approx(0.6));
    CHECK(rayBandFor(t, 0.3, 0.1, 5.0).back_m == Approx(0.8));
    CHECK(rayBandFor(t, 0.3, 0.5, 5.0).back_m == Approx(0.4));
    CHECK(rayBandFor(t, 0.3, 0.1, 0.1).back_m == Approx(0.3));
    CHECK(rayBandFor(t, 0.3, 0.1, std::numeric_limits<double>::infinity()).back_m == Approx(0.8));
    CHECK(rayBandFor(t, 0.3, 0.1, 0.6).front_m == Approx(0.8));  // the front does not change
    // Paper and fixed: [-eps, eps] along the ray, whatever the incidence.
    for (TruncationMode m : {TruncationMode::Paper, TruncationMode::Fixed}) {
        t.mode = m;
        r = rayBandFor(t, 0.5, 0.1);
        CHECK(r.front_m == Approx(0.5));
        CHECK(r.back_m == Approx(0.5));
        CHECK(rayBandFor(t, 0.5, 0.1, 0.7).back_m == Approx(0.5));  // no ring gap either
        CHECK(maxHalfLength(t) == Approx(0.8));
    }
    CHECK(parseTruncationMode("paper") == TruncationMode::Paper);
    CHECK(std::string(truncationModeName(TruncationMode::Paper)) == "paper");
    CHECK_THROWS_WITH(parseTruncationMode("grazing"), Catch::Contains("paper"));
}
