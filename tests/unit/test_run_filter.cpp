// What run_filter tells the user: a leftover selection silently replacing the typed s1 is
// the most surprising thing a filter can do, so the log must say it.
#include "shapes.h"
#include "run_filter.h"

#include <gtest/gtest.h>

using namespace geofilter;

TEST(RunFilter, LogSaysTheSelectionReplacedTheTypedFrequency) {
    const Mesh s = icosphere(3, 0.5);
    std::vector<int> selected(s.triangles.rows());
    for (size_t f = 0; f < selected.size(); ++f) selected[f] = static_cast<int>(f);
    const FilterSpec& spec = *find_filter("lowpass");
    ParameterValues values = default_values(spec, true);
    values[param::s1] = 33;
    values[param::s2] = 66;
    const RunOutput out = run_filter(spec, values, {s.points, s.triangles, selected, {}});
    const std::string expected_start = "s1 = " + format_number(out.s1_used) + " from " + std::to_string(selected.size()) +
                                       " selected faces";
    bool found = false;
    for (const auto& line : out.log)
        if (line.rfind(expected_start, 0) == 0 && line.find("instead of the typed 33") != std::string::npos) found = true;
    EXPECT_TRUE(found) << "no log line starts with '" << expected_start << "' and names the typed 33";
    EXPECT_NEAR(out.s1_used, 2 / (0.5 * 0.5), 0.05 * 8);
}
