// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/map/Truncation.h"

using namespace vdbmap;

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
    TruncationParams t;  // [0.10, 0.30] m, k = 1, n_ref = 100
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
    TruncationParams t;
    for (double n : {1.0, 5.0, 50.0, 1e3, 1e6})
        for (double f : {0.0, 0.3, 1.0}) {
            const double e = truncationFor(t, plane(f), n);
            CHECK(e >= t.min_m);
            CHECK(e <= t.max_m);
        }
}

TEST_CASE("Degenerate blocks and fixed mode use eps_max", "[tsdf][truncation]") {
    TruncationParams t;
    CHECK(truncationFor(t, PlaneEstimate{}, 3) == Approx(t.max_m));
    t.mode = TruncationMode::Fixed;
    CHECK(truncationFor(t, plane(0.0), 1e6) == Approx(t.max_m));
}

TEST_CASE("Truncation parameters are validated", "[tsdf][truncation]") {
    TruncationParams t;
    t.min_m = 0.4;
    CHECK_THROWS_AS(validateTruncation(t, "integrate.atsdf"), ConfigError);
    t = TruncationParams{};
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
    TruncationParams coarse, fine;
    coarse.reference_points = referencePointsForDensity(156.25, 0.10);
    fine.reference_points = referencePointsForDensity(156.25, 0.025);
    // A flat surface sampled at 1000 points per m^2 in both grids.
    const double n_coarse = 1000.0 * 0.8 * 0.8, n_fine = 1000.0 * 0.2 * 0.2;
    CHECK(truncationFor(coarse, plane(0.9), n_coarse) == Approx(truncationFor(fine, plane(0.9), n_fine)));
}
