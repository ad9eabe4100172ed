// SPDX-License-Identifier: Apache-2.0
// A closed-form street for moving-object tests (issue 33): flat ground z = 0, a thin pole, a
// parked box and a box driving along the street, scanned by an HDL-64-like LiDAR that moves
// along +x. Every return knows what it hit, so recall and precision are exact.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "vdbmap/core/Types.h"
#include "vdbmap/io/Dataset.h"
#include "vdbmap/io/LidarLabels.h"
#include "vdbmap/io/PointCloudIO.h"

namespace vdbmap::test {

enum class Hit : std::uint8_t { Ground = 0, Pole = 1, Parked = 2, Mover = 3 };

struct AxisBox {
    Vec3d min, max;
};

struct DynamicSceneOptions {
    int frames = 31;
    double ego_speed_m = 1.0;           ///< per frame, along +x
    double sensor_height_m = 1.73;
    Vec3d mover_start{12.0, 4.0, 0.0};  ///< centre of the mover's footprint at frame 0
    Vec3d mover_step{1.8, 0.0, 0.0};    ///< its motion per frame
    Vec3d mover_size{4.0, 1.8, 1.5};
    double mover_clearance_m = 0.2;     ///< its underside above the ground
    bool mover_moves = true;            ///< false: it stays at mover_start (a parked car)
    int mover_stop_frame = -1;          ///< >= 0: it stops there from this frame on
    Vec3d pole{20.0, -3.0, 0.0};
    double pole_radius_m = 0.05, pole_height_m = 4.0;
    AxisBox parked{{30.0, -7.0, 0.0}, {34.0, -5.2, 1.5}};
    int beams = 64;
    double elev_top_deg = 2.0, elev_bottom_deg = -24.8, azimuth_step_deg = 0.18;
    double max_range_m = 80.0;
};

struct DynamicScan {
    std::vector<Vec3f> points_L;
    std::vector<Hit> hits;
    Isometry3d T_W_L = Isometry3d::Identity();
};

inline AxisBox moverBox(const DynamicSceneOptions& o, int frame) {
    const int moved = o.mover_stop_frame >= 0 ? std::min(frame, o.mover_stop_frame) : frame;
    const Vec3d c = o.mover_start + (o.mover_moves ? static_cast<double>(moved) : 0.0) * o.mover_step;
    const Vec3d h = 0.5 * o.mover_size;
    return {{c.x() - h.x(), c.y() - h.y(), o.mover_clearance_m},
            {c.x() + h.x(), c.y() + h.y(), o.mover_clearance_m + o.mover_size.z()}};
}

/// Ray parameter of the entry into `b`, or +inf (slab test).
inline double rayBox(const Vec3d& o, const Vec3d& d, const AxisBox& b) {
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) {
            if (o[a] < b.min[a] || o[a] > b.max[a]) return std::numeric_limits<double>::infinity();
            continue;
        }
        double ta = (b.min[a] - o[a]) / d[a], tb = (b.max[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1 && t0 > 0.0 ? t0 : std::numeric_limits<double>::infinity();
}

/// Ray parameter of the vertical cylinder's side, or +inf.
inline double rayPole(const Vec3d& o, const Vec3d& d, const DynamicSceneOptions& s) {
    const double dx = o.x() - s.pole.x(), dy = o.y() - s.pole.y();
    const double a = d.x() * d.x() + d.y() * d.y();
    const double b = 2.0 * (dx * d.x() + dy * d.y());
    const double c = dx * dx + dy * dy - s.pole_radius_m * s.pole_radius_m;
    const double disc = b * b - 4.0 * a * c;
    if (a < 1e-12 || disc < 0.0) return std::numeric_limits<double>::infinity();
    const double t = (-b - std::sqrt(disc)) / (2.0 * a);
    const double z = o.z() + t * d.z();
    return t > 0.0 && z >= 0.0 && z <= s.pole_height_m ? t : std::numeric_limits<double>::infinity();
}

/// The scan of frame `frame` (sensor frame L axis-aligned with W).
inline DynamicScan dynamicScan(const DynamicSceneOptions& s, int frame) {
    DynamicScan scan;
    const Vec3d o(s.ego_speed_m * frame, 0.0, s.sensor_height_m);
    scan.T_W_L.translation() = o;
    const AxisBox mover = moverBox(s, frame);
    const double deg = 3.14159265358979323846 / 180.0;
    const int columns = static_cast<int>(std::lround(360.0 / s.azimuth_step_deg));
    for (int b = 0; b < s.beams; ++b) {
        const double e = (s.elev_top_deg + (s.elev_bottom_deg - s.elev_top_deg) * b / (s.beams - 1)) * deg;
        for (int c = 0; c < columns; ++c) {
            const double a = (c * s.azimuth_step_deg - 180.0 + 0.05) * deg;
            const Vec3d d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
            double t = d.z() < 0.0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
            Hit hit = Hit::Ground;
            const double tp = rayPole(o, d, s), tb = rayBox(o, d, s.parked), tm = rayBox(o, d, mover);
            if (tp < t) t = tp, hit = Hit::Pole;
            if (tb < t) t = tb, hit = Hit::Parked;
            if (tm < t) t = tm, hit = Hit::Mover;
            if (!(t <= s.max_range_m)) continue;
            scan.points_L.push_back((t * d).cast<float>());
            scan.hits.push_back(hit);
        }
    }
    return scan;
}

/// Writes the scans as a generic dataset (scans/NNNNNN.bin, poses.txt) in `dir`; with
/// `labels`, also labels/NNNNNN.label with SemanticKITTI ids (mover: 252 moving-car, else 40
/// road / 80 pole / 10 car) when `label_mover_moving`, else 10 for the mover too.
inline void writeDynamicDataset(const std::filesystem::path& dir, const std::vector<DynamicScan>& scans,
                                bool labels = false, bool label_mover_moving = true) {
    std::filesystem::create_directories(dir / "scans");
    if (labels) std::filesystem::create_directories(dir / "labels");
    std::ofstream poses(dir / "poses.txt");
    poses << std::setprecision(17);
    for (std::size_t f = 0; f < scans.size(); ++f) {
        std::ostringstream name;
        name << std::setw(6) << std::setfill('0') << f;
        PointCloud cloud;
        cloud.points = scans[f].points_L;
        cloud.intensity.assign(cloud.points.size(), 0.5f);
        writeBin(dir / "scans" / (name.str() + ".bin"), cloud);
        const Eigen::Matrix4d m = scans[f].T_W_L.matrix();
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 4; ++c) poses << m(r, c) << (r == 2 && c == 3 ? "\n" : " ");
        }
        if (labels) {
            LidarLabels l;
            for (const Hit h : scans[f].hits) {
                std::uint32_t id = h == Hit::Ground ? 40 : h == Hit::Pole ? 80 : 10;
                if (h == Hit::Mover && label_mover_moving) id = 252;
                l.raw.push_back(id);
            }
            writeLidarLabels(dir / "labels" / (name.str() + ".label"), l);
        }
    }
}

/// An empty folder below the system's temporary folder, named `prefix` + `name`.
inline std::filesystem::path freshScratch(const std::string& prefix, const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

/// The generic dataset writeDynamicDataset wrote in `dir` (with its labels when it wrote them).
inline std::shared_ptr<Dataset> openDynamicDataset(const std::filesystem::path& dir) {
    DatasetConfig dc;
    dc.format = "generic";
    dc.path = dir.string();
    dc.max_range_m = 100.0;
    if (std::filesystem::exists(dir / "labels")) dc.labels_dir = "labels";
    return Dataset::open(dc);
}

}  // namespace vdbmap::test
