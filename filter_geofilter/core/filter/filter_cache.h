// What apply_filter can keep from one run to the next on the same mesh. MeshLab's Preview
// applies a filter again and again to the same mesh with other parameters, then once more on
// Apply: everything that does not depend on the transfer function (mesh checks, Laplacian,
// components, boundary split, Kt and its symbolic analysis) is built once, a factor is reused
// while its shift still pays off, CG starts from the previous run's pair solutions, and a run
// with the same filter returns the held result.
#pragma once

#include "core/types.h"

#include <memory>

namespace geofilter {

namespace detail {
struct MeshStage;
}

class FilterCache {
public:
    // Meshes with more vertices are not kept: the cache holds about as much memory as one
    // filter run needs (~1.5 KB per vertex) for as long as it lives.
    explicit FilterCache(Eigen::Index max_vertices = 500000);
    ~FilterCache();
    FilterCache(const FilterCache&) = delete;
    FilterCache& operator=(const FilterCache&) = delete;

    void clear();
    Eigen::Index max_vertices() const { return max_vertices_; }

    // Internal to the core.
    std::unique_ptr<detail::MeshStage>& stage() { return stage_; }

private:
    Eigen::Index max_vertices_;
    std::unique_ptr<detail::MeshStage> stage_;
};

} // namespace geofilter
