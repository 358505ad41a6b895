#include "filter_geofilter_plugin.h"

#include "run_filter.h"

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/allocate.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <vector>

namespace {

const std::vector<geofilter::FilterSpec> &table() { return geofilter::filter_table(); }

QString qs(const std::string &s) { return QString::fromStdString(s); }

bool hasSelectedFaces(const CMeshO &cm)
{
	for (const auto &f : cm.face)
		if (!f.IsD() && f.IsS()) return true;
	return false;
}

// Reads every parameter of the table by its declared type. A script may carry a value of
// another Rich type under the same name; MeshLab's getters assert on that (meshlabserver
// aborts), so check the type first and refuse with a message naming the parameter.
geofilter::ParameterValues readValues(const geofilter::FilterSpec &spec, const RichParameterList &par, bool hasSelection)
{
	geofilter::ParameterValues values = geofilter::default_values(spec, hasSelection);
	for (const geofilter::ParameterSpec &p : spec.parameters) {
		const QString name = qs(p.name);
		if (!par.hasParameter(name)) continue;   // keep the default, as MeshLab itself would
		const Value &v = par.getParameterByName(name).value();
		const char *expected = nullptr;
		switch (p.type) {
		case geofilter::ParameterType::Float:
			if (v.isFloat()) values[p.name] = v.getFloat();
			else if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichFloat";
			break;
		case geofilter::ParameterType::Bool:
			if (v.isBool()) values[p.name] = v.getBool() ? 1 : 0;
			else expected = "RichBool";
			break;
		case geofilter::ParameterType::Int:
			// RichEnum derives from RichInt in MeshLab; either carries an int.
			if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichInt";
			break;
		case geofilter::ParameterType::Enum:
			if (v.isInt()) values[p.name] = v.getInt();
			else expected = "RichEnum";
			break;
		}
		if (expected)
			throw geofilter::Error("parameter " + p.name + " must be a " + expected + " (the script gives it as " +
			                       v.typeName().toStdString() + ")");
		if (p.type == geofilter::ParameterType::Enum) {
			const double i = values[p.name];
			if (i < 0 || i >= double(p.choices.size()))
				throw geofilter::Error("parameter " + p.name + " must be an index from 0 to " +
				                       std::to_string(p.choices.size() - 1) + " (got " +
				                       std::to_string(int(i)) + ")");
		}
	}
	return values;
}

// The core works on a compact, double-precision copy; `vertex` maps its rows back.
struct CoreMesh
{
	geofilter::Points points;
	geofilter::Triangles triangles;
	std::vector<int> selectedFaces;
	std::vector<CMeshO::VertexPointer> vertex;
};

CoreMesh copyMesh(CMeshO &cm)
{
	CoreMesh out;
	std::vector<int> compact(cm.vert.size(), -1);
	for (size_t i = 0; i < cm.vert.size(); ++i) {
		if (cm.vert[i].IsD()) continue;
		compact[i] = int(out.vertex.size());
		out.vertex.push_back(&cm.vert[i]);
	}
	out.points.resize(Eigen::Index(out.vertex.size()), 3);
	for (size_t i = 0; i < out.vertex.size(); ++i)
		for (int k = 0; k < 3; ++k) out.points(Eigen::Index(i), k) = out.vertex[i]->P()[k];

	std::vector<int> rows;
	rows.reserve(cm.face.size() * 3);
	for (auto &f : cm.face) {
		if (f.IsD()) continue;
		for (int k = 0; k < 3; ++k) {
			const size_t vi = vcg::tri::Index(cm, f.V(k));
			if (vi >= compact.size() || compact[vi] < 0)
				throw geofilter::Error("the mesh has a face that uses a deleted vertex: run Filters > Cleaning and Repairing"
				                       " > Remove Unreferenced Vertices / Compact, then try again");
			rows.push_back(compact[vi]);
		}
		if (f.IsS()) out.selectedFaces.push_back(int(rows.size() / 3 - 1));
	}
	out.triangles.resize(Eigen::Index(rows.size() / 3), 3);
	std::copy(rows.begin(), rows.end(), out.triangles.data());   // row-major, as built
	return out;
}

void addEllipsoidLayer(MeshDocument &md, const geofilter::Mesh &e)
{
	// Not made current: the user keeps working on the mesh they measured.
	MeshModel *layer = md.addNewMesh("", "GeoFilter ellipsoid", false);
	CMeshO &cm = layer->cm;
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, size_t(e.points.rows()));
	std::vector<CMeshO::VertexPointer> v;
	for (Eigen::Index i = 0; i < e.points.rows(); ++i, ++vi) {
		vi->P() = CMeshO::CoordType(CMeshO::ScalarType(e.points(i, 0)), CMeshO::ScalarType(e.points(i, 1)),
		                            CMeshO::ScalarType(e.points(i, 2)));
		v.push_back(&*vi);
	}
	auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(cm, size_t(e.triangles.rows()));
	for (Eigen::Index i = 0; i < e.triangles.rows(); ++i, ++fi)
		for (int k = 0; k < 3; ++k) fi->V(k) = v[size_t(e.triangles(i, k))];
	vcg::tri::UpdateBounding<CMeshO>::Box(cm);
	vcg::tri::UpdateNormal<CMeshO>::PerFaceNormalized(cm);
	vcg::tri::UpdateNormal<CMeshO>::PerVertexAngleWeighted(cm);
}

} // namespace

FilterGeoFilterPlugin::FilterGeoFilterPlugin()
{
	for (int i = 0; i < int(table().size()); ++i) typeList << i;
	// The action text is what menus show and scripts name, so it must be the table's name.
	for (FilterIDType t : types()) actionList << new QAction(filterName(t), this);
}

QString FilterGeoFilterPlugin::pluginName() const { return "FilterGeoFilter"; }

QString FilterGeoFilterPlugin::filterName(FilterIDType filter) const
{
	return filter >= 0 && filter < int(table().size()) ? qs(table()[size_t(filter)].name) : QString();
}

QString FilterGeoFilterPlugin::filterInfo(FilterIDType filter) const
{
	// Parameter help is shown as tooltips in the dialog, so the description is enough here.
	return filter >= 0 && filter < int(table().size()) ? qs(table()[size_t(filter)].description) : QString();
}

const geofilter::FilterSpec &FilterGeoFilterPlugin::spec(QAction *a) const { return table()[size_t(ID(a))]; }

MeshFilterInterface::FilterClass FilterGeoFilterPlugin::getClass(QAction *a)
{
	// All entries sit together under Smoothing, Fairing and Deformation; Measure is also
	// listed with MeshLab's other measuring filters.
	if (spec(a).kind == geofilter::FilterKind::Measure)
		return FilterClass(MeshFilterInterface::Smoothing | MeshFilterInterface::Measure);
	return MeshFilterInterface::Smoothing;
}

// The core builds its own connectivity from the vertex/face arrays.
int FilterGeoFilterPlugin::getRequirements(QAction *) { return MeshModel::MM_NONE; }

int FilterGeoFilterPlugin::postCondition(QAction *a) const
{
	if (spec(a).kind == geofilter::FilterKind::Measure) return MeshModel::MM_NONE;
	return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
}

MeshFilterInterface::FILTER_ARITY FilterGeoFilterPlugin::filterArity(QAction *) const { return SINGLE_MESH; }

void FilterGeoFilterPlugin::initParameterSet(QAction *a, MeshDocument &md, RichParameterList &par)
{
	const geofilter::FilterSpec &s = spec(a);
	// A selection on the mesh almost always means "this is the feature": default to using it.
	const bool sel = md.mm() != nullptr && hasSelectedFaces(md.mm()->cm);
	const geofilter::ParameterValues defaults = geofilter::default_values(s, sel);
	for (const geofilter::ParameterSpec &p : s.parameters) {
		const QString name = qs(p.name), label = qs(p.label), help = qs(p.help);
		const double d = defaults.at(p.name);
		switch (p.type) {
		case geofilter::ParameterType::Float: par.addParam(RichFloat(name, float(d), label, help)); break;
		case geofilter::ParameterType::Bool: par.addParam(RichBool(name, d != 0, label, help)); break;
		case geofilter::ParameterType::Int: par.addParam(RichInt(name, int(std::lround(d)), label, help)); break;
		case geofilter::ParameterType::Enum: {
			QStringList choices;
			for (const std::string &c : p.choices) choices << qs(c);
			par.addParam(RichEnum(name, int(std::lround(d)), choices, label, help));
			break;
		}
		}
	}
}

bool FilterGeoFilterPlugin::fail(const std::string &message)
{
	errorMessage = qs(message);
	// meshlabserver prints the log but never errorMessage: without this line a script
	// run would only say "Problem with filter".
	Log(GLLogStream::WARNING, "GeoFilter error: " + message);
	return false;
}

bool FilterGeoFilterPlugin::applyFilter(QAction *a, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb)
{
	errorMessage.clear();   // MeshLab keeps the previous run's message otherwise
	const geofilter::FilterSpec &s = spec(a);
	MeshModel *m = md.mm();
	if (m == nullptr) return fail("there is no current mesh: open or create a mesh first");
	try {
		CoreMesh mesh = copyMesh(m->cm);
		const geofilter::ParameterValues values = readValues(s, par, !mesh.selectedFaces.empty());

		geofilter::ProgressCallback progress;
		if (cb != nullptr) {
			const std::string prefix = s.name + ": ";
			progress = [cb, prefix](double fraction, const std::string &stage) {
				cb(std::clamp(int(std::lround(100 * fraction)), 0, 100), (prefix + stage).c_str());
				return true;   // MeshLab 2020.09 has no way to cancel a running filter
			};
		}
		const geofilter::RunOutput out =
		    geofilter::run_filter(s, values, geofilter::RunInput{mesh.points, mesh.triangles, mesh.selectedFaces, progress});

		if (s.kind == geofilter::FilterKind::Measure) {
			if (out.ellipsoid_mesh) addEllipsoidLayer(md, *out.ellipsoid_mesh);
		} else {
			if (out.points.rows() != mesh.points.rows())
				throw geofilter::Error("internal: the filter returned " + std::to_string(out.points.rows()) +
				                       " points for " + std::to_string(mesh.points.rows()) + " vertices");
			// Convert everything before touching the mesh so that a refusal leaves it as it was.
			std::vector<CMeshO::CoordType> moved(mesh.vertex.size());
			for (size_t i = 0; i < moved.size(); ++i) {
				for (int k = 0; k < 3; ++k) {
					const double x = out.points(Eigen::Index(i), k);
					if (!std::isfinite(x) || std::abs(x) > 1e37)   // beyond float range
						throw geofilter::Error("the filtered coordinates are not finite in single precision: the"
						                       " transfer function amplifies this mesh too much");
					moved[i][k] = CMeshO::ScalarType(x);
				}
			}
			for (size_t i = 0; i < moved.size(); ++i) mesh.vertex[i]->P() = moved[i];
			vcg::tri::UpdateBounding<CMeshO>::Box(m->cm);
			if (m->cm.fn > 0) {
				vcg::tri::UpdateNormal<CMeshO>::PerFaceNormalized(m->cm);
				vcg::tri::UpdateNormal<CMeshO>::PerVertexAngleWeighted(m->cm);
			}
		}
		for (const std::string &line : out.log) Log(s.name + ": " + line);
		return true;
	} catch (const geofilter::Error &e) {
		return fail(e.what());
	} catch (const std::exception &e) {
		return fail(std::string("internal error: ") + e.what());
	}
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterGeoFilterPlugin)
