// SPDX-License-Identifier: Apache-2.0
// vdbmap.Map: the adaptive-TSDF integrator (paper Sec. 4) driven from numpy, as VDBFusion's
// VDBVolume is. Its keyword arguments are the `integrate.atsdf` stage's options, bound and
// checked by the stage itself, so the defaults are `vdbmap run`'s (docs/python.md).
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "Bindings.h"
#include "pipeline/YamlOptions.h"
#include "stages/TsdfStages.h"
#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"
#include "vdbmap/map/AtsdfIntegrator.h"
#include "vdbmap/map/VdbIO.h"
#include "vdbmap/map/VoxelMap.h"
#include "vdbmap/mesh/MarchingCubes.h"
#include "vdbmap/mesh/MeshArrays.h"
#include "vdbmap/pipeline/StageRegistry.h"

namespace vdbmap::python {
namespace {

std::string shapeText(const py::array& a) {
    std::ostringstream os;
    os << "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) os << (d ? ", " : "") << a.shape(d);
    os << (a.ndim() == 1 ? ",)" : ")");
    return os.str();
}

std::string dtypeText(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

/// The (N, 3) points of `name`: float32 C-contiguous arrays are viewed in place (no copy),
/// float64 or strided ones converted once into `converted`.
PointSpan pointsOf(const py::array& points, const char* name, py::array_t<float>& converted) {
    const bool is_float = points.dtype().is(py::dtype::of<float>()) ||
                          points.dtype().is(py::dtype::of<double>());
    if (points.ndim() != 2 || points.shape(1) != 3 || !is_float)
        throw py::value_error(std::string(name) + ": expected an (N, 3) float32 or float64 array, got shape " +
                              shapeText(points) + " dtype " + dtypeText(points));
    constexpr int kFlags = py::array::c_style | py::array::forcecast;
    if (points.dtype().is(py::dtype::of<float>()) && (points.flags() & py::array::c_style)) {
        return PointSpan(reinterpret_cast<const Vec3f*>(points.data()), static_cast<std::size_t>(points.shape(0)));
    }
    converted = py::array_t<float, kFlags>::ensure(points);
    return PointSpan(reinterpret_cast<const Vec3f*>(converted.data()), static_cast<std::size_t>(converted.shape(0)));
}

/// A 4x4 rigid transform: finite, last row (0 0 0 1), rotation orthonormal with det +1.
Isometry3d poseOf(const py::array& pose, const char* name) {
    const auto fail = [&](const std::string& why) {
        throw py::value_error(std::string(name) + ": expected a 4x4 rigid transform, " + why);
    };
    if (pose.ndim() != 2 || pose.shape(0) != 4 || pose.shape(1) != 4)
        fail("got shape " + shapeText(pose));
    py::array_t<double, py::array::c_style | py::array::forcecast> m;
    try {
        m = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(pose);
    } catch (const py::error_already_set&) {
        m = {};
    }
    if (!m) fail("got dtype " + dtypeText(pose));
    Mat4d T;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) T(r, c) = m.at(r, c);
    if (!T.allFinite()) fail("got a non-finite entry");
    if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
        fail("its last row is not (0, 0, 0, 1)");
    const Mat3d R = T.topLeftCorner<3, 3>();
    const double err = (R.transpose() * R - Mat3d::Identity()).cwiseAbs().maxCoeff();
    if (err > 1e-4 || R.determinant() < 0.0) {
        std::ostringstream os;
        os << "its rotation is not orthonormal with determinant +1 (|R^T R - I| = " << err
           << ", det = " << R.determinant() << ")";
        fail(os.str());
    }
    Isometry3d out = Isometry3d::Identity();
    out.linear() = R;
    out.translation() = T.topRightCorner<3, 1>();
    return out;
}

py::dict statsDict(const IntegrationStats& t) {
    py::dict d;
    d["scans"] = t.scans;
    d["points_in"] = t.points_in;
    d["points_integrated"] = t.points_integrated;
    d["dropped_non_finite"] = t.dropped_non_finite;
    d["dropped_at_origin"] = t.dropped_at_origin;
    d["dropped_range"] = t.dropped_range;
    d["rays"] = t.rays;
    d["voxel_updates"] = t.voxel_updates;
    return d;
}

/// The integrate.atsdf stage bound to the keyword arguments (values given as JSON, which is
/// YAML), initialized: its checks and messages are the pipeline's.
class Map {
public:
    explicit Map(const py::kwargs& kwargs) {
        registerBuiltinStages();
        std::unique_ptr<Stage> stage = StageRegistry::instance().create("integrate.atsdf");
        OptionSpec spec;
        stage->declareOptions(spec);
        py::object dumps = py::module_::import("json").attr("dumps");
        std::vector<detail::YamlEntry> entries;
        for (const auto& [key, value] : kwargs) {
            const std::string k = py::str(key);
            std::string text;
            try {
                text = dumps(value).cast<std::string>();
            } catch (const py::error_already_set&) {
                throw py::value_error(k + ": a number, bool, string or list expected, got " +
                                      py::repr(value).cast<std::string>());
            }
            entries.push_back({k, YAML::Load(text), "keyword argument '" + k + "'"});
        }
        detail::bindEntries(spec, entries, "vdbmap.Map", "keyword arguments");
        stage->initialize();
        py::object loads = py::module_::import("json").attr("loads");
        for (const OptionInfo& info : spec.options())
            options_[py::str(info.key)] = loads(formatOptionValue(spec.value(info.key)));
        settings_ = detail::atsdfStageSettings(*stage);
        map_ = makeVoxelMap(settings_.config, settings_.voxel_size_m);  // as the stage makes it
        integrator_ = std::make_unique<AtsdfIntegrator>(*map_, settings_.config);
    }

    void integrate(const py::array& points, const py::array& T_W_L) {
        py::array_t<float> converted;
        const PointSpan span = pointsOf(points, "points", converted);
        const Isometry3d pose = poseOf(T_W_L, "T_W_L");
        py::gil_scoped_release release;
        integrator_->integrateScan(span, pose);
    }

    py::tuple extractTriangleMesh(double min_weight, int min_component_faces) const {
        MarchingCubesConfig config;
        config.min_weight = min_weight;
        config.min_component_faces = min_component_faces;
        MeshArrays arrays;
        {
            py::gil_scoped_release release;
            arrays = meshArrays(*extractMesh(*map_, config));
        }
        py::array_t<double> vertices(std::vector<py::ssize_t>{static_cast<py::ssize_t>(arrays.vertices_W.size()), 3});
        auto v = vertices.mutable_unchecked<2>();
        for (std::size_t i = 0; i < arrays.vertices_W.size(); ++i)
            for (int c = 0; c < 3; ++c) v(static_cast<py::ssize_t>(i), c) = arrays.vertices_W[i][c];
        py::array_t<std::int32_t> triangles(std::vector<py::ssize_t>{static_cast<py::ssize_t>(arrays.faces.size()), 3});
        auto t = triangles.mutable_unchecked<2>();
        for (std::size_t i = 0; i < arrays.faces.size(); ++i)
            for (int c = 0; c < 3; ++c) t(static_cast<py::ssize_t>(i), c) = static_cast<std::int32_t>(arrays.faces[i][static_cast<std::size_t>(c)]);
        return py::make_tuple(vertices, triangles);
    }

    void saveVdb(const std::string& path) {
        py::gil_scoped_release release;
        integrator_->finalize();  // truncation metadata; the map stays usable (lossless compaction)
        writeMapVdb(path, *map_);
    }

    /// sdf (m) and weight of the voxel nearest to each point; unobserved voxels: nan and 0.
    py::tuple query(const py::array& points) const {
        py::array_t<float> converted;
        const PointSpan span = pointsOf(points, "points", converted);
        const auto n = static_cast<py::ssize_t>(span.size());
        py::array_t<float> sdf(n), weight(n);
        float* s = sdf.mutable_data();
        float* w = weight.mutable_data();
        const double inv = 1.0 / map_->voxelSize();
        for (std::size_t i = 0; i < span.size(); ++i) {
            const Vec3f& p = span[i];
            const openvdb::Coord ijk(static_cast<int>(std::lround(p.x() * inv)), static_cast<int>(std::lround(p.y() * inv)),
                                     static_cast<int>(std::lround(p.z() * inv)));
            float d = 0.0f, wt = 0.0f;
            if (p.allFinite() && map_->probeVoxel(ijk, d, wt) && wt > 0.0f) {
                s[i] = d;
                w[i] = wt;
            } else {
                s[i] = std::nanf("");
                w[i] = 0.0f;
            }
        }
        return py::make_tuple(sdf, weight);
    }

    double voxelSize() const { return settings_.voxel_size_m; }
    py::dict options() const { return options_; }
    py::dict stats() const { return statsDict(integrator_->totals()); }
    std::size_t activeVoxels() const { return static_cast<std::size_t>(map_->activeVoxelCount()); }

private:
    detail::AtsdfStageSettings settings_;
    py::dict options_;
    std::shared_ptr<VoxelMap> map_;
    std::unique_ptr<AtsdfIntegrator> integrator_;
};

}  // namespace

void registerMap(py::module_& m) {
    py::class_<Map>(m, "Map", R"doc(
The adaptive-TSDF map (paper Sec. 4) on OpenVDB grids.

Keyword arguments are the options of the `integrate.atsdf` stage, with its defaults
(`vdbmap describe integrate.atsdf` lists them), e.g. Map(voxel_size_m=0.1,
truncation_mode="adaptive"). A wrong key or value raises vdbmap.ConfigError.)doc")
        .def(py::init<const py::kwargs&>())
        .def("integrate", &Map::integrate, py::arg("points"), py::arg("T_W_L"),
             "Integrates one scan: points (N, 3) float32/float64 in the LiDAR frame L, T_W_L the 4x4 "
             "pose of L in the world W. A C-contiguous float32 array is read in place. Releases the GIL.")
        .def("extract_triangle_mesh", &Map::extractTriangleMesh, py::arg("min_weight") = 0.1,
             py::arg("min_component_faces") = 0,
             "Marching cubes over the observed voxels: (vertices (n, 3) float64, triangles (m, 3) int32)")
        .def("save_vdb", &Map::saveVdb, py::arg("path"),
             "Writes map.vdb (grids 'surface', 'weight', 'truncation'; docs/DATA.md)")
        .def("query", &Map::query, py::arg("points"),
             "(sdf, weight) of the voxel nearest to each point: float32 (N,) arrays; nan and 0 where unobserved")
        .def_property_readonly("voxel_size_m", &Map::voxelSize)
        .def_property_readonly("options", &Map::options, "Every integrate.atsdf option with its value")
        .def_property_readonly("stats", &Map::stats, "Counts over the scans integrated so far")
        .def_property_readonly("active_voxels", &Map::activeVoxels);
}

}  // namespace vdbmap::python
