#include "filter_geofilter_plugin.h"

#include "meshlab_shared/meshlab_bridge.h"

#include <exception>
#include <string>
#include <vector>

namespace {

namespace bridge = geofilter::meshlab_bridge;
using bridge::qs;

const std::vector<geofilter::FilterSpec> &table() { return geofilter::filter_table(); }

bool validId(int id) { return id >= 0 && id < int(table().size()); }

Point3m point(const Eigen::Vector3d &v) { return Point3m(Scalarm(v[0]), Scalarm(v[1]), Scalarm(v[2])); }

// What pymeshlab hands back as the filter's result dict (and scripts can read): the same
// numbers the log prints, in types its QVariant conversion knows.
std::map<std::string, QVariant> measureOutputs(const geofilter::FeatureEllipsoid &e)
{
	Matrix33m axes;
	for (int r = 0; r < 3; ++r)
		for (int c = 0; c < 3; ++c) axes[r][c] = Scalarm(e.axes(r, c));
	Eigen::VectorXd frequencies(2);   // sphere-like, cylinder-like
	frequencies << e.frequency(geofilter::FeatureShape::Sphere), e.frequency(geofilter::FeatureShape::Cylinder);
	return {
	    {"centre", QVariant::fromValue(point(e.center))},
	    {"radii", QVariant::fromValue(point(e.radii))},
	    {"axes", QVariant::fromValue(axes)},
	    {"radius", QVariant(e.radius)},
	    {"frequencies", QVariant::fromValue(frequencies)},
	};
}

} // namespace

FilterGeoFilterPlugin::FilterGeoFilterPlugin()
{
	for (int i = 0; i < int(table().size()); ++i) typeList.push_back(i);
	// The action text is what menus show and scripts name, so it must be the table's name.
	for (ActionIDType t : types()) actionList.push_back(new QAction(filterName(t), this));
}

QString FilterGeoFilterPlugin::pluginName() const { return "FilterGeoFilter"; }

QString FilterGeoFilterPlugin::vendor() const { return "GeoFilter"; }

QString FilterGeoFilterPlugin::filterName(ActionIDType filter) const
{
	return validId(filter) ? qs(table()[size_t(filter)].name) : QString();
}

// Given explicitly: the name MeshLab would derive from "GeoFilter: Lowpass" is not the one
// the table promises to pymeshlab users.
QString FilterGeoFilterPlugin::pythonFilterName(ActionIDType filter) const
{
	return validId(filter) ? qs(table()[size_t(filter)].python_name) : QString();
}

QString FilterGeoFilterPlugin::filterInfo(ActionIDType filter) const
{
	// Parameter help is shown as tooltips in the dialog, so the description is enough here.
	return validId(filter) ? qs(table()[size_t(filter)].description) : QString();
}

const geofilter::FilterSpec &FilterGeoFilterPlugin::spec(const QAction *a) const
{
	const int id = ID(a);
	if (!validId(id)) wrongActionCalled(a);   // throws
	return table()[size_t(id)];
}

FilterPlugin::FilterClass FilterGeoFilterPlugin::getClass(const QAction *a) const
{
	// All entries sit together under Smoothing, Fairing and Deformation; Measure is also
	// listed with MeshLab's other measuring filters.
	if (spec(a).kind == geofilter::FilterKind::Measure) return FilterClass(FilterPlugin::Smoothing | FilterPlugin::Measure);
	return FilterPlugin::Smoothing;
}

// The core builds its own connectivity from the vertex/face arrays.
int FilterGeoFilterPlugin::getRequirements(const QAction *) { return MeshModel::MM_NONE; }

int FilterGeoFilterPlugin::postCondition(const QAction *a) const
{
	if (spec(a).kind == geofilter::FilterKind::Measure) return MeshModel::MM_NONE;
	return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
}

FilterPlugin::FilterArity FilterGeoFilterPlugin::filterArity(const QAction *) const { return SINGLE_MESH; }

RichParameterList FilterGeoFilterPlugin::initParameterList(const QAction *a, const MeshDocument &md)
{
	RichParameterList par;
	bridge::addParameters(spec(a), md.mm() != nullptr ? &md.mm()->cm : nullptr, par);
	return par;
}

std::map<std::string, QVariant> FilterGeoFilterPlugin::applyFilter(const QAction *a, const RichParameterList &par,
                                                                   MeshDocument &md, unsigned int &postConditionMask,
                                                                   vcg::CallBackPos *cb)
{
	const geofilter::FilterSpec &s = spec(a);
	MeshModel *m = md.mm();
	if (m == nullptr) throw MLException("GeoFilter: there is no current mesh: open or create a mesh first");
	std::map<std::string, QVariant> result;
	try {
		const bridge::FilterRun run = bridge::runOnMesh(s, m->cm, par, cb, cache_);
		const bridge::CoreMesh &mesh = run.mesh;
		const geofilter::RunOutput &out = run.out;

		if (s.kind == geofilter::FilterKind::Measure) {
			if (out.ellipsoid_mesh) {
				// Not made current: the user keeps working on the mesh they measured.
				MeshModel *layer = md.addNewMesh(QString(), "GeoFilter ellipsoid", false);
				layer->updateDataMask(MeshModel::MM_VERTCOLOR);   // render the colour fillEllipsoid set
				bridge::fillEllipsoid(layer->cm, *out.ellipsoid_mesh);
			}
			if (out.feature) result = measureOutputs(*out.feature);
			postConditionMask = MeshModel::MM_NONE;
		} else {
			bridge::storeFiltered(m->cm, mesh, out.points, out.normals);
			postConditionMask = MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL;
		}
		for (const std::string &line : out.log) log(s.name + ": " + line);
	} catch (const geofilter::Error &e) {
		throw MLException(qs(s.name + ": " + e.what()));
	} catch (const MLException &) {
		throw;
	} catch (const std::exception &e) {
		throw MLException(qs(s.name + ": internal error: " + e.what()));
	}
	return result;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterGeoFilterPlugin)
