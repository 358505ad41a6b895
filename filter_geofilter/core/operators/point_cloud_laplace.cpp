// Why local Delaunay fans: Sharp & Crane, "A Laplacian for Nonmanifold Triangle Meshes"
// (SGP 2020, section on point clouds). A cloud has no triangles, but every point can triangulate
// its own neighbourhood in its tangent plane; the triangles incident to the point (its Delaunay
// fan) are what a good mesh through the cloud would have there. The fans of all points together
// form a non-manifold soup that covers the surface about three times (a triangle shared by three
// points' fans appears in each), so its cotangent K and lumped M, each divided by 3, have the
// mesh operator's units and limit. Their tufted intrinsic cover, which would make every weight
// non-negative, is not built here: the soup's K is positive semi-definite either way (each
// triangle's linear-FEM stiffness is), which is all the filters' factorisations need.
#include "core/operators/point_cloud_laplace.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace geofilter {

namespace {

// A k-d tree over the rows of `points`, split at the median of the widest axis; small enough to
// own rather than add a dependency for one query type.
class KdTree {
public:
    explicit KdTree(const Points& points) : points_(points), index_(static_cast<size_t>(points.rows())) {
        std::iota(index_.begin(), index_.end(), 0);
        build(0, static_cast<int>(index_.size()));
    }

    // The k nearest points to point `self`, other than itself, nearest first.
    void nearest(int self, int k, std::vector<std::pair<double, int>>& found) const {
        found.clear();
        search(0, points_.row(self), self, k, found);
        std::sort_heap(found.begin(), found.end());
    }

private:
    static constexpr int kLeafSize = 12;
    struct Node {
        int begin, end;
        int axis = -1;  // -1: a leaf holding index_[begin .. end)
        double split = 0;
        int below = -1, above = -1;
    };

    int build(int begin, int end) {
        const int id = static_cast<int>(nodes_.size());
        nodes_.push_back({begin, end});
        if (end - begin <= kLeafSize) return id;
        Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(INFINITY), hi = -lo;
        for (int i = begin; i < end; ++i) {
            lo = lo.cwiseMin(points_.row(index_[i]));
            hi = hi.cwiseMax(points_.row(index_[i]));
        }
        int axis = 0;
        (hi - lo).maxCoeff(&axis);
        const int mid = begin + (end - begin) / 2;
        std::nth_element(index_.begin() + begin, index_.begin() + mid, index_.begin() + end,
                         [&](int a, int b) { return points_(a, axis) < points_(b, axis); });
        const double split = points_(index_[mid], axis);
        const int below = build(begin, mid);
        const int above = build(mid, end);
        nodes_[id].axis = axis;
        nodes_[id].split = split;
        nodes_[id].below = below;
        nodes_[id].above = above;
        return id;
    }

    // `found` is a max-heap on squared distance holding at most k candidates.
    void search(int node_id, const Eigen::RowVector3d& query, int self, int k,
                std::vector<std::pair<double, int>>& found) const {
        const Node& node = nodes_[node_id];
        if (node.axis < 0) {
            for (int i = node.begin; i < node.end; ++i) {
                const int j = index_[i];
                if (j == self) continue;
                const double d2 = (points_.row(j) - query).squaredNorm();
                if (static_cast<int>(found.size()) < k) {
                    found.emplace_back(d2, j);
                    std::push_heap(found.begin(), found.end());
                } else if (d2 < found.front().first) {
                    std::pop_heap(found.begin(), found.end());
                    found.back() = {d2, j};
                    std::push_heap(found.begin(), found.end());
                }
            }
            return;
        }
        // Everything below the split has coordinate <= split, everything above >= split.
        const double offset = query[node.axis] - node.split;
        const int near = offset < 0 ? node.below : node.above, far = offset < 0 ? node.above : node.below;
        search(near, query, self, k, found);
        if (static_cast<int>(found.size()) < k || offset * offset < found.front().first)
            search(far, query, self, k, found);
    }

    const Points& points_;
    std::vector<int> index_;
    std::vector<Node> nodes_;
};

void check_cloud(const Points& points, int k) {
    if (k < 3)
        throw Error("a point-cloud Laplacian needs at least 3 neighbours per point to triangulate around it (asked: " +
                    std::to_string(k) + ")");
    if (points.rows() < k + 1)
        throw Error("the point cloud has " + std::to_string(points.rows()) + " points; its Laplacian with " +
                    std::to_string(k) + " neighbours per point needs at least " + std::to_string(k + 1) +
                    ": give more points or fewer neighbours");
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (!points.row(i).allFinite())
            throw Error("point " + std::to_string(i) + " of the cloud has a non-finite coordinate");
    std::vector<int> order(static_cast<size_t>(points.rows()));
    std::iota(order.begin(), order.end(), 0);
    auto key = [&](int i) { return std::make_tuple(points(i, 0), points(i, 1), points(i, 2)); };
    std::sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
    int duplicates = 0;
    for (size_t i = 1; i < order.size(); ++i)
        if (key(order[i]) == key(order[i - 1])) ++duplicates;
    if (duplicates > 0)
        throw Error("the point cloud has " + std::to_string(duplicates) +
                    " exact duplicate point(s) (the same coordinates as another point): a duplicate has no"
                    " neighbourhood of its own; remove them first");
}

// The tangent frame of a neighbourhood: its principal axes (the normal along the least spread).
struct Frame {
    Eigen::Vector3d tangent, normal;
};

Frame principal_frame(const Points& points, int centre, const NeighbourTable& neighbours) {
    const Eigen::Index k = neighbours.cols();
    Eigen::MatrixXd local(k + 1, 3);
    local.row(0) = points.row(centre);
    for (Eigen::Index j = 0; j < k; ++j) local.row(j + 1) = points.row(neighbours(centre, j));
    const Eigen::MatrixXd centred = local.rowwise() - local.colwise().mean();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> pca(centred.transpose() * centred);
    const Eigen::Vector3d spread = pca.eigenvalues();  // ascending
    // Collinear points leave the second axis at rounding level: no plane, no triangles.
    if (!(spread[1] > 1e-12 * spread[2]))
        throw Error("the neighbours of point " + std::to_string(centre) +
                    " lie on a line: its tangent plane is undefined (a cloud sampled along a curve, or too few"
                    " neighbours for the sampling)");
    return {pca.eigenvectors().col(2), pca.eigenvectors().col(0)};
}

// Flips normals so that neighbours agree: the propagation of Hoppe et al. (1992) along a
// minimum spanning tree of the neighbour graph weighted by 1 - |n_i . n_j|, which crosses
// nearly parallel normals first and so does not flip across sharp bends. Each connected part is
// then turned as a whole so that most of its normals point away from its centroid.
void orient_normals(const Points& points, const NeighbourTable& neighbours, std::vector<Frame>& frames) {
    const int n = static_cast<int>(points.rows());
    std::vector<std::vector<int>> adjacent(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < neighbours.cols(); ++j) {
            adjacent[i].push_back(neighbours(i, j));
            adjacent[neighbours(i, j)].push_back(i);
        }
    std::vector<int> part(static_cast<size_t>(n), -1);
    using Candidate = std::tuple<double, int, int>;  // weight, point, the tree point it joins through
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue;
    int parts = 0;
    for (int seed = 0; seed < n; ++seed) {
        if (part[seed] >= 0) continue;
        std::vector<int> members;
        queue.emplace(0.0, seed, -1);
        while (!queue.empty()) {
            const auto [weight, i, from] = queue.top();
            queue.pop();
            if (part[i] >= 0) continue;
            part[i] = parts;
            members.push_back(i);
            if (from >= 0 && frames[i].normal.dot(frames[from].normal) < 0) frames[i].normal = -frames[i].normal;
            for (int j : adjacent[i])
                if (part[j] < 0) queue.emplace(1.0 - std::abs(frames[i].normal.dot(frames[j].normal)), j, i);
        }
        Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
        for (int i : members) centroid += points.row(i);
        centroid /= static_cast<double>(members.size());
        size_t outward = 0;
        for (int i : members) outward += (points.row(i) - centroid).dot(frames[i].normal.transpose()) > 0;
        if (2 * outward < members.size())
            for (int i : members) frames[i].normal = -frames[i].normal;
        ++parts;
    }
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// sin 1 degree: fan triangles whose angle at the centre is within a degree of 0 or 180 are
// slivers (see append_delaunay_fan); cot 1 degree = 57 bounds the weight one of them can add.
constexpr double kMinFanAngleSine = 0.0174524064372835;

// Indices of the convex hull's vertices, counter-clockwise (Andrew's monotone chain); points on
// a hull edge are left out.
std::vector<int> convex_hull(const std::vector<Eigen::Vector2d>& w) {
    std::vector<int> order(w.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return std::make_pair(w[a].x(), w[a].y()) < std::make_pair(w[b].x(), w[b].y()); });
    if (order.size() < 3) return order;
    std::vector<int> hull(2 * order.size());
    size_t size = 0;
    auto turns_left = [&](int a, int b, int c) { return cross2(w[b] - w[a], w[c] - w[a]) > 0; };
    for (int i : order) {  // lower chain
        while (size >= 2 && !turns_left(hull[size - 2], hull[size - 1], i)) --size;
        hull[size++] = i;
    }
    const size_t lower = size + 1;
    for (auto it = order.rbegin() + 1; it != order.rend(); ++it) {  // upper chain
        while (size >= lower && !turns_left(hull[size - 2], hull[size - 1], *it)) --size;
        hull[size++] = *it;
    }
    hull.resize(size - 1);  // the last is the first again
    return hull;
}

// Appends the triangles of point `centre`'s Delaunay fan among its first `candidates`
// neighbours, projected on the tangent plane. The Delaunay neighbours of the centre are the
// points whose bisector with it bounds its Voronoi cell; inverting each projected neighbour q
// to q / |q|^2 turns those bisectors into points, and the cell's edges, in order, into the
// convex hull of the inverted points. Two hull-consecutive neighbours a, b make a Delaunay
// triangle with the centre where their Voronoi edges meet, which is where (centre, a, b)
// turns counter-clockwise; on the open side of a boundary point they do not. False when no
// triangle was made.
bool append_delaunay_fan(const Points& points, int centre, const NeighbourTable& neighbours, int candidates,
                         const Frame& frame, std::vector<Eigen::Vector3i>& triangles) {
    const Eigen::Vector3d side = frame.normal.cross(frame.tangent);
    std::vector<Eigen::Vector2d> projected, inverted;
    std::vector<int> point_of;
    double farthest = 0;
    for (int j = 0; j < candidates; ++j) {
        const Eigen::Vector3d d = (points.row(neighbours(centre, j)) - points.row(centre)).transpose();
        projected.emplace_back(d.dot(frame.tangent), d.dot(side));
        farthest = std::max(farthest, projected.back().norm());
    }
    for (int j = 0; j < candidates; ++j) {
        const Eigen::Vector2d& q = projected[j];
        // A neighbour straight above the centre (a fold of the cloud within the neighbourhood)
        // has no direction in the plane.
        if (q.norm() <= 1e-9 * farthest) continue;
        inverted.push_back(q / q.squaredNorm());
        point_of.push_back(static_cast<int>(j));
    }
    const std::vector<int> hull = convex_hull(inverted);
    const size_t before = triangles.size();
    for (size_t h = 0; hull.size() >= 2 && h < hull.size(); ++h) {
        const int a = point_of[hull[h]], b = point_of[hull[(h + 1) % hull.size()]];
        const Eigen::Vector2d &qa = projected[a], &qb = projected[b];
        // A pair less than a degree from straight across the centre is the open side of a
        // straight border, or of a crease folded flat by the projection: rounding decides its
        // sign, it covers almost no area, and its cotangents are unbounded (a scan's lattice
        // of subdivided points gave weights 1e11 times the median, which no solver survives).
        // A pair less than a degree apart makes a sliver too.
        if (cross2(qa, qb) > kMinFanAngleSine * qa.norm() * qb.norm())
            triangles.emplace_back(centre, neighbours(centre, a), neighbours(centre, b));
    }
    return triangles.size() > before;
}

} // namespace

NeighbourTable nearest_neighbours(const Points& points, int k) {
    const int n = static_cast<int>(points.rows());
    const KdTree tree(points);
    NeighbourTable table(n, k);
    std::vector<std::pair<double, int>> found;
    for (int i = 0; i < n; ++i) {
        tree.nearest(i, k, found);
        for (int j = 0; j < k; ++j) table(i, j) = found[j].second;
    }
    return table;
}

PointCloudLaplacian point_cloud_laplacian(const Points& points, const PointCloudOptions& options) {
    const int k = options.neighbours;
    check_cloud(points, k);
    if (options.fan_candidates < 3)
        throw Error("a point's local triangulation needs at least 3 candidate neighbours (asked: " +
                    std::to_string(options.fan_candidates) + ")");
    const int n = static_cast<int>(points.rows());

    PointCloudLaplacian result;
    result.neighbours = nearest_neighbours(points, k);
    std::vector<Frame> frames(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) frames[i] = principal_frame(points, i, result.neighbours);
    orient_normals(points, result.neighbours, frames);

    std::vector<Eigen::Vector3i> fans;
    fans.reserve(static_cast<size_t>(n) * 7);
    result.fan_candidates = std::min(options.fan_candidates, k);
    for (int i = 0; i < n; ++i) {
        if (append_delaunay_fan(points, i, result.neighbours, result.fan_candidates, frames[i], fans)) continue;
        // The nearest few on a line (a dense scan line through sparser points, the edge of a
        // midpoint-subdivided sliver): all k, as many as the plane was fitted to.
        ++result.fans_from_all_neighbours;
        if (!append_delaunay_fan(points, i, result.neighbours, k, frames[i], fans))
            throw Error("point " + std::to_string(i) +
                        " has no triangle around it: its neighbours lie on a line through it in its tangent plane");
    }

    result.normals.resize(n, 3);
    for (int i = 0; i < n; ++i) result.normals.row(i) = frames[i].normal.transpose();
    result.local_triangles.resize(static_cast<Eigen::Index>(fans.size()), 3);
    for (size_t f = 0; f < fans.size(); ++f) result.local_triangles.row(static_cast<Eigen::Index>(f)) = fans[f].transpose();

    result.laplacian = cotan_laplacian(points, result.local_triangles);
    // Each piece of surface is covered by about three fans (one per corner of its triangle).
    result.laplacian.stiffness /= 3.0;
    result.laplacian.mass /= 3.0;
    return result;
}

} // namespace geofilter
