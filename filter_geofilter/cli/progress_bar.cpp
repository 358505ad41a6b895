#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace geofilter::cli {

namespace {
// A quick run would only flash the bar.
constexpr std::chrono::milliseconds show_after{400};
constexpr std::chrono::milliseconds redraw_every{100};
constexpr int bar_width = 30;
} // namespace

ProgressBar::ProgressBar(bool enabled)
    : enabled_(enabled && isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

ProgressBar::~ProgressBar() { clear(); }

void ProgressBar::update(double fraction, const std::string& stage) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - start_ < show_after || (drawn_ && now - last_draw_ < redraw_every && fraction < 1)) return;
    last_draw_ = now;
    fraction = std::clamp(fraction, 0.0, 1.0);
    const int filled = int(std::lround(fraction * bar_width));
    const double seconds = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "\r\033[Kgeofilter: [%s%s] %3d%%  %-28.28s %6.1f s", std::string(size_t(filled), '#').c_str(),
                 std::string(size_t(bar_width - filled), '.').c_str(), int(std::lround(100 * fraction)), stage.c_str(),
                 seconds);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::clear() {
    if (!drawn_) return;
    std::fputs("\r\033[K", stderr);
    std::fflush(stderr);
    drawn_ = false;
}

} // namespace geofilter::cli
