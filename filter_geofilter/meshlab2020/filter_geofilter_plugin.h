// MeshLab 2020.09 adapter for GeoFilter. Deliberately thin: names, parameters and help
// come from geofilter::filter_table(), the work from geofilter::run_filter(); this class
// only translates between MeshLab's types (RichParameterList, CMeshO, the log) and those.
#ifndef GEOFILTER_MESHLAB2020_PLUGIN_H
#define GEOFILTER_MESHLAB2020_PLUGIN_H

#include "core/filter/filter_cache.h"

#include <QObject>
#include <common/interfaces.h>

namespace geofilter {
struct FilterSpec;
}

class FilterGeoFilterPlugin : public QObject, public MeshFilterInterface
{
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
	Q_INTERFACES(MeshFilterInterface)

public:
	FilterGeoFilterPlugin();

	QString pluginName() const override;
	QString filterName(FilterIDType filter) const override;
	QString filterInfo(FilterIDType filter) const override;
	// Both base overloads stay visible; only the MeshDocument one is specialised.
	using MeshFilterInterface::filterInfo;
	using MeshFilterInterface::filterName;
	using MeshFilterInterface::initParameterSet;
	FilterClass getClass(QAction *a) override;
	int getRequirements(QAction *a) override;
	int postCondition(QAction *a) const override;
	FILTER_ARITY filterArity(QAction *a) const override;
	void initParameterSet(QAction *a, MeshDocument &md, RichParameterList &par) override;
	bool applyFilter(QAction *a, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb) override;

private:
	const geofilter::FilterSpec &spec(QAction *a) const;
	bool fail(const std::string &message);
	// Preview reruns a filter on the same mesh: what does not depend on the parameters is kept.
	geofilter::FilterCache cache_;
};

#endif
