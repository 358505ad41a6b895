// A one-line progress bar on stderr for solves long enough to wonder about, fed by the
// core's ProgressCallback. Drawn only on a terminal: redirected stderr stays a clean log.
#pragma once

#include <chrono>
#include <string>

namespace geofilter::cli {

class ProgressBar {
public:
    explicit ProgressBar(bool enabled);
    ~ProgressBar();  // erases the bar
    void update(double fraction, const std::string& stage);
    void clear();

private:
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_, last_draw_;
};

} // namespace geofilter::cli
