// MeshLab 2022.02+ adapter for GeoFilter (the FilterPlugin API, which pymeshlab also
// drives). Deliberately thin: names, parameters and help come from
// geofilter::filter_table(), the work from geofilter::run_filter(), the translation of
// meshes and parameters from meshlab_shared/meshlab_bridge.h; this class only holds what
// this API does its own way (const QActions, parameter lists returned by value, errors
// thrown as MLException, results returned in a map, python names).
#ifndef GEOFILTER_MESHLAB2022_PLUGIN_H
#define GEOFILTER_MESHLAB2022_PLUGIN_H

#include "core/filter/filter_cache.h"

#include <QObject>
#include <common/plugins/interfaces/filter_plugin.h>

namespace geofilter {
struct FilterSpec;
}

class FilterGeoFilterPlugin : public QObject, public FilterPlugin
{
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
	Q_INTERFACES(FilterPlugin)

public:
	FilterGeoFilterPlugin();

	QString pluginName() const override;
	QString vendor() const override;
	QString filterName(ActionIDType filter) const override;
	QString pythonFilterName(ActionIDType filter) const override;
	QString filterInfo(ActionIDType filter) const override;
	// The QAction overloads of the base stay visible next to the ID ones above.
	using FilterPlugin::filterInfo;
	using FilterPlugin::filterName;
	using FilterPlugin::pythonFilterName;
	FilterClass getClass(const QAction *a) const override;
	int getRequirements(const QAction *a) override;
	int postCondition(const QAction *a) const override;
	FilterArity filterArity(const QAction *a) const override;
	RichParameterList initParameterList(const QAction *a, const MeshDocument &md) override;
	using FilterPlugin::initParameterList;
	std::map<std::string, QVariant> applyFilter(const QAction *a, const RichParameterList &par, MeshDocument &md,
	                                            unsigned int &postConditionMask, vcg::CallBackPos *cb) override;

private:
	const geofilter::FilterSpec &spec(const QAction *a) const;
	// Preview reruns a filter on the same mesh: what does not depend on the parameters is kept.
	geofilter::FilterCache cache_;
};

#endif
