// The GeoFilter filters on the command line, for `geofilter` and
// `geofilter-mpi`. The filters, their parameters and defaults come from the filter table, the
// work from run_filter(): this file only wires files, options and messages around them.

#include "cli_run.h"
#include "cli_options.h"
#include "feature_source.h"
#include "mesh_io.h"
#include "output_files.h"
#include "plot.h"
#include "progress_bar.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>

namespace geofilter::cli {

namespace {

volatile std::sig_atomic_t interrupted = 0;

// The first Ctrl-C asks the solver to stop at its next progress report, so that the run
// ends through the normal refusal path (no output written); a second one kills at once.
extern "C" void on_interrupt(int) {
    interrupted = 1;
    std::signal(SIGINT, SIG_DFL);
}

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void check_paths(const CliOptions& o) {
    if (!format_of(o.input)) throw Error("cannot tell the format of INPUT '" + o.input + "': use " + supported_formats());
    if (!o.output.empty()) {
        if (!format_of(o.output))
            throw Error("cannot tell the format of OUTPUT '" + o.output + "': use " + supported_formats());
        if (same_file(o.input, o.output) && !o.overwrite_input)
            throw Error("OUTPUT '" + o.output + "' is the input file: give another name, or --overwrite-input to replace it");
    }
    if (!o.plot.empty()) {
        if (lower_extension(o.plot) != "png") throw UsageError("--plot writes a PNG: give a name ending in .png");
        if (same_file(o.plot, o.input) || (!o.output.empty() && same_file(o.plot, o.output)))
            throw Error("--plot '" + o.plot + "' names the input or output mesh");
    }
}

struct Feature {
    bool known = false;
    double radius = 0;  // r of s = 2/r^2 or 1/r^2
};

// The plot of the design actually used (after --radius or the selection moved it), and the
// same design in words for the summary line.
TransferPlot make_plot(const FilterSpec& spec, const ParameterValues& values, const RunOutput& out, const Feature& feature,
                       std::string& design) {
    TransferPlot plot;
    plot.g = out.transfer;
    const std::string feature_note = feature.known ? " (feature, r = " + format_number(feature.radius) + ")" : "";
    if (spec.kind == FilterKind::SecondOrder) {
        const double s2 = out.s2_used;
        design = "s1 = " + format_number(out.s1_used) + ", s2 = " + format_number(s2) + ", G0 = " + format_number(values.at(param::G0)) +
                 ", G1 = " + format_number(values.at(param::G1)) + ", Ginf = " + format_number(values.at(param::Ginf));
        plot.title = "geofilter " + spec.cli_name + ", eq. 15: " + design;
        plot.markers = {{"s1 = " + format_number(out.s1_used) + feature_note, out.s1_used}, {"s2 = " + format_number(s2), s2}};
        return plot;
    }
    if (spec.kind == FilterKind::Butterworth || spec.kind == FilterKind::Denoise) {
        design = "Butterworth order " + format_number(values.at(param::order)) + ", cutoff sc = " + format_number(out.s1_used) + ", operator " +
                 operator_name(out.op);
        plot.title = "geofilter " + spec.cli_name + ": " + design;
        plot.markers = {{"sc = " + format_number(out.s1_used) + feature_note, out.s1_used}};
        return plot;
    }
    // Pole-zero: run_filter scaled every corner when the selection set one of them.
    PoleZeroSpec pz;
    pz.G0 = values.at(param::G0);
    const int corner = int(values.at(param::feature_corner));
    std::vector<std::string> names;
    for (const auto& prefix : {param::zero_prefix, param::pole_prefix})
        for (int i = 1; i <= param::max_pole_zero; ++i) names.push_back(prefix + std::to_string(i));
    // The radius or the selection set the chosen corner, the others keeping their ratios.
    const double typed = values.at(names[size_t(corner)]);
    const double scale = out.s1_used > 0 && typed > 0 ? out.s1_used / typed : 1.0;
    std::string zeros, poles;
    for (size_t i = 0; i < names.size(); ++i) {
        const double c = values.at(names[i]) * scale;
        if (!(c > 0)) continue;
        const bool zero = i < size_t(param::max_pole_zero);
        (zero ? pz.zeros : pz.poles).push_back(c);
        (zero ? zeros : poles) += (zero ? zeros : poles).empty() ? format_number(c) : ", " + format_number(c);
        plot.markers.push_back({names[i] + " = " + format_number(c) + (int(i) == corner ? feature_note : ""), c});
    }
    design = "G0 = " + format_number(pz.G0) + ", zeros " + (zeros.empty() ? "none" : zeros) + ", poles " +
             (poles.empty() ? "none" : poles);
    plot.title = "geofilter " + spec.cli_name + ", eq. 16: " + design;
    plot.asymptotes = pz;
    return plot;
}

int run(const CliOptions& o, const CommandLineTool& tool) {
    const std::string& program = tool.program;
    const FilterSpec& spec = *o.preset;
    const bool measure = spec.kind == FilterKind::Measure;
    const auto started = std::chrono::steady_clock::now();
    check_paths(o);
    if (tool.check_options) tool.check_options(o);

    std::vector<std::string> log;  // printed only once everything worked: a refusal is one line
    ParameterValues values = o.values;
    Feature feature;
    // Denoise designs from the selected bump or from the mesh: nothing to check before both are read.
    if (!measure && spec.kind != FilterKind::Denoise) {
        // Refuses a bad design before a large mesh is read. Scaling the frequencies (by the
        // selection, or the radius's default on the mesh) keeps a design valid or invalid, so a
        // unit radius stands in for a default not known yet.
        ParameterValues check = values;
        complete_lengths(spec, check, 1.0);
        std::vector<std::string> unused;
        design_from_values(spec, check, nullptr, unused);
    }
    PendingOutputs outputs;
    const std::string mesh_temporary = o.output.empty() ? "" : outputs.reserve(o.output);
    const std::string plot_temporary = o.plot.empty() ? "" : outputs.reserve(o.plot);

    // geofilter-mpi may filter the file without this process reading it whole.
    std::optional<RunOutput> filtered_elsewhere;
    if (tool.filter_file && !measure) filtered_elsewhere = tool.filter_file(o, values, mesh_temporary, log);
    RunOutput out;
    std::optional<MeshFile> mesh;
    std::vector<int> selected, selected_points;
    bool cloud = false;
    if (filtered_elsewhere) {
        out = std::move(*filtered_elsewhere);
        if (out.radius_used > 0) feature = {true, out.radius_used};
    } else {
        mesh.emplace(MeshFile::read(o.input));
        cloud = is_point_cloud(mesh->points(), mesh->triangles());
        log.push_back("read " + o.input + ": " + std::to_string(mesh->points().rows()) +
                      (cloud ? " points and no faces: a point cloud"
                             : " vertices, " + std::to_string(mesh->triangles().rows()) + " triangles") +
                      " (" + format_name(mesh->format()) + ")");
        for (const auto& note : mesh->notes()) log.push_back(note);
        if (cloud && o.select_stored)
            throw Error("--select-stored reads a face selection and '" + o.input +
                        "' is a point cloud (no faces): select its points with --select-sphere or --select-box");
        if (o.select_stored && !mesh->has_stored_flags())
            throw Error("--select-stored: '" + o.input + "' stores no face selection (only PLY can: in MeshLab, export"
                        " with the Flags box ticked)");
        if (o.select_stored && mesh->stored_selection().empty() && o.spheres.empty() && o.boxes.empty())
            throw Error("--select-stored: no face of '" + o.input + "' is selected");
        if (!o.select_stored && !mesh->stored_selection().empty())
            log.push_back("the input stores a selection of " + std::to_string(mesh->stored_selection().size()) +
                          " faces; --select-stored would take the feature from it");

        if (cloud && o.selects_region()) selected_points = select_points(mesh->points(), o, log);
        selected =
            o.selects_region() && !cloud
                ? select_faces(mesh->points(), mesh->triangles(), o, o.select_stored ? mesh->stored_selection() : std::vector<int>{}, log)
                : std::vector<int>{};

        ProgressBar bar(!o.quiet);
        std::signal(SIGINT, on_interrupt);
        const ProgressCallback progress = [&bar](double fraction, const std::string& stage) {
            bar.update(fraction, stage);
            return interrupted == 0;
        };
        if (spec.parameter(param::region) && values.at(param::region) == 1 && !o.selects_region())
            throw Error(cloud ? "--region selected filters only the selected points of the cloud: give them with"
                                " --select-sphere or --select-box"
                              : "--region selected filters only the selected faces: give them with --select-sphere,"
                                " --select-box or --select-stored");
        out =
            run_filter(spec, values, RunInput{mesh->points(), mesh->triangles(), selected, progress, &mesh->vertex_quality(),
                                              nullptr, tool.external_solver, tool.complex_factorization, selected_points});
        bar.clear();
        if (interrupted) throw Error("interrupted");
        if (out.radius_used > 0) feature = {true, out.radius_used};

        std::ostringstream summary;
        if (measure) {
            if (!mesh_temporary.empty()) write_mesh(mesh_temporary, *out.ellipsoid_mesh);
            outputs.commit();
            if (!o.quiet) {
                for (const auto& line : log) std::cerr << program << ": " << line << '\n';
                for (const auto& line : out.log) std::cout << line << '\n';
            }
            // The summary is the measurement asked for: printed even with --quiet.
            const FeatureEllipsoid& e = *out.feature;
            // 10 digits: the measurement is the result here, and a script may compare it.
            summary << program << ": measure: r = " << format_number(e.radius, 10) << ": sphere-like s = 2/r^2 = "
                    << format_number(e.frequency(FeatureShape::Sphere), 10) << ", cylinder-like s = 1/r^2 = "
                    << format_number(e.frequency(FeatureShape::Cylinder), 10) << " ("
                    << (e.point_count > 0 ? std::to_string(e.point_count) + " points" : std::to_string(e.face_count) + " faces")
                    << ")";
            if (!o.output.empty()) summary << "; ellipsoid written to " << o.output;
            std::cout << summary.str() << std::endl;
            return 0;
        }
    }

    std::string design;
    const TransferPlot plot = make_plot(spec, values, out, feature, design);
    if (!plot_temporary.empty()) write_transfer_plot(plot_temporary, plot);
    if (mesh) mesh->write(mesh_temporary, out.points, selected, cloud ? &out.normals : nullptr);
    if (interrupted) throw Error("interrupted");
    outputs.commit();
    log.insert(log.end(), out.log.begin(), out.log.end());
    log.push_back("wrote " + o.output + (o.plot.empty() ? "" : " and the plot " + o.plot));
    if (!o.quiet) {
        for (const auto& line : log) std::cerr << program << ": " << line << '\n';
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        std::cout << program << ": " << spec.cli_name << ": " << o.input << " -> " << o.output << ": "
                  << out.report.active_vertices << " vertices filtered; " << design
                  << (feature.known ? "; feature r = " + format_number(feature.radius) : std::string()) << "; "
                  << solver_used(out.report) << ", " << format_number(seconds, 3) << " s" << std::endl;
    }
    return 0;
}

void print_error(const std::string& program, const std::string& message) {
    std::string line = message;
    std::replace(line.begin(), line.end(), '\n', ' ');  // one line, whatever the source
    std::cerr << program << ": error: " << line << std::endl;
}

} // namespace

int run_command_line(const std::vector<std::string>& args, const CommandLineTool& tool) {
    try {
        const CliOptions options = parse_command_line(args);
        if (options.help) {
            std::cout << help_text(options.preset);
            return 0;
        }
        return run(options, tool);
    } catch (const UsageError& e) {
        print_error(tool.program, e.what());
        return 2;
    } catch (const geofilter::Error& e) {
        print_error(tool.program, e.what());
        return 1;
    } catch (const std::bad_alloc&) {
        print_error(tool.program, "out of memory");
        return 1;
    } catch (const std::exception& e) {
        print_error(tool.program, std::string("internal error: ") + e.what());
        return 1;
    }
}

} // namespace geofilter::cli
