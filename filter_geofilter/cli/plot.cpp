#include "plot.h"

#include "core/types.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

extern char** environ;

namespace geofilter::cli {

namespace {

// gnuplot's single-quoted strings take everything literally except the quote, which is doubled.
std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

double asymptote(const PoleZeroSpec& pz, double s) {
    // Each zero turns the line up by one decade per decade past it, each pole down.
    double a = pz.G0;
    for (double z : pz.zeros) a *= std::max(1.0, s / z);
    for (double p : pz.poles) a *= std::min(1.0, p / s);
    return std::abs(a);
}

std::string gnuplot_program() {
#ifdef GEOFILTER_GNUPLOT
    if (access(GEOFILTER_GNUPLOT, X_OK) == 0) return GEOFILTER_GNUPLOT;
#endif
    return "gnuplot";  // from PATH
}

// Runs gnuplot on `script`; returns its exit status and what it printed.
int run_gnuplot(const std::string& script, std::string& output) {
    int pipe_fds[2];
    if (pipe(pipe_fds) != 0) throw Error(std::string("cannot run gnuplot: ") + std::strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
    posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
    const std::string program = gnuplot_program();
    std::vector<char*> argv{const_cast<char*>(program.c_str()), const_cast<char*>(script.c_str()), nullptr};
    pid_t pid = 0;
    const int spawn_error = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipe_fds[1]);
    if (spawn_error != 0) {
        close(pipe_fds[0]);
        throw Error("--plot needs gnuplot, which could not be started (" + std::string(std::strerror(spawn_error)) +
                    "): apt install gnuplot-nox");
    }
    char buffer[4096];
    for (ssize_t n; (n = read(pipe_fds[0], buffer, sizeof buffer)) != 0;) {
        if (n < 0) {
            if (errno == EINTR) continue;
            break;
        }
        output.append(buffer, size_t(n));
    }
    close(pipe_fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

std::string last_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    const size_t nl = text.find_last_of('\n');
    return nl == std::string::npos ? text : text.substr(nl + 1);
}

} // namespace

void write_transfer_plot(const std::string& png_path, const TransferPlot& plot) {
    double s_lo = std::numeric_limits<double>::infinity(), s_hi = 0;
    for (const auto& m : plot.markers) {
        if (!(m.frequency > 0) || !std::isfinite(m.frequency)) continue;
        s_lo = std::min(s_lo, m.frequency);
        s_hi = std::max(s_hi, m.frequency);
    }
    if (s_hi == 0) s_lo = s_hi = 10;
    // Two decades either side show the flat low and high bands around the features.
    s_lo /= 100;
    s_hi *= 100;

    const int samples = 1200;
    std::ostringstream data;
    data.precision(10);
    double g_max = 0, g_min = std::numeric_limits<double>::infinity();
    bool negative = false;
    for (int i = 0; i <= samples; ++i) {
        const double s = s_lo * std::pow(s_hi / s_lo, double(i) / samples);
        const double g = plot.g(s);
        const double magnitude = std::abs(g);
        if (std::isfinite(magnitude) && magnitude > 0) {
            g_max = std::max(g_max, magnitude);
            g_min = std::min(g_min, magnitude);
        }
        negative = negative || g < 0;
        // NaN breaks gnuplot's line: each sign gets its own segments.
        data << s << ' ' << (g > 0 ? magnitude : NAN) << ' ' << (g < 0 ? magnitude : NAN) << ' '
             << (plot.asymptotes ? asymptote(*plot.asymptotes, s) : NAN) << '\n';
        if (plot.asymptotes) g_max = std::max(g_max, asymptote(*plot.asymptotes, s));
    }
    if (!(g_max > 0)) g_max = 1;
    g_max = std::max(g_max, 1.0);
    // Near a zero of G the magnitude plunges without bound: six decades below the peak are enough.
    const double y_lo = std::max(std::min(g_min, 1.0) / 2, g_max * 1e-6), y_hi = g_max * 3;

    std::ostringstream gp;
    gp.precision(10);
    gp << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
          "  set terminal pngcairo size 1000,650 noenhanced font ',11'\n"
          "} else {\n"
          "  set terminal png size 1000,650 noenhanced\n"
          "}\n"
       << "set output " << quoted(png_path) << "\n"
       << "set title " << quoted(plot.title) << "\n"
       << "set logscale xy\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
       << "set xlabel 's: eigenvalue of -L (1/length^2); a sphere-like feature of radius r has s = 2/r^2'\n"
       << "set ylabel '|G(s)|: gain of the mode of frequency s'\n"
       << "set xrange [" << s_lo << ":" << s_hi << "]\nset yrange [" << y_lo << ":" << y_hi << "]\n"
       << "set key below box maxrows 2\nset bmargin 7\n";
    // Over less than three decades gnuplot labels too few ticks to read the gain off: 1-2-5 steps.
    if (y_hi / y_lo < 1e3) {
        gp << "set ytics (";
        const char* separator = "";
        for (double decade = std::pow(10.0, std::floor(std::log10(y_lo))); decade < y_hi; decade *= 10)
            for (double step : {1.0, 2.0, 5.0})
                if (decade * step >= y_lo && decade * step <= y_hi) {
                    gp << separator << "'" << decade * step << "' " << decade * step;
                    separator = ", ";
                }
        gp << ")\n";
    }
    const char* colours[] = {"#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
    int n = 0;
    for (const auto& m : plot.markers) {
        if (!(m.frequency > 0) || !std::isfinite(m.frequency)) continue;
        const char* c = colours[n % 8];
        gp << "set arrow from " << m.frequency << ", graph 0 to " << m.frequency << ", graph 1 nohead dt 4 lw 1.5 lc rgb '"
           << c << "'\n";
        // Staggered so that labels of nearby frequencies do not print over each other.
        gp << "set label " << quoted(m.label) << " at " << m.frequency << ", graph " << 0.96 - 0.05 * (n % 4)
           << " offset 0.5,0 tc rgb '" << c << "'\n";
        ++n;
    }
    gp << "$gain << EOD\n" << data.str() << "EOD\n";
    gp << "plot $gain using 1:2 with lines lw 2.5 lc rgb '#1f77b4' title 'G(s) > 0'";
    if (negative) gp << ", \\\n  $gain using 1:3 with lines lw 2.5 dt 2 lc rgb '#d62728' title 'G(s) < 0 (|G| shown)'";
    if (plot.asymptotes)
        gp << ", \\\n  $gain using 1:4 with lines lw 1.5 dt 3 lc rgb 'black' title 'asymptotes: +-20 dB/decade per corner'";
    gp << ", \\\n  1 with lines lw 1 dt 3 lc rgb '#999999' title '|G| = 1'\n";

    char script_path[] = "/tmp/geofilter-plot-XXXXXX";
    const int fd = mkstemp(script_path);
    if (fd < 0) throw Error(std::string("cannot write the gnuplot script in /tmp: ") + std::strerror(errno));
    close(fd);
    struct ScriptFile {
        const char* path;
        ~ScriptFile() { std::remove(path); }
    } script_file{script_path};
    {
        std::ofstream out(script_path);
        out << gp.str();
        if (!out) throw Error("cannot write the gnuplot script " + std::string(script_path));
    }
    std::string output;
    const int status = run_gnuplot(script_path, output);
    struct stat st {};
    if (status != 0 || stat(png_path.c_str(), &st) != 0 || st.st_size == 0) {
        const std::string reason = last_line(output);
        throw Error("gnuplot could not draw " + png_path + " (exit " + std::to_string(status) + ")" +
                    (reason.empty() ? "" : ": " + reason));
    }
}

} // namespace geofilter::cli
