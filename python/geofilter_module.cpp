// The Python module `geofilter`: the filter table's filters on numpy arrays, without
// MeshLab. A thin adapter like the MeshLab plugins: it reads arrays and keyword arguments,
// calls run_filter, and returns arrays and the report.
#include "core/operators/point_cloud_laplace.h"
#include "exact_pairs.h"
#include "run_filter.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace py = pybind11;
using namespace geofilter;

namespace {

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<long long, py::array::c_style | py::array::forcecast>;

std::string shape_of(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

// The core takes owning row-major matrices; the one copy of the input is 24 bytes a vertex,
// next to the ~1.5 KB a vertex the filter itself needs.
Points points_from(const py::object& object) {
    const py::array raw = py::array::ensure(object);
    if (!raw || raw.ndim() != 2 || raw.shape(1) != 3)
        throw py::value_error("V must be an array of shape (n, 3), got " + (raw ? shape_of(raw) : std::string("a non-array")));
    const DoubleArray a = DoubleArray::ensure(raw);
    if (!a) throw py::type_error("V must hold numbers");
    Points p(a.shape(0), 3);
    if (a.size()) std::memcpy(p.data(), a.data(), sizeof(double) * static_cast<size_t>(a.size()));
    return p;
}

// None or no rows: a point cloud (run_filter filters it through its own Laplacian).
Triangles triangles_from(const py::object& object) {
    if (object.is_none()) return Triangles(0, 3);
    const py::array raw = py::array::ensure(object);
    if (raw && raw.ndim() == 2 && raw.shape(0) == 0 && raw.shape(1) == 3) return Triangles(0, 3);
    if (!raw || raw.ndim() != 2 || raw.shape(1) != 3)
        throw py::value_error("F must be an integer array of shape (m, 3), got " +
                              (raw ? shape_of(raw) : std::string("a non-array")));
    if (raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u')
        throw py::type_error("F must hold integers (vertex indices), got dtype " + std::string(py::str(raw.dtype())));
    const IndexArray a = IndexArray::ensure(raw);
    Triangles t(a.shape(0), 3);
    const auto view = a.unchecked<2>();
    for (py::ssize_t f = 0; f < a.shape(0); ++f)
        for (int k = 0; k < 3; ++k) {
            const long long v = view(f, k);
            if (v < 0 || v > std::numeric_limits<int>::max())
                throw py::value_error("F[" + std::to_string(f) + "] refers to vertex " + std::to_string(v) + ", which does not exist");
            t(f, k) = static_cast<int>(v);
        }
    return t;
}

// selected_faces or selected_vertices (`what`): indices or a boolean mask.
std::vector<int> indices_from(const py::object& object, const std::string& what = "selected_faces",
                              const std::string& item = "face") {
    if (object.is_none()) return {};
    const py::array raw = py::array::ensure(object);
    if (!raw || raw.ndim() != 1) throw py::value_error(what + " must be a 1-D array of " + item + " indices or a boolean mask");
    std::vector<int> faces;
    if (raw.dtype().kind() == 'b') {
        const auto mask = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(raw);
        for (py::ssize_t f = 0; f < mask.size(); ++f)
            if (mask.data()[f]) faces.push_back(static_cast<int>(f));
        return faces;
    }
    if (raw.size() == 0) return faces;
    if (raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u')
        throw py::type_error(what + " must hold " + item + " indices (integers) or be a boolean mask");
    const IndexArray a = IndexArray::ensure(raw);
    for (py::ssize_t i = 0; i < a.size(); ++i) faces.push_back(static_cast<int>(a.data()[i]));
    return faces;
}

py::array_t<double> array_from(const Points& p) {
    py::array_t<double> out({static_cast<py::ssize_t>(p.rows()), static_cast<py::ssize_t>(3)});
    if (p.size()) std::memcpy(out.mutable_data(), p.data(), sizeof(double) * static_cast<size_t>(p.size()));
    return out;
}

ParameterValues values_from(const FilterSpec& spec, const py::kwargs& kwargs, bool has_selection) {
    ParameterValues values = default_values(spec, has_selection);
    for (const auto& item : kwargs) {
        const std::string name = py::str(item.first);
        const ParameterSpec* p = spec.parameter(name);
        if (!p) {
            std::string known;
            for (const auto& q : spec.parameters) known += (known.empty() ? "" : ", ") + q.name;
            throw py::type_error(spec.cli_name + "() got an unknown parameter '" + name + "'; its parameters are: " + known);
        }
        values[name] = py::cast<double>(item.second);
    }
    return values;
}

py::dict report_of(const RunOutput& out) {
    py::dict r;
    r["log"] = out.log;
    r["s1"] = out.s1_used;
    r["solver"] = std::string(solver_name(out.report.solver));
    r["iterations"] = out.report.iterations;
    r["relative_residual"] = out.report.relative_residual;
    r["components"] = out.report.components;
    r["warnings"] = out.report.warnings;
    if (out.normals.rows() > 0) r["normals"] = array_from(out.normals);  // a cloud's estimated normals
    r["seconds"] = py::dict(py::arg("assembly") = out.report.seconds_assembly,
                            py::arg("factorization") = out.report.seconds_factorization,
                            py::arg("solve") = out.report.seconds_solve, py::arg("total") = out.report.seconds_total);
    return r;
}

py::dict feature_of(const FeatureEllipsoid& e) {
    py::dict d;
    d["center"] = std::vector<double>(e.center.data(), e.center.data() + 3);
    d["axes"] = std::vector<std::vector<double>>{{e.axes(0, 0), e.axes(1, 0), e.axes(2, 0)},
                                                 {e.axes(0, 1), e.axes(1, 1), e.axes(2, 1)},
                                                 {e.axes(0, 2), e.axes(1, 2), e.axes(2, 2)}};
    d["radii"] = std::vector<double>(e.radii.data(), e.radii.data() + 3);
    d["radius"] = e.radius;
    d["area"] = e.area;
    d["face_count"] = e.face_count;
    d["point_count"] = e.point_count;
    d["sphere_frequency"] = e.frequency(FeatureShape::Sphere);
    d["cylinder_frequency"] = e.frequency(FeatureShape::Cylinder);
    return d;
}

py::tuple run(const FilterSpec& spec, const py::object& v, const py::object& f, const py::object& selected,
              const py::object& selected_points, const py::kwargs& kwargs) {
    const Points points = points_from(v);
    const Triangles triangles = triangles_from(f);
    const std::vector<int> faces = indices_from(selected);
    std::vector<int> vertices = indices_from(selected_points, "selected_vertices", "vertex");
    if (!vertices.empty() && triangles.rows() > 0)
        throw py::value_error("selected_vertices selects a point cloud's points (F omitted); a mesh's selection is"
                              " selected_faces");
    const bool has_selection = !faces.empty() || !vertices.empty();
    ParameterValues values = values_from(spec, kwargs, has_selection);
    if (kwargs.contains(param::radius) && has_selection && values.at(param::use_selection) != 0)
        throw py::value_error("radius and " + std::string(faces.empty() ? "selected_vertices" : "selected_faces") +
                              " both give the feature: pass one, or useSelection=False");
    RunOutput out;
    {
        py::gil_scoped_release release;  // the solve may take seconds: let other threads run
        out = run_filter(spec, values, RunInput{points, triangles, faces, {}, nullptr, nullptr, {}, exact_pair_factorization(),
                                                std::move(vertices)});
    }
    if (spec.kind == FilterKind::Measure) return py::make_tuple(feature_of(*out.feature), report_of(out));
    return py::make_tuple(array_from(out.points), report_of(out));
}

// The cloud's operator as plain numpy arrays, so that no scipy is needed: K as coordinate
// triplets (each entry once), M's diagonal, the oriented normals for the caller to keep, and the
// local triangles through which every filter of the module runs on the cloud.
py::dict point_cloud_operator(const py::object& v, int neighbours) {
    const Points points = points_from(v);
    PointCloudLaplacian cloud;
    {
        py::gil_scoped_release release;
        cloud = point_cloud_laplacian(points, PointCloudOptions{neighbours});
    }
    const SparseMatrix& k = cloud.laplacian.stiffness;
    const auto entries = static_cast<py::ssize_t>(k.nonZeros());
    py::array_t<long long> rows(entries), cols(entries);
    py::array_t<double> values(entries);
    py::ssize_t e = 0;
    for (Eigen::Index col = 0; col < k.outerSize(); ++col)
        for (SparseMatrix::InnerIterator it(k, col); it; ++it, ++e) {
            rows.mutable_data()[e] = it.row();
            cols.mutable_data()[e] = col;
            values.mutable_data()[e] = it.value();
        }
    const Eigen::VectorXd& m = cloud.laplacian.mass;
    py::array_t<double> mass(static_cast<py::ssize_t>(m.size()));
    std::copy(m.data(), m.data() + m.size(), mass.mutable_data());
    const Triangles& t = cloud.local_triangles;
    py::array_t<int> triangles({static_cast<py::ssize_t>(t.rows()), static_cast<py::ssize_t>(3)});
    if (t.size()) std::memcpy(triangles.mutable_data(), t.data(), sizeof(int) * static_cast<size_t>(t.size()));
    py::dict d;
    d["K"] = py::make_tuple(rows, cols, values);
    d["M"] = mass;
    d["normals"] = array_from(cloud.normals);
    d["triangles"] = triangles;
    return d;
}

} // namespace

PYBIND11_MODULE(geofilter, m) {
    m.doc() = "GeoFilter (Kim & Rossignac 2005): mesh filters whose frequencies come from the size of a feature. "
              "Each filter takes V (n x 3 float array) and F (m x 3 integer array) and returns (V_filtered, report). "
              "Frequencies are eigenvalues of the Laplace-Beltrami operator, in 1/length^2: a sphere-like feature of "
              "radius r has s = 2/r^2, a cylinder-like one 1/r^2.";
    py::register_exception<Error>(m, "Error", PyExc_ValueError);

    for (const FilterSpec& spec : filter_table()) {
        const FilterSpec* s = &spec;
        std::string doc = spec.name + ". " + spec.description + "\n\nParameters (keyword, table defaults):";
        for (const auto& p : spec.parameters)
            doc += "\n  " + p.name + " = " +
                   (p.type == ParameterType::Length && p.default_value != 0
                        ? format_number(100 * p.default_value) + " % of the diagonal"
                        : format_number(p.default_value)) +
                   ": " + p.help;
        if (spec.kind == FilterKind::Measure) {
            m.def(
                spec.cli_name.c_str(),
                [s](const py::object& v, const py::object& f, const py::object& selected, const py::object& points) {
                    return run(*s, v, f, selected, points, py::kwargs());
                },
                py::arg("V"), py::arg("F") = py::none(), py::arg("selected_faces") = py::none(), py::kw_only(),
                py::arg("selected_vertices") = py::none(),
                ("Fits the feature ellipsoid to the selected faces (indices or a boolean mask), or on a point cloud"
                 " (F None) to selected_vertices; returns (feature, report)."
                 "\n\n" + doc).c_str());
            continue;
        }
        m.def(
            spec.cli_name.c_str(),
            [s](const py::object& v, const py::object& f, const py::object& selected, const py::object& points,
                const py::kwargs& kwargs) { return run(*s, v, f, selected, points, kwargs); },
            py::arg("V"), py::arg("F") = py::none(), py::kw_only(), py::arg("selected_faces") = py::none(),
            py::arg("selected_vertices") = py::none(),
            ("Returns (V_filtered, report). selected_faces (indices or a boolean mask) is the feature, as MeshLab's"
             " selection (useSelection); radius=r gives its size instead (default: a few % of the diagonal)."
             " F omitted, None or empty: V is a point cloud, filtered through its own Laplacian"
             " (point_cloud_laplacian), its selection selected_vertices and report['normals'] its estimated"
             " normals.\n\n" +
             doc).c_str());
    }

    m.def(
        "design",
        [](const std::string& name, const py::kwargs& kwargs) {
            const FilterSpec* spec = find_filter(name);
            if (!spec || spec->kind == FilterKind::Measure) throw py::value_error("no GeoFilter filter is called '" + name + "'");
            const ParameterValues values = values_from(*spec, kwargs, false);
            std::vector<std::string> log;
            return design_from_values(*spec, values, nullptr, log);
        },
        py::arg("name"),
        "The transfer function G(s) a filter would apply, from the same parameters (no mesh needed).");

    py::class_<TransferFunction>(m, "TransferFunction")
        .def("__call__", [](const TransferFunction& g, double s) { return g(s); }, py::arg("s"))
        .def(
            "__call__",
            [](const TransferFunction& g, const DoubleArray& s) {
                DoubleArray out(std::vector<py::ssize_t>(s.shape(), s.shape() + s.ndim()));
                for (py::ssize_t i = 0; i < s.size(); ++i) out.mutable_data()[i] = g(s.data()[i]);
                return out;
            },
            py::arg("s"))
        .def_property_readonly("poles", [](const TransferFunction& g) { return g.poles; })
        .def_property_readonly("at_infinity", &TransferFunction::at_infinity)
        .def("__repr__", &TransferFunction::describe);

    const std::string cloud_doc =
        "The Laplace-Beltrami operator of a point cloud V (n x 3), in the units of the mesh filters' (a sphere of "
        "radius r: 2/r^2): each point's Delaunay fan in its tangent plane (fitted to its k nearest neighbours) among "
        "the nearest " + std::to_string(PointCloudOptions{}.fan_candidates) + " (k, if fewer), the cotangent "
        "stiffness and lumped mass of all fans, divided by 3 (Sharp & Crane 2020). Returns a dict: K = (rows, cols, "
        "values), each entry once (dense: Kd = np.zeros((n, n)); Kd[rows, cols] = values), M = the lumped mass (n,), "
        "normals = unit normals oriented consistently (n, 3), triangles = the fans (m, 3): any filter of this module "
        "run as filter(V, triangles) filters the cloud with this operator.";
    m.def("point_cloud_laplacian", &point_cloud_operator, py::arg("V"), py::arg("k") = PointCloudOptions{}.neighbours,
          cloud_doc.c_str());

    py::list names;
    for (const FilterSpec& spec : filter_table()) names.append(spec.cli_name);
    m.attr("filters") = names;
}
