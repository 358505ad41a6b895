// The MeshLab 2022.02+ plugin driven the way pymeshlab drives it: MeshLab's own
// PluginManager loads the plugin folders, pymeshlab::FunctionSet (MeshLab's common/python,
// the table pymeshlab builds its methods from) maps python names to filters and python
// keyword names back to MeshLab parameters, parameters start from initParameterList and are
// overwritten by value, applyFilter runs with a postCondition mask and a callback, results
// come back as a QVariant map and errors as MLException. Every GeoFilter filter is run at
// least once the way ms.apply_filter('apply_geofilter_...', s1=..., useselection=...) runs it
// (applyPython). Meshes come from filter_create and from code; files go through io_base.
//
// Besides its own checks, the test writes cases (input PLY, parameters, output PLY) to
// GEOFILTER_TEST_WORKDIR/cases.json, which test_compare_2020.py replays with the 2020.09
// plugin through meshlabserver.

#include "core/filter/filter.h"
#include "core/filter/region.h"
#include "shapes.h"
#include "filter_table.h"
#include "reference_design.h"

#include <common/globals.h>
#include <common/mlexception.h>
#include <common/plugins/interfaces/filter_plugin.h>
#include <common/plugins/plugin_manager.h>
#include <common/python/function_set.h>
#include <common/utilities/load_save.h>

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <vcg/complex/algorithms/update/selection.h>

#include <gtest/gtest.h>

#include <QDir>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using geofilter::FilterSpec;

QString qs(const std::string &s) { return QString::fromStdString(s); }

std::string env(const char *name, const char *fallback)
{
	const char *v = std::getenv(name);
	return v && *v ? v : fallback;
}

// Set by CMake (tests/meshlab2022/CMakeLists.txt); environment overrides are for running by hand.
const std::string kOurPluginDir = env("GEOFILTER_PLUGIN_DIR", GEOFILTER_PLUGIN_DIR);
const std::string kMeshLabPluginDir = env("MESHLAB_PLUGIN_DIR", MESHLAB_PLUGIN_DIR);
const std::string kWorkDir = env("GEOFILTER_TEST_WORKDIR", GEOFILTER_TEST_WORKDIR);

const FilterSpec &tableEntry(const std::string &name)
{
	const FilterSpec *s = geofilter::find_filter(name);
	if (!s) throw std::runtime_error("no table entry " + name);
	return *s;
}

// ---------------------------------------------------------------------------------------
// The host: one PluginManager for the process, as in pymeshlab (meshlab::pluginManagerInstance).

class Host : public ::testing::Environment
{
public:
	void SetUp() override
	{
		PluginManager &pm = meshlab::pluginManagerInstance();
		// MeshLab's own plugins we need (io_base, filter_create), then ours, each folder loaded
		// whole as MeshLab and pymeshlab do at start; loadPlugins throws if any file fails.
		for (const std::string &dir : {kMeshLabPluginDir, kOurPluginDir}) {
			if (!QDir(qs(dir)).exists()) FAIL() << "plugin folder " << dir << " does not exist";
			try {
				pm.loadPlugins(QDir(qs(dir)));
			} catch (const MLException &e) {
				FAIL() << "loading " << dir << ": " << e.what();
			}
		}
		functions = std::make_unique<pymeshlab::FunctionSet>(pm);
	}
	void TearDown() override { functions.reset(); }

	static std::unique_ptr<pymeshlab::FunctionSet> functions;
};
std::unique_ptr<pymeshlab::FunctionSet> Host::functions;

struct Found
{
	FilterPlugin *plugin = nullptr;
	QAction *action = nullptr;
};

// By MeshLab name (menus, scripts) ...
Found byName(const QString &name)
{
	PluginManager &pm = meshlab::pluginManagerInstance();
	Found f;
	f.action = pm.filterAction(name);
	if (f.action) f.plugin = pm.getFilterPluginFromAction(f.action);
	return f;
}

// ... and by python name, resolved like MeshSet::applyFilter: FunctionSet -> MeshLab name -> action.
Found byPythonName(const QString &python)
{
	if (!Host::functions->containsFilterFunction(python)) return {};
	return byName(Host::functions->filterFunction(python).meshlabFunctionName());
}

struct FilterRun
{
	std::map<std::string, QVariant> outputs;
	unsigned int postConditionMask = MeshModel::MM_UNKNOWN;
	std::vector<std::pair<int, std::string>> progress;
	std::vector<std::string> log;
};

// The progress callback is a plain function pointer (vcg::CallBackPos): collect through a global.
std::vector<std::pair<int, std::string>> *g_progress = nullptr;
bool collectProgress(const int pos, const char *str)
{
	if (g_progress) g_progress->emplace_back(pos, str ? str : "");
	return true;
}

using Values = std::map<std::string, QVariant>;

// MeshLab 2025.07 renamed RichAbsPerc, a length shown with its percentage, to RichPercentage.
#if __has_include(<common/parameters/rich_parameter/rich_percentage.h>)
using RichLength = RichPercentage;
#else
using RichLength = RichAbsPerc;
#endif

// pymeshlab.PercentageValue(x) for a length is written "x%" here: x % of the RichAbsPerc's
// range, as pymeshlab turns a percentage into the absolute value the filter reads.
QVariant percentage(double x) { return QVariant(QString::number(x, 'g', 17) + "%"); }

// The mesh's size as the plugin measures it: the live vertices' bounding box.
double diagonalOf(const CMeshO &cm)
{
	vcg::Box3<double> box;
	for (const auto &v : cm.vert)
		if (!v.IsD()) box.Add(vcg::Point3d(v.cP()[0], v.cP()[1], v.cP()[2]));
	return box.Diag();
}

// A value set by the parameter's type. An enum takes an index, or, as pymeshlab's keyword
// arguments allow, one of its labels.
void setValue(RichParameter &p, const QVariant &v, const std::string &name)
{
	if (p.isOfType<RichEnum>()) {
		const QStringList &labels = dynamic_cast<const RichEnum &>(p).enumvalues;
		const int i = v.type() == QVariant::String ? labels.indexOf(v.toString()) : v.toInt();
		if (i < 0 || i >= labels.size())
			throw std::runtime_error(name + ": '" + v.toString().toStdString() + "' is none of the enum's values");
		p.setValue(IntValue(i));
	}
	else if (p.isOfType<RichLength>() && v.type() == QVariant::String && v.toString().endsWith('%')) {
		const auto &range = dynamic_cast<const RichLength &>(p);
		const double x = v.toString().chopped(1).toDouble();
		p.setValue(FloatValue(Scalarm(range.min + (range.max - range.min) * x / 100)));
	}
	else if (p.value().isBool()) p.setValue(BoolValue(v.toBool()));
	else if (p.value().isInt()) p.setValue(IntValue(v.toInt()));
	else if (p.value().isFloat()) p.setValue(FloatValue(Scalarm(v.toDouble())));
	else throw std::runtime_error("unsupported parameter type for " + name);
}

FilterRun execute(MeshDocument &md, const Found &f, const RichParameterList &rpl);

// By MeshLab name and MeshLab parameter names, as a .mlx script or the GUI's dialog states them.
FilterRun apply(MeshDocument &md, const Found &f, const Values &values = {})
{
	if (!f.plugin || !f.action) throw std::runtime_error("filter not found");
	RichParameterList rpl = f.plugin->initParameterList(f.action, md);
	for (const auto &[name, v] : values) {
		const QString n = qs(name);
		if (!rpl.hasParameter(n)) throw std::runtime_error("no parameter " + name);
		setValue(rpl.getParameterByName(n), v, name);
	}
	return execute(md, f, rpl);
}

// pymeshlab's keyword arguments: python parameter names with Python's values (bool, int,
// float, or str for an enum's label).
using Kwargs = std::map<std::string, QVariant>;

// ms.apply_filter(python, **kwargs) as pymeshlab's MeshSet::applyFilter does it, on the objects
// of MeshLab's src/common/python it is built on: FunctionSet::filterFunction gives the Function,
// whose meshlabFunctionName() names the filter; each keyword must be one of the Function's
// parameters (Function::contains, on FunctionParameter::pythonName: the MeshLab name through
// computePythonName, i.e. lower-cased), and getFilterFunctionParameter(..).meshlabName() names
// the parameter to set in the list initParameterList made for the current document. pymeshlab
// raises on an unknown keyword (since 2022.2): so does this.
FilterRun applyPython(MeshDocument &md, const std::string &python, const Kwargs &kwargs = {})
{
	if (!Host::functions->containsFilterFunction(qs(python)))
		throw std::runtime_error("no python filter " + python);
	const pymeshlab::Function &fn = Host::functions->filterFunction(qs(python));
	const Found f = byName(fn.meshlabFunctionName());
	if (!f.plugin || !f.action) throw std::runtime_error(python + ": no filter " + fn.meshlabFunctionName().toStdString());
	RichParameterList rpl = f.plugin->initParameterList(f.action, md);
	for (const auto &[key, v] : kwargs) {
		if (!fn.contains(qs(key))) throw std::runtime_error(python + ": no python parameter " + key);
		const QString meshlab = fn.getFilterFunctionParameter(qs(key)).meshlabName();
		if (!rpl.hasParameter(meshlab)) throw std::runtime_error(python + ": " + key + " maps to no parameter");
		setValue(rpl.getParameterByName(meshlab), v, key);
	}
	return execute(md, f, rpl);
}

// The python keyword names of MeshLab-named values: what a pymeshlab user types.
Kwargs pythonKwargs(const Values &values)
{
	Kwargs k;
	for (const auto &[name, v] : values) k[qs(name).toLower().toStdString()] = v;
	return k;
}

// What pymeshlab's applyFilter/applyFilterRPL do after the parameters, minus Python:
// requirements, the document state, the call, and compaction of every mesh afterwards.
FilterRun execute(MeshDocument &md, const Found &f, const RichParameterList &rpl)
{
	FilterRun run;
	if (md.mm() != nullptr) {
		QStringList missing;
		if (!f.plugin->isFilterApplicable(f.action, *md.mm(), missing))
			throw std::runtime_error("filter not applicable: " + missing.join(",").toStdString());
		md.mm()->updateDataMask(f.plugin->getRequirements(f.action));
	}
	md.meshDocStateData().clear();
	md.meshDocStateData().create(md);
	const int logStart = md.Log.logStringList().size();
	f.plugin->setLog(&md.Log);
	g_progress = &run.progress;
	struct Reset
	{
		FilterPlugin *p;
		~Reset() { p->setLog(nullptr); g_progress = nullptr; }
	} reset{f.plugin};
	run.outputs = f.plugin->applyFilter(f.action, rpl, md, run.postConditionMask, collectProgress);
	for (MeshModel &mm : md.meshIterator()) vcg::tri::Allocator<CMeshO>::CompactEveryVector(mm.cm);
	const auto &all = md.Log.logStringList();
	for (int i = logStart; i < all.size(); ++i) run.log.push_back(all[i].second.toStdString());
	return run;
}

MeshModel &createSphere(MeshDocument &md, double radius, int subdiv)
{
	applyPython(md, "create_sphere", {{"radius", radius}, {"subdiv", subdiv}});
	if (md.mm() == nullptr || md.mm()->cm.vn != 10 * (1 << (2 * subdiv)) + 2)
		throw std::runtime_error("filter_create's sphere is not the expected icosphere");
	return *md.mm();
}

MeshModel &addMesh(MeshDocument &md, const geofilter::Mesh &m, const QString &label)
{
	MeshModel *mm = md.addNewMesh(QString(), label, true);
	CMeshO &cm = mm->cm;
	auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(cm, size_t(m.points.rows()));
	std::vector<CMeshO::VertexPointer> v;
	for (Eigen::Index i = 0; i < m.points.rows(); ++i, ++vi) {
		vi->P() = Point3m(Scalarm(m.points(i, 0)), Scalarm(m.points(i, 1)), Scalarm(m.points(i, 2)));
		v.push_back(&*vi);
	}
	auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(cm, size_t(m.triangles.rows()));
	for (Eigen::Index i = 0; i < m.triangles.rows(); ++i, ++fi)
		for (int k = 0; k < 3; ++k) fi->V(k) = v[size_t(m.triangles(i, k))];
	mm->updateBoxAndNormals();
	return *mm;
}

// The same rule as the harness's Conditional Face Selection "(z0 > c) && (z1 > c) && (z2 > c)",
// evaluated in double on the float coordinates as muparser does.
int selectCap(CMeshO &cm, double c)
{
	int n = 0;
	for (auto &f : cm.face) {
		if (f.IsD()) continue;
		bool in = true;
		for (int k = 0; k < 3; ++k) in = in && double(f.V(k)->P()[2]) > c;
		if (in) { f.SetS(); ++n; } else f.ClearS();
	}
	return n;
}

// Everything a filter could touch, bitwise: coordinates, normals, flags, box, counts.
std::vector<char> meshBytes(const CMeshO &cm)
{
	std::vector<char> b;
	auto put = [&b](const void *p, size_t n) {
		const char *c = static_cast<const char *>(p);
		b.insert(b.end(), c, c + n);
	};
	put(&cm.vn, sizeof cm.vn);
	put(&cm.fn, sizeof cm.fn);
	put(&cm.bbox, sizeof cm.bbox);
	for (const auto &v : cm.vert) {
		const Point3m p = v.cP(), n = v.cN();
		const int flags = v.cFlags();
		put(&p, sizeof p);
		put(&n, sizeof n);
		put(&flags, sizeof flags);
	}
	for (const auto &f : cm.face) {
		const Point3m n = f.cN();
		const int flags = f.cFlags();
		put(&n, sizeof n);
		put(&flags, sizeof flags);
	}
	return b;
}

struct Snapshot
{
	std::vector<std::vector<char>> meshes;
	explicit Snapshot(MeshDocument &md)
	{
		for (MeshModel &mm : md.meshIterator()) meshes.push_back(meshBytes(mm.cm));
	}
	bool operator==(const Snapshot &o) const { return meshes == o.meshes; }
};

double meanRadius(const CMeshO &cm)
{
	double sum = 0;
	int n = 0;
	for (const auto &v : cm.vert)
		if (!v.IsD()) { sum += double(v.cP().Norm()); ++n; }
	return sum / n;
}

// Eq. 15 from the shared test reference (tests/support): its five conditions solved as a
// linear system, not the core's closed form, so that the sphere tests check the core against
// the paper's conditions.
double eq15(double s, double s1, double s2, double G0, double G1, double Ginf)
{
	return geofilter::reference::eq15_reference(s1, s2, G0, G1, Ginf).gain(s);
}

const Values kFig6 = {{"s1", 10.0}, {"s2", 25.0}, {"G0", 1.0}, {"G1", 30.0}, {"Ginf", 0.0}, {"useSelection", false}};
// The same as pymeshlab keywords: ms.apply_filter('apply_geofilter_custom', s1=10, ..., useselection=False).
const Kwargs kFig6Python = {{"s1", 10.0}, {"s2", 25.0}, {"g0", 1.0}, {"g1", 30.0}, {"ginf", 0.0}, {"useselection", false}};

// ---------------------------------------------------------------------------------------

TEST(Loading, PluginPassesMeshLabsChecks)
{
	// What pymeshlab.load_plugin does first: PluginManager::checkPlugin (Qt plugin, MeshLab
	// plugin, same version and precision, a class, requirements and conditions per filter).
	const QString file = QDir(qs(kOurPluginDir)).absoluteFilePath("libfilter_geofilter.so");
	ASSERT_TRUE(QFileInfo::exists(file)) << file.toStdString();
	try {
		MeshLabPluginType type = PluginManager::checkPlugin(file);
		EXPECT_TRUE(type.isFilterPlugin());
	} catch (const MLException &e) {
		FAIL() << e.what();
	}
}

TEST(Loading, EveryFilterFoundByNameAndPythonName)
{
	ASSERT_FALSE(geofilter::filter_table().empty());
	for (const FilterSpec &s : geofilter::filter_table()) {
		SCOPED_TRACE(s.name);
		const Found n = byName(qs(s.name));
		ASSERT_NE(n.plugin, nullptr) << "not found by name";
		EXPECT_EQ(n.plugin->pluginName().toStdString(), "FilterGeoFilter");
		EXPECT_EQ(n.plugin->pythonFilterName(n.action).toStdString(), s.python_name);
		EXPECT_EQ(n.plugin->filterInfo(n.action).toStdString(), s.description);
		EXPECT_EQ(n.plugin->filterArity(n.action), FilterPlugin::SINGLE_MESH);
		EXPECT_TRUE(n.plugin->getClass(n.action) & FilterPlugin::Smoothing);
		const Found p = byPythonName(qs(s.python_name));
		ASSERT_NE(p.plugin, nullptr) << "not found by python name " << s.python_name;
		EXPECT_EQ(p.action, n.action);
		// pymeshlab's keyword arguments are MeshLab's parameter names lower-cased.
		const pymeshlab::Function &fn = Host::functions->filterFunction(qs(s.python_name));
		EXPECT_EQ(fn.meshlabFunctionName().toStdString(), s.name);
		EXPECT_EQ(fn.parametersNumber(), s.parameters.size());
		for (const auto &par : s.parameters) {
			const QString python = qs(par.name).toLower();
			ASSERT_TRUE(fn.contains(python)) << "no python parameter " << par.name;
			EXPECT_EQ(fn.getFilterFunctionParameter(python).meshlabName().toStdString(), par.name);
		}
	}
}

TEST(Parameters, MatchTheTableAndUseSelectionFollowsTheSelection)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	for (int selected = 0; selected < 2; ++selected) {
		if (selected) {
			ASSERT_GT(selectCap(m.cm, 0.5), 0);
		}
		for (const FilterSpec &s : geofilter::filter_table()) {
			SCOPED_TRACE(s.name + (selected ? " (selection)" : " (no selection)"));
			const Found f = byName(qs(s.name));
			const RichParameterList rpl = f.plugin->initParameterList(f.action, md);
			ASSERT_EQ(rpl.size(), s.parameters.size());
			for (const auto &p : s.parameters) {
				ASSERT_TRUE(rpl.hasParameter(qs(p.name))) << p.name;
				const Value &v = rpl.getParameterByName(qs(p.name)).value();
				// The dialog folds the expert's parameters under its advanced button.
				EXPECT_EQ(rpl.getParameterByName(qs(p.name)).isAdvanced(), p.expert) << p.name;
				switch (p.type) {
				case geofilter::ParameterType::Length: {
					// MeshLab's convention for lengths: absolute or % of the diagonal.
					const RichParameter &rp = rpl.getParameterByName(qs(p.name));
					ASSERT_TRUE(rp.isOfType<RichLength>()) << p.name;
					const auto &range = dynamic_cast<const RichLength &>(rp);
					const double diagonal = diagonalOf(m.cm);
					EXPECT_EQ(range.min, 0) << p.name;
					EXPECT_NEAR(range.max, diagonal, 1e-6 * diagonal) << p.name;
					EXPECT_NEAR(v.getFloat(), p.default_value * diagonal, 1e-6 * diagonal) << p.name;
					break;
				}
				case geofilter::ParameterType::Float:
					ASSERT_TRUE(v.isFloat()) << p.name;
					// FloatValue's constructor takes a float, even in a double-precision MeshLab
					// (2022.02 to 2025.07): every RichFloat passes through single precision.
					EXPECT_EQ(v.getFloat(), Scalarm(float(p.default_value))) << p.name;
					break;
				case geofilter::ParameterType::Bool:
					ASSERT_TRUE(v.isBool()) << p.name;
					if (p.name == geofilter::param::use_selection) EXPECT_EQ(v.getBool(), bool(selected));
					else EXPECT_EQ(v.getBool(), p.default_value != 0) << p.name;
					break;
				case geofilter::ParameterType::Int:
				case geofilter::ParameterType::Enum:
					ASSERT_TRUE(v.isInt()) << p.name;
					EXPECT_EQ(v.getInt(), int(p.default_value)) << p.name;
					break;
				}
			}
		}
	}
}

// (a) docs/paper-notes.md §6: icospheres of several radii, Fig. 6's filter, radius ratio
// within 2% of G(2/r^2).
TEST(Sphere, Fig6RadiusRatiosFollowEq15)
{
	EXPECT_NEAR(eq15(10, 10, 25, 1, 30, 0), 30.0, 1e-9);   // the test's own eq. 15
	EXPECT_NEAR(eq15(25, 10, 25, 1, 30, 0), 1.0, 1e-9);
	const std::vector<std::pair<double, int>> cases = {{0.2, 3}, {0.3, 3}, {0.45, 3}, {0.7, 3}, {1.0, 4}, {2.0, 3}};
	for (const auto &[r, level] : cases) {
		SCOPED_TRACE("r = " + std::to_string(r));
		MeshDocument md;
		MeshModel &m = createSphere(md, r, level);
		const FilterRun run = applyPython(md, "apply_geofilter_custom", kFig6Python);
		const double ratio = meanRadius(m.cm) / r;
		const double expected = std::abs(eq15(2 / (r * r), 10, 25, 1, 30, 0));
		EXPECT_NEAR(ratio / expected, 1.0, 0.02) << "ratio " << ratio << ", G(2/r^2) = " << expected;
	}
}

TEST(Sphere, PaperSolverAgrees)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 0.45, 3);
	Kwargs v = kFig6Python;
	v["solver"] = "Jacobi-PCG (paper)";   // an enum by its label, as pymeshlab allows
	const FilterRun run = applyPython(md, "apply_geofilter_custom", v);
	bool mentioned = false;
	for (const auto &l : run.log) mentioned = mentioned || l.find("solver Jacobi-PCG") != std::string::npos;
	EXPECT_TRUE(mentioned);
	EXPECT_NEAR(meanRadius(m.cm) / 0.45 / std::abs(eq15(2 / (0.45 * 0.45), 10, 25, 1, 30, 0)), 1.0, 0.02);
}

TEST(Running, LogsProgressesAndReportsWhatChanged)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	const FilterRun run = applyPython(md, "apply_geofilter_lowpass", {{"useselection", false}});
	EXPECT_EQ(run.postConditionMask, unsigned(MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNORMAL | MeshModel::MM_FACENORMAL));
	EXPECT_TRUE(run.outputs.empty());
	bool peak = false, solver = false;
	for (const auto &l : run.log) {
		EXPECT_EQ(l.rfind("GeoFilter: Lowpass: ", 0), 0u) << l;
		peak = peak || l.find("peak |G|") != std::string::npos;
		solver = solver || l.find(": solver ") != std::string::npos;
	}
	EXPECT_TRUE(peak && solver) << "log lines missing (" << run.log.size() << " lines)";
	ASSERT_FALSE(run.progress.empty());
	for (const auto &[pos, text] : run.progress) {
		EXPECT_GE(pos, 0);
		EXPECT_LE(pos, 100);
		EXPECT_EQ(text.rfind("GeoFilter: Lowpass: ", 0), 0u) << text;
	}
	// The box and the normals follow the moved vertices.
	Box3m box;
	for (const auto &v : m.cm.vert) box.Add(v.cP());
	EXPECT_EQ(box.min, m.cm.bbox.min);
	EXPECT_EQ(box.max, m.cm.bbox.max);
	const auto &v0 = m.cm.vert[0];
	EXPECT_GT((v0.cN() * v0.cP()) / v0.cP().Norm() / v0.cN().Norm(), Scalarm(0.99));
}

// The GUI's dialog and .mlx scripts reach a filter by its MeshLab name and parameter names,
// pymeshlab by the python ones: the same filter, the same result, bit for bit.
TEST(Running, MeshLabAndPythonNamesGiveTheSameMesh)
{
	for (const FilterSpec &s : geofilter::filter_table()) {
		if (s.kind == geofilter::FilterKind::Measure) continue;
		SCOPED_TRACE(s.name);
		MeshDocument byMeshLab, byPython;
		createSphere(byMeshLab, 1.0, 3);
		createSphere(byPython, 1.0, 3);
		apply(byMeshLab, byName(qs(s.name)), {{"useSelection", false}, {"solver", 0}});
		applyPython(byPython, s.python_name, {{"useselection", false}, {"solver", "Factored (sparse Cholesky)"}});
		EXPECT_TRUE(Snapshot(byMeshLab) == Snapshot(byPython));
	}
}

// Through pymeshlab's route: python filter name and keywords; the message names the MeshLab filter.
void expectRefusedUnchanged(MeshDocument &md, const std::string &python, const Kwargs &kwargs, const std::string &words)
{
	const std::string filter = Host::functions->filterFunction(qs(python)).meshlabFunctionName().toStdString();
	const Snapshot before(md);
	try {
		applyPython(md, python, kwargs);
		ADD_FAILURE() << filter << " accepted what it should refuse (" << words << ")";
	} catch (const MLException &e) {
		EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
		EXPECT_EQ(std::string(e.what()).rfind(filter + ": ", 0), 0u) << e.what();
	}
	EXPECT_TRUE(Snapshot(md) == before) << "the document changed although the filter refused";
}

TEST(Errors, UnstableDesignLeavesTheMeshBitForBitUnchanged)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	// docs/paper-notes.md §4: real roots 18.0 and 52.0 of the denominator.
	expectRefusedUnchanged(md, "apply_geofilter_custom",
	                       {{"s1", 25.0}, {"s2", 10.0}, {"g0", 1.0}, {"g1", 3.0}, {"ginf", 0.0}, {"useselection", false}},
	                       "stab");
}

TEST(Errors, UseSelectionWithoutSelectionIsRefused)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	expectRefusedUnchanged(md, "apply_geofilter_lowpass", {{"useselection", true}}, "no faces are selected");
}

TEST(Errors, AmplificationBeyondTheScalarRangeIsRefused)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	// A gain of 1e38 at s = 0 scales the sphere past the 1e37 guard (float range ends at 3.4e38).
	expectRefusedUnchanged(md, "apply_geofilter_pole_zero",
	                       {{"g0", 1e38}, {"z1", 100.0}, {"z2", 0.0}, {"p1", 200.0}, {"p2", 0.0}, {"useselection", false}},
	                       "not finite");
}

// pymeshlab's keywords are the lower-cased names: MeshLab's spelling is no keyword, and an
// enum label must be one of the enum's. Refused before the filter runs, the mesh untouched.
TEST(Errors, PythonKeywordsAreLowerCaseAndChecked)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	const Snapshot before(md);
	for (const Kwargs &k : {Kwargs{{"useSelection", false}}, Kwargs{{"G0", 1.0}}, Kwargs{{"sigma", 0.5}},
	                        Kwargs{{"solver", "Cholesky"}}, Kwargs{{"solver", 2}}}) {
		SCOPED_TRACE(k.begin()->first);
		EXPECT_THROW(applyPython(md, "apply_geofilter_lowpass", k), std::runtime_error);
	}
	EXPECT_THROW(applyPython(md, "apply_geofilter_low_pass"), std::runtime_error);
	EXPECT_TRUE(Snapshot(md) == before);
}

TEST(Errors, ParameterOfTheWrongTypeIsNamed)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	const Found f = byName("GeoFilter: Lowpass");
	RichParameterList rpl = f.plugin->initParameterList(f.action, md);
	RichParameterList wrong;
	for (const RichParameter &p : rpl)
		if (p.name() == "s1") wrong.addParam(RichString("s1", "25"));
		else wrong.addParam(p);
	const Snapshot before(md);
	unsigned int mask = MeshModel::MM_UNKNOWN;
	try {
		f.plugin->applyFilter(f.action, wrong, md, mask, nullptr);
		ADD_FAILURE() << "a string s1 was accepted";
	} catch (const MLException &e) {
		EXPECT_NE(std::string(e.what()).find("parameter s1 must be a RichFloat"), std::string::npos) << e.what();
	}
	EXPECT_TRUE(Snapshot(md) == before);
}

TEST(Measure, ReturnsTheEllipsoidAndAddsALayer)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	ASSERT_GT(selectCap(m.cm, 0.5), 0);
	const std::vector<char> before = meshBytes(m.cm);
	const FilterRun run = applyPython(md, "compute_geofilter_feature_measure");
	EXPECT_TRUE(meshBytes(m.cm) == before) << "measuring changed the measured mesh";
	EXPECT_EQ(run.postConditionMask, unsigned(MeshModel::MM_NONE));
	ASSERT_EQ(md.meshNumber(), 2u);
	EXPECT_EQ(md.mm(), &m) << "the measured mesh must stay current";
	const MeshModel *layer = md.getMesh(1);
	ASSERT_NE(layer, nullptr);
	EXPECT_EQ(layer->label().toStdString(), "GeoFilter ellipsoid");
	EXPECT_EQ(layer->cm.vn, 642);

	for (const char *k : {"centre", "radii", "axes", "radius", "frequencies"})
		ASSERT_EQ(run.outputs.count(k), 1u) << "no output " << k;
	// The types pymeshlab's toPyDict converts: Point3m, Matrix33m, double, Eigen::VectorXd.
	ASSERT_TRUE(run.outputs.at("centre").canConvert<Point3m>());
	ASSERT_TRUE(run.outputs.at("radii").canConvert<Point3m>());
	ASSERT_TRUE(run.outputs.at("axes").canConvert<Matrix33m>());
	ASSERT_EQ(std::string(run.outputs.at("radius").typeName()), "double");
	ASSERT_TRUE(run.outputs.at("frequencies").canConvert<Eigen::VectorXd>());
	const Point3m c = run.outputs.at("centre").value<Point3m>();
	const Point3m radii = run.outputs.at("radii").value<Point3m>();
	const double r = run.outputs.at("radius").toDouble();
	const Eigen::VectorXd s = run.outputs.at("frequencies").value<Eigen::VectorXd>();
	// The cap z > 0.5 of the unit sphere: base radius sqrt(0.75), height 0.5.
	EXPECT_NEAR(c[0], 0, 0.02);
	EXPECT_NEAR(c[1], 0, 0.02);
	EXPECT_NEAR(c[2], 0.75, 0.05);
	EXPECT_GE(radii[0], radii[1]);
	EXPECT_GE(radii[1], radii[2]);
	EXPECT_NEAR(radii[0], std::sqrt(0.75), 0.1);
	EXPECT_NEAR(radii[2], 0.25, 0.05);
	EXPECT_NEAR(r, (radii[0] + radii[1]) / 2, 1e-5);
	ASSERT_EQ(s.size(), 2);
	EXPECT_NEAR(s[0], 2 / (r * r), 1e-9 * s[0]);
	EXPECT_NEAR(s[1], 1 / (r * r), 1e-9 * s[1]);
	bool feature = false;
	for (const auto &l : run.log) feature = feature || l.rfind("GeoFilter: Measure Selected Feature: feature: ", 0) == 0;
	EXPECT_TRUE(feature);
}

TEST(Measure, WithoutSelectionIsRefused)
{
	MeshDocument md;
	createSphere(md, 1.0, 3);
	expectRefusedUnchanged(md, "compute_geofilter_feature_measure", {}, "no faces are selected");
}

// ---------------------------------------------------------------------------------------
// Region: filter only the selection, with the blend band; the vertex quality as a
// weight. The math itself is checked against a dense reference in tests/unit/test_region.cpp;
// here: that the plugin reads region/blendWidth/quality and writes back only inside D.

// The current mesh as the core sees it (double copies of the float coordinates).
geofilter::Mesh coreCopy(const CMeshO &cm)
{
	geofilter::Mesh m;
	m.points.resize(cm.vn, 3);
	for (int i = 0; i < cm.vn; ++i)
		for (int k = 0; k < 3; ++k) m.points(i, k) = double(cm.vert[size_t(i)].cP()[k]);
	m.triangles.resize(cm.fn, 3);
	for (int f = 0; f < cm.fn; ++f)
		for (int k = 0; k < 3; ++k) m.triangles(f, k) = int(vcg::tri::Index(cm, cm.face[size_t(f)].cV(k)));
	return m;
}

const Values kRegionDesign = {{"s1", 20.0}, {"s2", 50.0}, {"G0", 1.0}, {"G1", 3.0}, {"Ginf", 0.9},
                              {"useSelection", false}};

TEST(Region, SelectedCapChangesOnlyTheCapAndItsBand)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	ASSERT_GT(selectCap(m.cm, 0.6), 20);
	const geofilter::Mesh before = coreCopy(m.cm);
	std::vector<int> selected;
	for (size_t f = 0; f < m.cm.face.size(); ++f)
		if (m.cm.face[f].IsS()) selected.push_back(int(f));
	Values values = kRegionDesign;
	values["region"] = 1;
	values["blendWidth"] = 0.4;
	const FilterRun run = apply(md, byName(QString("GeoFilter: Band Exaggeration")), values);
	const geofilter::Mesh after = coreCopy(m.cm);

	const std::vector<double> w = geofilter::region_weight(before.points, before.triangles, selected, 0.4);
	const geofilter::Points expected = geofilter::apply_filter_weighted(
	    before.points, before.triangles, geofilter::design_second_order({20, 50, 1, 3, 0.9}), w);
	int outside = 0;
	double worst = 0;
	for (Eigen::Index i = 0; i < before.points.rows(); ++i) {
		if (w[size_t(i)] == 0) {
			++outside;
			EXPECT_TRUE(after.points.row(i) == before.points.row(i)) << "vertex " << i << " outside D moved";
		} else {
			worst = std::max(worst, (after.points.row(i) - expected.row(i)).norm());
		}
	}
	EXPECT_GT(outside, 300);
	EXPECT_LT(worst, 1e-6 * 2) << "float write-back of the core's result (bbox diagonal 2)";
	EXPECT_GT((after.points - before.points).rowwise().norm().maxCoeff(), 0.01) << "the cap must change";
	bool logged = false;
	for (const auto &l : run.log) logged = logged || l.find("left exactly as they were") != std::string::npos;
	EXPECT_TRUE(logged);
}

// The dialog in sizes: a radius given as a length, or as pymeshlab's percentage of the
// diagonal, filters as the paper's design typed with s1 = 2/r^2 (and the preset's s2 = 2 s1),
// which is what geofilter --radius r runs; within the float write-back, 1e-6 of the diagonal.
TEST(Sizes, ARadiusAsALengthOrAPercentageIsTheDesignOfItsFrequency)
{
	for (const bool asPercentage : {false, true}) {
		SCOPED_TRACE(asPercentage ? "percentage" : "length");
		MeshDocument md;
		MeshModel &m = createSphere(md, 1.0, 3);
		for (auto &v : m.cm.vert) {
			const double x = v.P()[0], y = v.P()[1];
			v.P() *= Scalarm(1 + 0.05 * std::sin(7 * x) * std::cos(5 * y));
		}
		m.updateBoxAndNormals();
		const geofilter::Mesh before = coreCopy(m.cm);
		const double diagonal = diagonalOf(m.cm), r = 0.15;
		Kwargs kwargs{{"useselection", false}, {"tolerance", 1e-10}};
		kwargs["radius"] = asPercentage ? percentage(100 * r / diagonal) : QVariant(r);
		const FilterRun run = applyPython(md, "apply_geofilter_lowpass", kwargs);
		const geofilter::Mesh after = coreCopy(m.cm);
		geofilter::FilterOptions options;
		options.tolerance = 1e-10;
		const geofilter::Points expected = geofilter::apply_filter(
		    before.points, before.triangles, geofilter::design_second_order({2 / (r * r), 4 / (r * r), 1, 1.1, 0}), options);
		EXPECT_LT((after.points - expected).cwiseAbs().maxCoeff(), 1e-6 * diagonal);
		EXPECT_GT((after.points - before.points).cwiseAbs().maxCoeff(), 1e-3 * diagonal) << "the filter changed the mesh";
		bool logged = false;
		for (const auto &l : run.log) logged = logged || l.find("from the feature radius r = 0.15") != std::string::npos;
		EXPECT_TRUE(logged);
	}
}

// A point cloud layer (vertices, no faces), as pymeshlab loads a scan: the plugin builds the
// cloud's Laplacian, so the noisy sphere of points is smoothed and its mean radius scales by
// the designed gain at 2/r^2, as the sphere mesh's does.
TEST(Cloud, APointCloudLayerIsFilteredByItsOwnLaplacian)
{
	geofilter::Mesh cloud;
	cloud.points = geofilter::fibonacci_sphere(3000, 1.0);
	cloud.triangles.resize(0, 3);
	for (Eigen::Index i = 0; i < cloud.points.rows(); ++i) cloud.points.row(i) *= 1 + 0.01 * std::sin(37.0 * i);
	MeshDocument md;
	MeshModel &m = addMesh(md, cloud, "cloud");
	const FilterRun run = applyPython(md, "apply_geofilter_lowpass", {{"radius", 0.3}, {"useselection", false}});
	const geofilter::Mesh after = coreCopy(m.cm);
	ASSERT_EQ(after.points.rows(), cloud.points.rows());
	const Eigen::VectorXd before = cloud.points.rowwise().norm(), radii = after.points.rowwise().norm();
	auto spread = [](const Eigen::VectorXd &r) { return std::sqrt((r.array() - r.mean()).square().mean()); };
	EXPECT_LT(spread(radii), 0.3 * spread(before));
	const double s1 = 2 / (0.3 * 0.3), expected = std::abs(eq15(2.0, s1, 2 * s1, 1, 1.1, 0));
	EXPECT_NEAR(radii.mean() / before.mean(), expected, 0.01 * expected);
	bool logged = false;
	for (const auto &l : run.log) logged = logged || l.find("point cloud: 3000 points") != std::string::npos;
	EXPECT_TRUE(logged);
	// The cloud had no normals: the layer gets the ones the filter estimated, oriented outward.
	double worst = 1;
	for (Eigen::Index i = 0; i < after.points.rows(); ++i) {
		const auto &n = m.cm.vert[size_t(i)].cN();
		const Eigen::Vector3d normal{double(n[0]), double(n[1]), double(n[2])};
		worst = std::min(worst, normal.dot(cloud.points.row(i).normalized().transpose()));
	}
	EXPECT_GT(worst, 0.99) << "a vertex normal of the cloud layer is not its sphere's outward normal";
}

TEST(Region, QualityWeightOneIsTheWholeMeshFilterAndZeroChangesNothing)
{
	MeshDocument whole, one, zero;
	createSphere(whole, 1.0, 3);
	MeshModel &m1 = createSphere(one, 1.0, 3);
	MeshModel &m0 = createSphere(zero, 1.0, 3);
	for (auto &v : m1.cm.vert) v.Q() = 1;
	for (auto &v : m0.cm.vert) v.Q() = 0;
	Values values = kRegionDesign;
	apply(whole, byName(QString("GeoFilter: Band Exaggeration")), values);
	values["region"] = 2;
	apply(one, byName(QString("GeoFilter: Band Exaggeration")), values);
	apply(zero, byName(QString("GeoFilter: Band Exaggeration")), values);
	ASSERT_EQ(whole.mm()->cm.vert.size(), m1.cm.vert.size());
	// Equal to the solver's tolerance, not bit for bit: the whole-mesh run may reuse a factor
	// the plugin's FilterCache holds from an earlier test on the same sphere (tests run in
	// random order), and a reused factor takes other CG steps. Both are within 1e-7 of the
	// diagonal (2) of the exact filter; the float write-back adds its rounding.
	double worst = 0;
	for (size_t i = 0; i < m1.cm.vert.size(); ++i)
		worst = std::max(worst, double((whole.mm()->cm.vert[i].cP() - m1.cm.vert[i].cP()).Norm()));
	EXPECT_LT(worst, 1e-6 * 2);  // a NaN fails too
	// Coordinates untouched; normals are recomputed from the same coordinates.
	const geofilter::Mesh a = coreCopy(m0.cm);
	MeshDocument fresh;
	const geofilter::Mesh b = coreCopy(createSphere(fresh, 1.0, 3).cm);
	EXPECT_TRUE(a.points == b.points);
}

TEST(Region, BadRegionsAreRefusedAndTheMeshIsUnchanged)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	// As pymeshlab users call it: python name, lower-case keywords.
	Kwargs kwargs = {{"s1", 20.0}, {"s2", 50.0}, {"g0", 1.0}, {"g1", 3.0}, {"ginf", 0.9}, {"useselection", false}};
	kwargs["region"] = 1;
	expectRefusedUnchanged(md, "apply_geofilter_lowpass", kwargs, "no faces are selected");
	for (auto &v : m.cm.vert) v.Q() = 0.5;
	m.cm.vert[5].Q() = std::numeric_limits<float>::quiet_NaN();
	kwargs["region"] = 2;
	expectRefusedUnchanged(md, "apply_geofilter_lowpass", kwargs, "NaN");
}

TEST(Measure, EllipsoidLayerIsColouredAndStandsOffTheSurface)
{
	MeshDocument md;
	MeshModel &m = createSphere(md, 1.0, 3);
	ASSERT_GT(selectCap(m.cm, 0.5), 0);
	const FilterRun run = apply(md, byPythonName("compute_geofilter_feature_measure"));
	const MeshModel *layer = md.getMesh(1);
	ASSERT_NE(layer, nullptr);
	EXPECT_TRUE(layer->hasDataMask(MeshModel::MM_VERTCOLOR));
	for (const auto &v : layer->cm.vert) ASSERT_TRUE(v.cC() == vcg::Color4b(255, 128, 0, 255));
	bool axes = false;
	for (const auto &l : run.log) axes = axes || l.find("ellipsoid axes") != std::string::npos;
	EXPECT_TRUE(axes);
	// The measured ellipsoid touches the sphere at the cap's apex (z = 1); the shown one passes above it.
	Scalarm top = -1;
	for (const auto &v : layer->cm.vert) top = std::max(top, v.cP()[2]);
	EXPECT_GT(top, Scalarm(1.0));
	EXPECT_LT(top, Scalarm(1.05));
}

// ---------------------------------------------------------------------------------------
// (b) Cases for the comparison with the 2020.09 plugin (test_compare_2020.py).

struct Case
{
	std::string tag, filter;
	std::string input;        // "sphere" (filter_create, r = 1, level 3) or "bumpy" (code)
	double selectAbove = NAN; // cap selection threshold, or none
	Values values;            // on top of the table's defaults
};

std::vector<Case> comparisonCases()
{
	std::vector<Case> cases;
	for (const FilterSpec &s : geofilter::filter_table()) {
		if (s.kind == geofilter::FilterKind::Measure) continue;
		std::string tag = s.cli_name;
		cases.push_back({tag, s.name, "bumpy", NAN, {{"useSelection", false}}});
	}
	cases.push_back({"fig6_sphere", "GeoFilter: Custom", "sphere", NAN, kFig6});
	cases.push_back({"exaggerate_selection", "GeoFilter: Band Exaggeration", "bumpy", 0.6, {{"useSelection", true}}});
	cases.push_back({"polezero_selection", "GeoFilter: Pole-Zero", "bumpy", 0.6,
	                 {{"useSelection", true}, {"featureCorner", 4}, {"featureShape", 1}}});
	cases.push_back({"lowpass_jacobi", "GeoFilter: Lowpass", "bumpy", NAN, {{"useSelection", false}, {"solver", 1}}});
	cases.push_back({"measure", "GeoFilter: Measure Selected Feature", "bumpy", 0.6, {}});
	return cases;
}

QJsonValue json(const QVariant &v)
{
	if (v.type() == QVariant::Bool) return v.toBool();
	if (v.type() == QVariant::Int) return v.toInt();
	return v.toDouble();
}

TEST(Comparison, WriteCasesFor2020)
{
	const QString dir = qs(kWorkDir);
	ASSERT_TRUE(QDir().mkpath(dir));

	// Inputs are written once with io_base and read back, so that this run and the 2020.09
	// run start from the same file. Coordinates are rounded to float first: a double-precision
	// MeshLab then sees exactly what the single-precision 2020.09 reads.
	auto toFloat = [](MeshModel &m) -> MeshModel & {
		for (auto &v : m.cm.vert)
			for (int k = 0; k < 3; ++k) v.P()[k] = Scalarm(float(v.P()[k]));
		m.updateBoxAndNormals();
		return m;
	};
	{
		MeshDocument md;
		meshlab::saveMeshWithStandardParameters(dir + "/input-sphere.ply", toFloat(createSphere(md, 1.0, 3)));
		geofilter::Mesh bumpy = geofilter::icosphere(4, 1.0);
		geofilter::perturb_radially(bumpy, 0.02, 11);
		meshlab::saveMeshWithStandardParameters(dir + "/input-bumpy.ply", toFloat(addMesh(md, bumpy, "bumpy")));
	}

	QJsonArray out;
	for (const Case &c : comparisonCases()) {
		SCOPED_TRACE(c.tag);
		MeshDocument md;
		const QString input = dir + "/input-" + qs(c.input) + ".ply";
		const std::list<MeshModel *> loaded = meshlab::loadMeshWithStandardParameters(input, md);
		ASSERT_EQ(loaded.size(), 1u);
		MeshModel &m = *md.mm();
		if (!std::isnan(c.selectAbove)) {
			ASSERT_GT(selectCap(m.cm, c.selectAbove), 0);
		}

		Values values;   // every parameter, so that the 2020.09 script states the same ones
		for (const auto &p : tableEntry(c.filter).parameters)   // a length's default: as the dialog's, on this mesh
			values[p.name] = p.type == geofilter::ParameterType::Length ? double(float(p.default_value * diagonalOf(m.cm)))
			                                                           : p.default_value;
		for (const auto &[k, v] : c.values) values[k] = v;
		for (const auto &p : tableEntry(c.filter).parameters)
			if (p.type == geofilter::ParameterType::Bool) values[p.name] = values[p.name].toDouble() != 0;
			else if (p.type != geofilter::ParameterType::Float && p.type != geofilter::ParameterType::Length)
				values[p.name] = int(values[p.name].toDouble());

		// As a pymeshlab user calls it: ms.apply_filter('apply_geofilter_...', s1=..., useselection=...),
		// enums by label (pymeshlab's documented form); the 2020.09 script gets the MeshLab names.
		Values byLabel = values;
		for (const auto &p : tableEntry(c.filter).parameters)
			if (p.type == geofilter::ParameterType::Enum) byLabel[p.name] = qs(p.choices.at(size_t(values.at(p.name).toInt())));
		const FilterRun run = applyPython(md, tableEntry(c.filter).python_name, pythonKwargs(byLabel));
		const QString output = dir + "/out2022-" + qs(c.tag) + ".ply";
		const bool measure = tableEntry(c.filter).kind == geofilter::FilterKind::Measure;
		// The measure's product is its new layer; filters change the current mesh.
		meshlab::saveMeshWithStandardParameters(output, measure ? *md.getMesh(1) : m);

		// In the table's order, with MeshLab's type names: what a 2020.09 script must state.
		QJsonArray params;
		for (const auto &p : tableEntry(c.filter).parameters) {
			static const char *const rich[] = {"RichFloat", "RichBool", "RichInt", "RichEnum", "RichAbsPerc"};
			params.append(QJsonObject{{"name", qs(p.name)},
			                          {"type", rich[int(p.type)]},
			                          {"value", json(values.at(p.name))},
			                          {"choices", int(p.choices.size())}});
		}
		QJsonObject results;
		for (const auto &[k, v] : run.outputs) {
			if (v.canConvert<Point3m>()) {
				const Point3m p = v.value<Point3m>();
				results[qs(k)] = QJsonArray{p[0], p[1], p[2]};
			} else if (v.canConvert<Eigen::VectorXd>()) {
				QJsonArray a;
				for (double x : v.value<Eigen::VectorXd>()) a.append(x);
				results[qs(k)] = a;
			} else if (std::string(v.typeName()) == "double") {
				results[qs(k)] = v.toDouble();
			}
		}
		QJsonObject o{{"tag", qs(c.tag)},     {"filter", qs(c.filter)}, {"input", input},
		              {"output", output},     {"params", params},       {"results", results},
		              {"measure", measure},   {"scalar", sizeof(Scalarm) == sizeof(double) ? "double" : "float"}};
		if (!std::isnan(c.selectAbove)) o["select_above"] = c.selectAbove;
		out.append(o);
	}
	QFile f(dir + "/cases.json");
	ASSERT_TRUE(f.open(QIODevice::WriteOnly | QIODevice::Truncate));
	f.write(QJsonDocument(out).toJson());
}

} // namespace

int main(int argc, char **argv)
{
	::testing::InitGoogleTest(&argc, argv);
	::testing::AddGlobalTestEnvironment(new Host);
	return RUN_ALL_TESTS();
}
