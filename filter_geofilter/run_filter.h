// What every adapter does once it has read its parameters and the mesh: design the
// transfer function (taking the frequency from the selection if asked), run it, and
// say what happened in log lines. Adapters only translate to and from their API.
#pragma once

#include "core/feature/feature.h"
#include "core/filter/filter.h"
#include "core/operators/point_cloud_laplace.h"
#include "core/types.h"
#include "filter_table.h"

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace geofilter {

// Parameter values by name; bools as 0/1, enums as the index. Missing names take the
// table's default.
using ParameterValues = std::map<std::string, double>;

struct RunInput {
    const Points& points;
    const Triangles& triangles;
    const std::vector<int>& selected_faces;
    ProgressCallback progress;
    // Per-vertex quality, for region = quality as weight (null or empty: the mesh has none).
    const std::vector<double>* vertex_quality = nullptr;
    // Kept by an adapter whose user reruns filters on the same mesh (MeshLab's Preview);
    // null: nothing is kept between runs.
    FilterCache* cache = nullptr;
    // The factored solver's algorithm on another engine (FilterOptions::external_solver).
    ExternalFactoredSolver external_solver;
    // Exact solves of complex pole pairs (FilterOptions::complex_factorization); adapters pass
    // exact_pair_factorization() (exact_pairs.h), empty: CG for every pair.
    ComplexShiftedFactorization complex_factorization;
    // A point cloud's selected points (vertex indices): its feature for useSelection and its
    // region for region = selected faces. Read only when the input is a cloud (no triangles);
    // a mesh's selection is its faces.
    std::vector<int> selected_vertices;
};

struct RunOutput {
    Points points;                              // filtered coordinates (empty for Measure)
    std::optional<FeatureEllipsoid> feature;    // set when the selection was measured
    std::optional<Mesh> ellipsoid_mesh;         // Measure: the fitted ellipsoid as a mesh
    TransferFunction transfer;                  // the designed G(s) (filters only)
    double s1_used = 0;                         // the frequency actually used
    double s2_used = 0;                         // second-order filters: the unit-gain frequency used
    double radius_used = 0;                     // the feature radius behind s1_used (0: typed frequencies)
    Operator op = Operator::Cotangent;          // the Laplacian the filter ran on
    Points normals;                             // a point cloud's estimated unit normals (empty for a mesh)
    FilterReport report;
    std::vector<std::string> log;               // human-readable lines, in order
};

// Default parameter values for `spec` (the table's, or the adapter's choice for
// useSelection, which should follow "has the mesh selected faces"). Lengths are the table's
// fraction of `diagonal`, the mesh's bounding-box diagonal; without one (NaN) they are left
// out, and run_filter takes them from the mesh it filters.
ParameterValues default_values(const FilterSpec& spec, bool has_selection,
                               double diagonal = std::numeric_limits<double>::quiet_NaN());

// Gives every Length parameter that has no value its default on a mesh of this diagonal.
void complete_lengths(const FilterSpec& spec, ParameterValues& values, double diagonal);

// The transfer function for the given values. The frequency comes from `feature` when given,
// else from typed frequencies (s1, cutoff; corners when radius is 0), else from the feature
// radius. Throws Error naming the parameter at fault.
// Denoise without a feature has no design of its own: it picks one on the mesh (run_filter,
// denoise_sampling_noise), so it is refused here.
TransferFunction design_from_values(const FilterSpec& spec, const ParameterValues& values,
                                    const FeatureEllipsoid* feature, std::vector<std::string>& log, double* s1_used = nullptr,
                                    double* s2_used = nullptr);

// The Laplacian a filter runs on: the `operator` parameter, or the filter's own choice when
// it is Automatic (or the filter has no such parameter: the paper's cotangent). None: Denoise
// without a feature on Automatic, which picks the operator on the mesh.
std::optional<Operator> operator_from_values(const FilterSpec& spec, const ParameterValues& values, bool has_feature);

// The solver options the values ask for (solver, tolerance, iteration cap, fixBoundary).
FilterOptions filter_options(const FilterSpec& spec, const ParameterValues& values);

// run_filter's steps before and after the filtering itself, for an engine that filters a
// mesh no process holds whole (geofilter-mpi reading by slices): the design from the values
// and the measured feature, with its log lines; then, once `out.report` is in, the log
// lines that report it.
RunOutput design_run(const FilterSpec& spec, const ParameterValues& values, const std::optional<FeatureEllipsoid>& feature);
void log_filter_report(RunOutput& out, const FilterOptions& options);

// Runs the filter. Throws Error (with the message an adapter shows verbatim) on any
// refusal; the input is never modified.
// Points and no triangles are a point cloud: every filter runs unchanged on the triangles of
// the cloud's own Laplacian (as_surface_for_filtering), and its selection is its points
// (selected_vertices); the output has the filtered points and the estimated normals.
RunOutput run_filter(const FilterSpec& spec, const ParameterValues& values, const RunInput& input);

// Whether run_filter takes the input as a point cloud: points, no triangles.
bool is_point_cloud(const Points& points, const Triangles& triangles);

// What the filters run on for a point cloud: its points and the local Delaunay fans of its
// Laplacian (point_cloud_laplace.h) as the triangles, whose cotangent operator is the cloud's
// (times 3, which M^-1 K cancels), so a filter designed for meshes means the same on it. The
// selected points become the selected faces: the fan triangles all three of whose corners are
// selected, which region = selected faces and Denoise's bump rule use like a mesh's selection.
struct CloudSurface {
    PointCloudLaplacian cloud;        // K, M, normals, neighbours, local_triangles
    std::vector<int> selected_faces;  // rows of cloud.local_triangles inside the selected points
    std::vector<std::string> warnings;
};
// Throws Error naming the problem (too few points for the neighbourhoods, duplicates,
// non-finite coordinates, neighbourhoods on a line, selected indices out of range).
CloudSurface as_surface_for_filtering(const Points& points, const std::vector<int>& selected_points);

// run_filter's last step: throws Error naming the first vertex whose filtered coordinates are
// NaN or infinite, so that no front end writes them.
void require_finite_output(const Points& points);

// The ellipsoid as a mesh (an icosphere stretched by the radii, rotated and moved).
Mesh ellipsoid_mesh(const FeatureEllipsoid& e, int subdivision_levels = 3);

} // namespace geofilter
