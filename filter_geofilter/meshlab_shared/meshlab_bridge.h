// What the MeshLab adapters (2020.09 MeshFilterInterface, 2022.02+ FilterPlugin) have in
// common: CMeshO, RichParameterList, Value and the Rich* parameter classes are spelled and
// behave the same in both APIs, so the translation between them and the core lives here
// once. What differs (the plugin interface, logging, how errors and results are returned,
// how a layer is added) stays in each adapter.
//
// Include it from an adapter's .cpp AFTER that adapter's MeshLab API header: the names
// above come from there, and which header declares them is exactly what differs.
#pragma once

#include "exact_pairs.h"
#include "run_filter.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/allocate.h>

#include <QString>
#include <QStringList>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace geofilter {
namespace meshlab_bridge {

inline QString qs(const std::string &s) { return QString::fromStdString(s); }

// A length: an absolute value shown with its percentage of a range. MeshLab 2025.07 renamed
// RichAbsPerc to RichPercentage; both hold the absolute value.
#if __has_include(<common/parameters/rich_parameter/rich_percentage.h>)
using RichLength = RichPercentage;
#else
using RichLength = RichAbsPerc;
#endif

// A Rich* parameter of the table's name, label and help. 2022.02+ dialogs fold the ones marked
// advanced behind a button; 2020.09's constructors have no such flag.
template <class Rich, class... Value>
Rich richParameter(const ParameterSpec &p, Value &&...value)
{
#if __has_include(<common/plugins/interfaces/filter_plugin.h>)
	return Rich(qs(p.name), std::forward<Value>(value)..., qs(p.label), qs(p.help), p.expert);
#else
	return Rich(qs(p.name), std::forward<Value>(value)..., qs(p.label), qs(p.help));
#endif
}

inline bool hasSelectedFaces(const CMeshO &cm)
{
	for (const auto &f : cm.face)
		if (!f.IsD() && f.IsS()) return true;
	return false;
}

// The mesh's size as the core measures it (the live vertices' bounding box), so that a
// percentage in the dialog and a default radius mean what they mean in the other front ends.
inline double diagonalOf(const CMeshO &cm)
{
	vcg::Box3<double> box;
	for (const auto &v : cm.vert)
		if (!v.IsD()) box.Add(vcg::Point3d(v.cP()[0], v.cP()[1], v.cP()[2]));
	return box.IsNull() ? 0.0 : box.Diag();
}

// The dialog, a script and pymeshlab all build their parameters from this list, so the
// table's names, labels, help and defaults reach every front end unchanged. `cm` is the
// current mesh (null: none), whose selection and size set the defaults.
inline void addParameters(const FilterSpec &spec, const CMeshO *cm, RichParameterList &par)
{
	// A selection on the mesh almost always means "this is the feature": default to using it.
	const double diagonal = cm ? diagonalOf(*cm) : 0.0;
	const ParameterValues defaults = default_values(spec, cm != nullptr && hasSelectedFaces(*cm), diagonal);
	for (const ParameterSpec &p : spec.parameters) {
		const double d = defaults.at(p.name);
		switch (p.type) {
		// MeshLab's convention for a length: absolute, or a percentage of the diagonal (0 to 100 %).
		case ParameterType::Length: par.addParam(richParameter<RichLength>(p, d, 0.0, diagonal > 0 ? diagonal : 1.0)); break;
		case ParameterType::Float: par.addParam(richParameter<RichFloat>(p, d)); break;
		case ParameterType::Bool: par.addParam(richParameter<RichBool>(p, d != 0)); break;
		case ParameterType::Int: par.addParam(richParameter<RichInt>(p, int(std::lround(d)))); break;
		case ParameterType::Enum: {
			QStringList choices;
			for (const std::string &c : p.choices) choices << qs(c);
			par.addParam(richParameter<RichEnum>(p, int(std::lround(d)), choices));
			break;
		}
		}
	}
}

// Reads every parameter of the table by its declared type. A script may carry a value of
// another Rich type under the same name; MeshLab's getters assert on that (meshlabserver
// aborts), so check the type first and refuse with a message naming the parameter.
inline ParameterValues readValues(const FilterSpec &spec, const RichParameterList &par, bool hasSelection)
{
	ParameterValues values = default_values(spec, hasSelection);
	for (const ParameterSpec &p : spec.parameters) {
		const QString name = qs(p.name);
		if (!par.hasParameter(name)) continue;   // keep the default, as MeshLab itself would
		const Value &v = par.getParameterByName(name).value();
		const char *expected = nullptr;
		switch (p.type) {
		case ParameterType::Float:
			if (v.isFloat()) values[p.name] = v.getFloat();
			else if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichFloat";
			break;
		case ParameterType::Length:   // RichAbsPerc holds the absolute length
			if (v.isFloat()) values[p.name] = v.getFloat();
			else expected = "RichAbsPerc (RichPercentage)";
			break;
		case ParameterType::Bool:
			if (v.isBool()) values[p.name] = v.getBool() ? 1 : 0;
			else expected = "RichBool";
			break;
		case ParameterType::Int:
			// 2020.09's RichEnum derives from RichInt; in 2022+ both hold an int value.
			if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichInt";
			break;
		case ParameterType::Enum:
			if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichEnum";
			break;
		}
		if (expected)
			throw Error("parameter " + p.name + " must be a " + expected + " (the script gives it as " +
			            v.typeName().toStdString() + ")");
		if (p.type == ParameterType::Enum) {
			const double i = values[p.name];
			if (i < 0 || i >= double(p.choices.size()))
				throw Error("parameter " + p.name + " must be an index from 0 to " + std::to_string(p.choices.size() - 1) +
				            " (got " + std::to_string(int(i)) + ")");
		}
	}
	return values;
}

// The core works on a compact, double-precision copy; `vertex` maps its rows back.
struct CoreMesh
{
	Points points;
	Triangles triangles;
	std::vector<int> selectedFaces;
	std::vector<int> selectedVertices;   // a point cloud's selection (compact indices)
	std::vector<CMeshO::VertexPointer> vertex;
	std::vector<double> quality;   // per-vertex quality when the mesh has it (region = quality)
};

inline CoreMesh copyMesh(CMeshO &cm)
{
	CoreMesh out;
	std::vector<int> compact(cm.vert.size(), -1);
	for (size_t i = 0; i < cm.vert.size(); ++i) {
		if (cm.vert[i].IsD()) continue;
		compact[i] = int(out.vertex.size());
		if (cm.vert[i].IsS()) out.selectedVertices.push_back(compact[i]);
		out.vertex.push_back(&cm.vert[i]);
	}
	out.points.resize(Eigen::Index(out.vertex.size()), 3);
	for (size_t i = 0; i < out.vertex.size(); ++i)
		for (int k = 0; k < 3; ++k) out.points(Eigen::Index(i), k) = out.vertex[i]->P()[k];
	if (vcg::tri::HasPerVertexQuality(cm))
		for (const auto *v : out.vertex) out.quality.push_back(double(v->Q()));

	std::vector<int> rows;
	rows.reserve(cm.face.size() * 3);
	for (auto &f : cm.face) {
		if (f.IsD()) continue;
		for (int k = 0; k < 3; ++k) {
			const size_t vi = vcg::tri::Index(cm, f.V(k));
			if (vi >= compact.size() || compact[vi] < 0)
				throw Error("the mesh has a face that uses a deleted vertex: run Filters > Cleaning and Repairing"
				            " > Remove Unreferenced Vertices / Compact, then try again");
			rows.push_back(compact[vi]);
		}
		if (f.IsS()) out.selectedFaces.push_back(int(rows.size() / 3 - 1));
	}
	out.triangles.resize(Eigen::Index(rows.size() / 3), 3);
	std::copy(rows.begin(), rows.end(), out.triangles.data());   // row-major, as built
	return out;
}

// MeshLab's progress bar takes a percentage and a C string; the core reports a fraction
// and a stage. Returns true always: neither API's front ends offer a way to cancel.
inline ProgressCallback progressFor(vcg::CallBackPos *cb, const FilterSpec &spec)
{
	if (cb == nullptr) return {};
	const std::string prefix = spec.name + ": ";
	return [cb, prefix](double fraction, const std::string &stage) {
		cb(std::clamp(int(std::lround(100 * fraction)), 0, 100), (prefix + stage).c_str());
		return true;
	};
}

// What both adapters do between reading a filter call and writing its result: copy the
// current mesh, read the parameters, run the filter. Throws geofilter::Error.
struct FilterRun
{
	CoreMesh mesh;
	RunOutput out;
};

inline FilterRun runOnMesh(const FilterSpec &spec, CMeshO &cm, const RichParameterList &par, vcg::CallBackPos *cb,
                           FilterCache &cache)
{
	FilterRun run;
	run.mesh = copyMesh(cm);
	const ParameterValues values = readValues(spec, par, !run.mesh.selectedFaces.empty());
	run.out = run_filter(spec, values,
	                     RunInput{run.mesh.points, run.mesh.triangles, run.mesh.selectedFaces, progressFor(cb, spec),
	                              &run.mesh.quality, &cache, {}, exact_pair_factorization(),
	                              run.mesh.selectedVertices});
	return run;
}

// Writes the filtered coordinates back. Everything is converted (and refused if it does not
// fit the mesh's scalar type) before the first vertex moves, so a refusal leaves the mesh
// bit-for-bit as it was.
// `cloud_normals`: a point cloud's normals as the filter estimated them (empty for a mesh),
// written into the layer as MeshLab's own "Compute normals for point sets" would, so that
// the cloud renders lit and MLS or Poisson reconstruction can follow.
inline void storeFiltered(CMeshO &cm, const CoreMesh &mesh, const Points &filtered, const Points &cloud_normals)
{
	using Scalar = CMeshO::ScalarType;
	if (filtered.rows() != mesh.points.rows())
		throw Error("internal: the filter returned " + std::to_string(filtered.rows()) + " points for " +
		            std::to_string(mesh.points.rows()) + " vertices");
	// 1e37 rather than the exact maximum: normals and areas of such a mesh would overflow anyway.
	const double limit = std::min(1e37, double(std::numeric_limits<Scalar>::max()));
	std::vector<CMeshO::CoordType> moved(mesh.vertex.size());
	for (size_t i = 0; i < moved.size(); ++i) {
		for (int k = 0; k < 3; ++k) {
			const double x = filtered(Eigen::Index(i), k);
			if (!std::isfinite(x) || std::abs(x) > limit)
				throw Error(std::string("the filtered coordinates are not finite in ") +
				            (sizeof(Scalar) == sizeof(float) ? "single" : "double") +
				            " precision: the transfer function amplifies this mesh too much");
			moved[i][k] = Scalar(x);
		}
	}
	for (size_t i = 0; i < moved.size(); ++i) mesh.vertex[i]->P() = moved[i];
	vcg::tri::UpdateBounding<CMeshO>::Box(cm);
	if (cm.fn > 0) {
		vcg::tri::UpdateNormal<CMeshO>::PerFaceNormalized(cm);
		vcg::tri::UpdateNormal<CMeshO>::PerVertexAngleWeighted(cm);
	} else if (cloud_normals.rows() == Eigen::Index(mesh.vertex.size())) {
		for (size_t i = 0; i < mesh.vertex.size(); ++i)
			for (int k = 0; k < 3; ++k) mesh.vertex[i]->N()[k] = Scalar(cloud_normals(Eigen::Index(i), k));
	}
}

// The ellipsoid layer's per-vertex colour: an orange that stands out against MeshLab's grey
// meshes. The adapters also mark the layer as having vertex colour, or MeshLab ignores it.
inline vcg::Color4b ellipsoidColour() { return vcg::Color4b(255, 128, 0, 255); }

// Fills an empty mesh with the fitted ellipsoid (the caller creates the layer: that differs
// between the APIs).
inline void fillEllipsoid(CMeshO &cm, const Mesh &e)
{
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, size_t(e.points.rows()));
	std::vector<CMeshO::VertexPointer> v;
	for (Eigen::Index i = 0; i < e.points.rows(); ++i, ++vi) {
		vi->P() = CMeshO::CoordType(CMeshO::ScalarType(e.points(i, 0)), CMeshO::ScalarType(e.points(i, 1)),
		                            CMeshO::ScalarType(e.points(i, 2)));
		vi->C() = ellipsoidColour();
		v.push_back(&*vi);
	}
	auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(cm, size_t(e.triangles.rows()));
	for (Eigen::Index i = 0; i < e.triangles.rows(); ++i, ++fi)
		for (int k = 0; k < 3; ++k) fi->V(k) = v[size_t(e.triangles(i, k))];
	vcg::tri::UpdateBounding<CMeshO>::Box(cm);
	vcg::tri::UpdateNormal<CMeshO>::PerFaceNormalized(cm);
	vcg::tri::UpdateNormal<CMeshO>::PerVertexAngleWeighted(cm);
}

} // namespace meshlab_bridge
} // namespace geofilter
