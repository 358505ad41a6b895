// Small things both of geofilter-mpi's paths use: who am I among how many, where each rank's
// block starts in a gathered array, how long since.
#pragma once

#include <mpi.h>

#include <chrono>
#include <vector>

namespace geofilter::mpi {

struct Ranks {
    int rank = 0, size = 1;
    explicit Ranks(MPI_Comm comm) {
        MPI_Comm_rank(comm, &rank);
        MPI_Comm_size(comm, &size);
    }
};

inline std::vector<int> displacements(const std::vector<int>& counts) {
    std::vector<int> displs(counts.size(), 0);
    for (size_t r = 1; r < counts.size(); ++r) displs[r] = displs[r - 1] + counts[r - 1];
    return displs;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace geofilter::mpi
