#include "core/types.h"

#include <sstream>

namespace geofilter {

std::string format_number(double value, int significant_digits) {
    std::ostringstream os;
    os.precision(significant_digits);
    os << value;
    return os.str();
}

double bounding_box_diagonal(const Points& points) {
    if (points.rows() == 0) return 0;
    return (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
}

} // namespace geofilter
