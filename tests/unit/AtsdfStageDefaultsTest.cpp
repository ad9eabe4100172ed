// SPDX-License-Identifier: Apache-2.0
// One source of defaults (issue 32): the integrate.atsdf stage, given no options, builds the
// integrator a library caller gets from a default-constructed AtsdfConfig.
#include <catch2/catch.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <variant>

#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/Truncation.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/map/VoxelSize.h"
#include "vdbmap/pipeline/Stage.h"
#include "vdbmap/pipeline/StageRegistry.h"

using namespace vdbmap;

namespace {

/// The stage as the pipeline leaves it for an empty options node: declared (defaults written
/// into its members), nothing bound, initialized.
struct DefaultStage {
    std::unique_ptr<Stage> stage;
    OptionSpec spec;
    DefaultStage() {
        registerBuiltinStages();
        stage = StageRegistry::instance().create("integrate.atsdf");
        stage->declareOptions(spec);
        stage->initialize();
    }
    double number(const std::string& key) const {
        const OptionValue v = spec.value(key);
        if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
        return std::get<double>(v);
    }
    bool flag(const std::string& key) const { return std::get<bool>(spec.value(key)); }
    std::string text(const std::string& key) const { return std::get<std::string>(spec.value(key)); }
};

}  // namespace

TEST_CASE("integrate.atsdf's defaults are AtsdfConfig's, field by field", "[tsdf][config]") {
    const DefaultStage s;
    const AtsdfConfig d;
    const TruncationParams& t = d.truncation;
    std::size_t keys = 0;
    auto same = [&](const std::string& key, double field) {
        INFO(key);
        CHECK(s.number(key) == field);
        ++keys;
    };
    CHECK(s.number("voxel_size_m") == kDefaultVoxelSizeM);
    ++keys;
    CHECK(s.text("truncation_mode") == truncationModeName(t.mode));
    ++keys;
    same("truncation_min_voxels", t.min_voxels);
    same("truncation_max_voxels", t.max_voxels);
    same("truncation_min_m", t.min_m);
    same("truncation_max_m", t.max_m);
    same("truncation_max_along_ray_m", t.max_along_ray_m);
    same("grazing_band_voxels", t.grazing_band_voxels);
    CHECK(s.flag("grazing_band_both_sides") == t.grazing_band_both_sides);
    CHECK(s.flag("grazing_band_to_next_ring") == t.grazing_band_to_next_ring);
    keys += 2;
    same("flatness_k", t.flatness_k);
    same("reference_density_pts_m2", t.reference_density_pts_m2);
    same("reference_points", t.reference_points);
    same("min_points_for_pca", d.min_points_for_pca);
    same("weight_floor", d.weight_floor);
    same("max_weight", d.max_weight);
    same("range_noise_m", d.range_noise_m);
    same("noise_ratio", d.noise_ratio);
    same("falloff_voxels", d.falloff_voxels);
    CHECK(s.text("merge_points") == mergePointsName(d.merge_divisions));
    CHECK(s.flag("space_carving") == d.space_carving);
    keys += 2;
    same("working_set_scans", d.working_set_scans);
    // Every option of the stage is one of the fields above: a new option must be added here
    // (and bound to a field of AtsdfConfig).
    // The moving-object removal's options (dynamic_*) bind DynamicRemovalConfig, checked in
    // DynamicRemovalTest; every other option is counted above.
    std::size_t dynamic_keys = 0;
    for (const auto& o : s.spec.options()) dynamic_keys += o.key.rfind("dynamic_", 0) == 0 ? 1 : 0;
    CHECK(dynamic_keys > 0);
    CHECK(s.spec.options().size() == keys + dynamic_keys);
    // The metre fields that are not options stay 0 in the struct: the voxel counts apply.
    CHECK(t.grazing_band_m == 0.0);
    CHECK(d.falloff_m == 0.0);
}

TEST_CASE("The default AtsdfConfig resolves to the product's street settings", "[tsdf][config]") {
    // At the default 0.10 m voxel: eps in [4, 8] voxels, b = 2 voxels, l = 1 voxel, n_ref from
    // 156.25 points per m^2 over a 0.8 m block = 100, merged rays per voxel in the adaptive mode,
    // the band behind grazing points to the next ring, max weight 1000.
    const AtsdfConfig r = resolveAtsdfConfig(AtsdfConfig{}, 0.10);
    CHECK(r.truncation.min_m == Approx(0.40));
    CHECK(r.truncation.max_m == Approx(0.80));
    CHECK(r.truncation.grazing_band_m == Approx(0.20));
    CHECK(r.truncation.reference_points == Approx(100.0));
    CHECK(r.truncation.grazing_band_to_next_ring);
    CHECK(r.falloff_m == Approx(0.10));
    CHECK(r.merge_divisions == 1);
    CHECK(r.max_weight == 1000.0);
    // Resolved configs resolve to themselves.
    const AtsdfConfig rr = resolveAtsdfConfig(r, 0.05);
    CHECK(rr.truncation.min_m == r.truncation.min_m);
    CHECK(rr.truncation.max_m == r.truncation.max_m);
    CHECK(rr.truncation.grazing_band_m == r.truncation.grazing_band_m);
    CHECK(rr.truncation.reference_points == r.truncation.reference_points);
    CHECK(rr.falloff_m == r.falloff_m);

    SECTION("lengths in voxels follow the voxel size; metres win where given") {
        const AtsdfConfig fine = resolveAtsdfConfig(AtsdfConfig{}, 0.025);
        CHECK(fine.truncation.min_m == Approx(0.10));
        CHECK(fine.truncation.max_m == Approx(0.20));
        CHECK(fine.truncation.grazing_band_m == Approx(0.05));
        CHECK(fine.truncation.reference_points == Approx(6.25));  // 156.25 * 0.2^2
        CHECK(fine.falloff_m == Approx(0.025));
        AtsdfConfig given;
        given.truncation.max_m = 0.3;  // eps_min from voxels (0.4 m) is capped at eps_max
        given.truncation.mode = TruncationMode::Fixed;
        const AtsdfConfig g = resolveAtsdfConfig(given, 0.10);
        CHECK(g.truncation.max_m == Approx(0.3));
        CHECK(g.truncation.min_m == Approx(0.3));
        CHECK(g.merge_divisions == 0);  // auto: no merging outside the adaptive mode
    }
}

TEST_CASE("A library caller with AtsdfConfig{} runs the stage's integrator", "[tsdf][config]") {
    const std::shared_ptr<VoxelMap> map = makeVoxelMap(AtsdfConfig{}, kDefaultVoxelSizeM);
    const AtsdfIntegrator integrator(*map, AtsdfConfig{});
    const AtsdfConfig& c = integrator.config();
    CHECK(c.truncation.max_m == Approx(0.80));
    CHECK(map->codec().sdfRange() == Approx(0.80f));
    CHECK(map->codec().weightRange() == Approx(1000.0f));
    CHECK(c.merge_divisions == 1);
    CHECK(integrator.usesRings());
    // A map too small for the defaults is refused, naming the option.
    VoxelMap small(kDefaultVoxelSizeM, 0.3f, 100.0f);
    CHECK_THROWS_WITH(AtsdfIntegrator(small, AtsdfConfig{}), Catch::Contains("truncation_max_m"));
}

TEST_CASE("The stage and the library reject the same bad values with the option's name",
          "[tsdf][config]") {
    AtsdfConfig c;
    c.truncation.min_voxels = -1.0;
    CHECK_THROWS_WITH(validateAtsdfConfig(c, 0.1, "integrate.atsdf"),
                      Catch::Contains("truncation_min_voxels") && Catch::Contains("got -1"));
    c = AtsdfConfig{};
    c.truncation.reference_density_pts_m2 = 0.0;
    CHECK_THROWS_WITH(validateAtsdfConfig(c, 0.1, "integrate.atsdf"),
                      Catch::Contains("reference_density_pts_m2"));
    c = AtsdfConfig{};
    c.merge_divisions = 3;
    CHECK_THROWS_WITH(validateAtsdfConfig(c, 0.1, "integrate.atsdf"), Catch::Contains("merge_divisions"));
    CHECK(parseMergePoints("half_voxel") == 2);
    CHECK(parseMergePoints(mergePointsName(kMergeAuto)) == kMergeAuto);
    CHECK_THROWS_AS(parseMergePoints("cell"), ConfigError);
}
