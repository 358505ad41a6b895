#include "filter_geofilter_plugin.h"

#include "meshlab_shared/meshlab_bridge.h"

#include <exception>
#include <string>
#include <vector>

namespace {

namespace bridge = geofilter::meshlab_bridge;
using bridge::qs;

const std::vector<geofilter::FilterSpec> &table() { return geofilter::filter_table(); }

void addEllipsoidLayer(MeshDocument &md, const geofilter::Mesh &e)
{
	// Not made current: the user keeps working on the mesh they measured.
	MeshModel *layer = md.addNewMesh("", "GeoFilter ellipsoid", false);
	layer->updateDataMask(MeshModel::MM_VERTCOLOR);   // render the colour fillEllipsoid set
	bridge::fillEllipsoid(layer->cm, e);
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
	bridge::addParameters(spec(a), md.mm() != nullptr ? &md.mm()->cm : nullptr, par);
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
		const bridge::FilterRun run = bridge::runOnMesh(s, m->cm, par, cb, cache_);
		const bridge::CoreMesh &mesh = run.mesh;
		const geofilter::RunOutput &out = run.out;

		if (s.kind == geofilter::FilterKind::Measure) {
			if (out.ellipsoid_mesh) addEllipsoidLayer(md, *out.ellipsoid_mesh);
		} else {
			bridge::storeFiltered(m->cm, mesh, out.points, out.normals);
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
