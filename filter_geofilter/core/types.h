// Shared vocabulary of the GeoFilter core: plain Eigen matrices and one error type.
// The core knows nothing of Qt or MeshLab so that the same math serves every adapter.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <stdexcept>
#include <string>

namespace geofilter {

// Row-major so that an adapter can map a contiguous xyz buffer without copying.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Triangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using SparseMatrix = Eigen::SparseMatrix<double>;

struct Mesh {
    Points points;
    Triangles triangles;
};

// Every refusal of the core is an Error whose message names the problem and,
// where there is one, the fix. Adapters show what() verbatim.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A number as messages and logs show it: 6 significant digits unless asked for more.
std::string format_number(double value, int significant_digits = 6);

// The length of the bounding box's diagonal: the mesh's size, which relative lengths and
// tolerances are fractions of (0 for no points).
double bounding_box_diagonal(const Points& points);

} // namespace geofilter
