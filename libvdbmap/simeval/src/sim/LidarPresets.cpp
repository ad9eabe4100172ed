// SPDX-License-Identifier: Apache-2.0
// Beam elevation tables of real Velodyne sensors.
#include <cmath>

#include "vdbmap/Error.h"
#include "vdbmap/sim/LidarModel.h"

namespace vdbmap {

LidarModel hdl64ePreset() {
    // Velodyne HDL-64E S2 user's manual and datasheet (63-HDL64ES2): 64 lasers in two blocks
    // of 32. Upper block +2.0 deg down to -8.33 deg in 1/3 deg steps, lower block -8.83 deg
    // down to -24.33 deg in 1/2 deg steps (vertical field of view 26.9 deg, nominal values;
    // each unit's calibration file refines them by a few hundredths of a degree).
    LidarModel model;
    model.name = "hdl64";
    for (int i = 0; i < 32; ++i) model.elevations_deg.push_back(2.0 - i / 3.0);
    for (int i = 0; i < 32; ++i) model.elevations_deg.push_back(-8.83 - 0.5 * i);
    model.azimuth_resolution_deg = 0.18;  // 2000 firings per revolution at 10 Hz
    model.min_range_m = 0.9;
    model.max_range_m = 120.0;
    model.range_noise_sigma_m = 0.02;  // datasheet: accuracy < 2 cm (1 sigma)
    model.dropout_probability = 0.01;
    return model;
}

LidarModel vls128Preset() {
    // Velodyne VLS-128 (Alpha Prime) per-laser vertical angles, laser id 0..127 in firing
    // order (degrees), as in the VLS128.yaml calibration of the ros-drivers/velodyne driver. Non-uniform: densest (0.11 deg) around the horizon, +15 to -25.
    static const double kElevationsDeg[128] = {
        -11.742, -1.990, 3.400,   -5.290,  -0.780, 4.610,   -4.080,  1.310,   //
        -6.500,  -1.110, 4.280,   -4.410,  0.100,  6.480,   -3.200,  2.190,   //
        -3.860,  1.530,  -9.244,  -1.770,  2.740,  -5.950,  -0.560,  4.830,   //
        -2.980,  2.410,  -6.280,  -0.890,  3.620,  -5.070,  0.320,   7.580,   //
        -0.340,  5.180,  -3.640,  1.750,   -25.00, -2.430,  2.960,   -5.730,  //
        0.540,   9.700,  -2.760,  2.630,   -7.650, -1.550,  3.840,   -4.850,  //
        3.180,   -5.510, -0.120,  5.730,   -4.300, 1.090,   -16.042, -2.210,  //
        4.060,   -4.630, 0.760,   15.000,  -3.420, 1.970,   -6.850,  -1.330,  //
        -5.620,  -0.230, 5.430,   -3.530,  0.980,  -19.582, -2.320,  3.070,   //
        -4.740,  0.650,  11.750,  -2.650,  1.860,  -7.150,  -1.440,  3.950,   //
        -2.100,  3.290,  -5.400,  -0.010,  4.500,  -4.190,  1.200,   -13.565, //
        -1.220,  4.170,  -4.520,  0.870,   6.080,  -3.310,  2.080,   -6.650,  //
        1.420,   -10.346, -1.880, 3.510,   -6.060, -0.670,  4.720,   -3.970,  //
        2.300,   -6.390, -1.000,  4.390,   -5.180, 0.210,   6.980,   -3.090,  //
        4.980,   -3.750, 1.640,   -8.352,  -2.540, 2.850,   -5.840,  -0.450,  //
        8.430,   -2.870, 2.520,   -6.170,  -1.660, 3.730,   -4.960,  0.430};
    LidarModel model;
    model.name = "vls128";
    model.elevations_deg.assign(std::begin(kElevationsDeg), std::end(kElevationsDeg));
    model.azimuth_resolution_deg = 0.2;  // 10 Hz
    model.min_range_m = 1.0;
    model.max_range_m = 245.0;
    model.range_noise_sigma_m = 0.01;  // the paper's LGSVL setting: 1 cm white noise
    model.dropout_probability = 0.01;
    return model;
}

LidarModel lidarPreset(const std::string& name) {
    if (name == "hdl64" || name == "hdl64e") return hdl64ePreset();
    if (name == "vls128") return vls128Preset();
    throw ConfigError("unknown LiDAR preset '" + name + "' (valid: hdl64, vls128)");
}

}  // namespace vdbmap
