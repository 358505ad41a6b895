#include "distributed_pipeline.h"

#include "ply_slices.h"
#include "ranks.h"

#include "core/mesh/components.h"
#include "core/feature/feature.h"
#include "core/operators/laplace.h"
#include "core/mesh/mesh_prep.h"
#include "core/solve/solvers.h"
#include "filter_table.h"

#include <petscis.h>
#include <petscmat.h>
#include <petscvec.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>

namespace geofilter::mpi {

namespace {

// What every rank needs to take part in one file's filter, sent by rank 0.
struct FileJob {
    std::string preset, input, output;
    ParameterValues values;
    std::vector<cli::SphereRegion> spheres;
    std::vector<cli::BoxRegion> boxes;
    PoleSolver pole_solver = PoleSolver::Direct;
};

class Packer {
public:
    std::vector<char> bytes;
    void number(double v) { append(&v, sizeof v); }
    void text(const std::string& s) {
        number(double(s.size()));
        append(s.data(), s.size());
    }
    double number() {
        double v;
        take(&v, sizeof v);
        return v;
    }
    std::string text() {
        std::string s(size_t(number()), '\0');
        take(s.data(), s.size());
        return s;
    }

private:
    void append(const void* p, size_t n) { bytes.insert(bytes.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n); }
    void take(void* p, size_t n) {
        std::memcpy(p, bytes.data() + at_, n);
        at_ += n;
    }
    size_t at_ = 0;
};

FileJob broadcast_job(MPI_Comm comm, const FileJob* job) {
    Packer p;
    if (job) {
        p.text(job->preset);
        p.text(job->input);
        p.text(job->output);
        p.number(double(int(job->pole_solver)));
        p.number(double(job->values.size()));
        for (const auto& [name, value] : job->values) {
            p.text(name);
            p.number(value);
        }
        p.number(double(job->spheres.size()));
        for (const auto& s : job->spheres) {
            for (int k = 0; k < 3; ++k) p.number(s.center[k]);
            p.number(s.radius);
        }
        p.number(double(job->boxes.size()));
        for (const auto& b : job->boxes)
            for (int k = 0; k < 3; ++k) {
                p.number(b.low[k]);
                p.number(b.high[k]);
            }
    }
    unsigned long size = p.bytes.size();
    MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG, 0, comm);
    p.bytes.resize(size);
    MPI_Bcast(p.bytes.data(), int(size), MPI_CHAR, 0, comm);
    FileJob out;
    out.preset = p.text();
    out.input = p.text();
    out.output = p.text();
    out.pole_solver = PoleSolver(int(p.number()));
    for (int i = int(p.number()); i > 0; --i) {
        const std::string name = p.text();
        out.values[name] = p.number();
    }
    out.spheres.resize(size_t(p.number()));
    for (auto& s : out.spheres) {
        for (int k = 0; k < 3; ++k) s.center[k] = p.number();
        s.radius = p.number();
    }
    out.boxes.resize(size_t(p.number()));
    for (auto& b : out.boxes)
        for (int k = 0; k < 3; ++k) {
            b.low[k] = p.number();
            b.high[k] = p.number();
        }
    return out;
}

// Runs a step that makes no collective call; if it throws on any rank, every rank throws the
// message of the first rank that failed, so that rank 0 reports it and no rank is left behind.
void together(MPI_Comm comm, const std::function<void()>& step) {
    const Ranks ranks(comm);
    std::string message;
    int first = ranks.size;
    try {
        step();
    } catch (const Error& e) {
        message = e.what();
        first = ranks.rank;
    } catch (const std::bad_alloc&) {
        message = "out of memory on rank " + std::to_string(ranks.rank) + ": run on more ranks or machines";
        first = ranks.rank;
    }
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first == ranks.size) return;
    unsigned long length = message.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG, first, comm);
    message.resize(length);
    MPI_Bcast(message.data(), int(length), MPI_CHAR, first, comm);
    throw Error(message);
}

// Rank r's share of n records starts here.
long long slice_start(long long n, int r, int ranks) { return n * r / ranks; }

int owner_of(long long v, long long n, int ranks) {
    int r = int(std::min<long long>(ranks - 1, v * ranks / n));
    while (r + 1 < ranks && slice_start(n, r + 1, ranks) <= v) ++r;
    while (r > 0 && slice_start(n, r, ranks) > v) --r;
    return r;
}

// Sends outgoing[r] to rank r; returns what each rank sent here.
template <class T>
std::vector<std::vector<T>> exchange(MPI_Comm comm, const std::vector<std::vector<T>>& outgoing, MPI_Datatype type) {
    const Ranks ranks(comm);
    std::vector<int> send_counts(size_t(ranks.size)), receive_counts(size_t(ranks.size));
    for (int r = 0; r < ranks.size; ++r) send_counts[size_t(r)] = int(outgoing[size_t(r)].size());
    MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm);
    std::vector<int> send_displs(size_t(ranks.size), 0), receive_displs(size_t(ranks.size), 0);
    for (int r = 1; r < ranks.size; ++r) {
        send_displs[size_t(r)] = send_displs[size_t(r - 1)] + send_counts[size_t(r - 1)];
        receive_displs[size_t(r)] = receive_displs[size_t(r - 1)] + receive_counts[size_t(r - 1)];
    }
    std::vector<T> send, receive(size_t(receive_displs.back() + receive_counts.back()));
    send.reserve(size_t(send_displs.back() + send_counts.back()));
    for (const auto& part : outgoing) send.insert(send.end(), part.begin(), part.end());
    MPI_Alltoallv(send.data(), send_counts.data(), send_displs.data(), type, receive.data(), receive_counts.data(),
                  receive_displs.data(), type, comm);
    std::vector<std::vector<T>> incoming(size_t(ranks.size));
    for (int r = 0; r < ranks.size; ++r)
        incoming[size_t(r)].assign(receive.begin() + receive_displs[size_t(r)],
                                   receive.begin() + receive_displs[size_t(r)] + receive_counts[size_t(r)]);
    return incoming;
}

// This rank's part of the mesh: its slice of the vertices, then the other ranks' vertices its
// faces use (ghosts, sorted by global index); its slice of the faces in that local numbering.
struct LocalMesh {
    long long vertices = 0, first_vertex = 0, owned = 0;
    long long faces = 0, first_face = 0;
    std::vector<char> vertex_records;
    FaceSlice face_slice;
    std::vector<long long> ghosts;
    Points points;         // owned, then ghosts
    Triangles triangles;   // this rank's faces, local numbering
    std::vector<bool> usable;

    long long global(Eigen::Index local) const {
        return local < owned ? first_vertex + local : ghosts[size_t(local - owned)];
    }
    int local(long long global_index) const {
        if (global_index >= first_vertex && global_index < first_vertex + owned) return int(global_index - first_vertex);
        return int(owned + (std::lower_bound(ghosts.begin(), ghosts.end(), global_index) - ghosts.begin()));
    }
};

// The rows of `owned` (one per owned vertex) that this rank's ghosts have on their owners.
Eigen::MatrixXd ghost_rows(MPI_Comm comm, const LocalMesh& m, const Eigen::MatrixXd& owned) {
    const Ranks ranks(comm);
    const Eigen::Index width = owned.cols();
    std::vector<std::vector<long long>> requests(size_t(ranks.size));
    for (long long v : m.ghosts) requests[size_t(owner_of(v, m.vertices, ranks.size))].push_back(v);
    const auto asked = exchange(comm, requests, MPI_LONG_LONG);
    std::vector<std::vector<double>> replies(size_t(ranks.size));
    for (int r = 0; r < ranks.size; ++r)
        for (long long v : asked[size_t(r)])
            for (Eigen::Index k = 0; k < width; ++k) replies[size_t(r)].push_back(owned(Eigen::Index(v - m.first_vertex), k));
    const auto answered = exchange(comm, replies, MPI_DOUBLE);
    Eigen::MatrixXd rows(Eigen::Index(m.ghosts.size()), width);
    Eigen::Index next = 0;
    for (int r = 0; r < ranks.size; ++r)  // the ghosts are sorted, so grouped by owner in rank order
        for (size_t i = 0; i < requests[size_t(r)].size(); ++i, ++next)
            for (Eigen::Index k = 0; k < width; ++k) rows(next, k) = answered[size_t(r)][size_t(width) * i + size_t(k)];
    return rows;
}

// Adds each ghost's row of `local` (owned rows, then ghost rows) to its owner's row.
void add_ghost_rows_to_owners(MPI_Comm comm, const LocalMesh& m, Eigen::MatrixXd& local) {
    const Ranks ranks(comm);
    const Eigen::Index width = local.cols();
    std::vector<std::vector<double>> outgoing(size_t(ranks.size));
    for (size_t g = 0; g < m.ghosts.size(); ++g) {
        auto& out = outgoing[size_t(owner_of(m.ghosts[g], m.vertices, ranks.size))];
        out.push_back(double(m.ghosts[g]));
        for (Eigen::Index k = 0; k < width; ++k) out.push_back(local(Eigen::Index(m.owned + long(g)), k));
    }
    for (const auto& part : exchange(comm, outgoing, MPI_DOUBLE))
        for (size_t i = 0; i < part.size(); i += size_t(width) + 1)
            for (Eigen::Index k = 0; k < width; ++k)
                local(Eigen::Index(part[i] - double(m.first_vertex)), k) += part[i + 1 + size_t(k)];
}

// Every rank reads its slices; refuses as prepare_mesh does (the same messages).
// This rank's vertex and face records. Collective: a rank that fails makes every rank fail.
void read_slices(MPI_Comm comm, const FileJob& job, PlyLayout& layout, LocalMesh& m) {
    const Ranks ranks(comm);
    together(comm, [&] {
        std::string why_not;
        const std::optional<PlyLayout> read = slice_layout(job.input, why_not);
        if (!read) throw Error("cannot read '" + job.input + "' by slices on rank " + std::to_string(ranks.rank) + ": " + why_not);
        layout = *read;
        m.vertices = layout.vertex_count;
        m.first_vertex = slice_start(m.vertices, ranks.rank, ranks.size);
        m.owned = slice_start(m.vertices, ranks.rank + 1, ranks.size) - m.first_vertex;
        m.faces = layout.face_count;
        m.first_face = slice_start(m.faces, ranks.rank, ranks.size);
        const long long my_faces = slice_start(m.faces, ranks.rank + 1, ranks.size) - m.first_face;
        m.vertex_records = read_vertex_records(job.input, layout, m.first_vertex, m.owned);
        m.face_slice = read_face_records(job.input, layout, m.first_face, my_faces);
    });
}

// The faces' corners in the local numbering (owned, then ghosts).
void number_faces_locally(LocalMesh& m) {
    const auto& corners = m.face_slice.corners;
    m.triangles.resize(Eigen::Index(corners.size() / 3), 3);
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f)
        for (int k = 0; k < 3; ++k) m.triangles(f, k) = m.local(corners[size_t(3 * f + k)]);
}

LocalMesh read_local_mesh(MPI_Comm comm, const FileJob& job, PlyLayout& layout) {
    LocalMesh m;
    read_slices(comm, job, layout, m);
    // The first bad vertex and the first bad face over all ranks, as the whole-mesh check finds them.
    long long bad[2] = {m.vertices, m.faces}, bad_corner = 0;
    m.points.resize(Eigen::Index(m.owned), 3);
    for (long long i = 0; i < m.owned; ++i) {
        m.points.row(Eigen::Index(i)) = position_in_record(layout, m.vertex_records.data() + i * layout.vertex_stride).transpose();
        if (!m.points.row(Eigen::Index(i)).allFinite() && bad[0] == m.vertices) bad[0] = m.first_vertex + i;
    }
    const auto& corners = m.face_slice.corners;
    for (size_t c = 0; c < corners.size() && bad[1] == m.faces; ++c)
        if (corners[c] < 0 || corners[c] >= m.vertices) {
            bad[1] = m.first_face + long(c / 3);
            bad_corner = corners[c];
        }
    long long worst[2];
    MPI_Allreduce(bad, worst, 2, MPI_LONG_LONG, MPI_MIN, comm);
    if (worst[0] < m.vertices)
        throw Error("vertex " + std::to_string(worst[0]) +
                    " has a NaN or infinite coordinate: remove or repair it (e.g. MeshLab's Remove Unreferenced/Duplicate"
                    " Vertices after deleting it)");
    if (worst[1] < m.faces) {
        if (bad[1] != worst[1]) bad_corner = std::numeric_limits<long long>::min();
        MPI_Allreduce(MPI_IN_PLACE, &bad_corner, 1, MPI_LONG_LONG, MPI_MAX, comm);
        throw Error("cannot read '" + job.input + "' as PLY: face " + std::to_string(worst[1]) + " uses vertex " +
                    std::to_string(bad_corner) + " of " + std::to_string(m.vertices));
    }

    // The ghosts' positions, from their owners.
    for (long long v : corners)
        if (v < m.first_vertex || v >= m.first_vertex + m.owned) m.ghosts.push_back(v);
    std::sort(m.ghosts.begin(), m.ghosts.end());
    m.ghosts.erase(std::unique(m.ghosts.begin(), m.ghosts.end()), m.ghosts.end());
    const Eigen::MatrixXd ghost_points = ghost_rows(comm, m, m.points);
    m.points.conservativeResize(Eigen::Index(m.owned) + ghost_points.rows(), 3);
    m.points.bottomRows(ghost_points.rows()) = ghost_points;

    number_faces_locally(m);
    m.usable.resize(size_t(m.triangles.rows()));
    for (long long f = 0; f < m.triangles.rows(); ++f) {
        const auto t = m.triangles.row(Eigen::Index(f));
        m.usable[size_t(f)] = usable_face(m.points.row(t[0]), m.points.row(t[1]), m.points.row(t[2]), corners[size_t(3 * f)],
                                          corners[size_t(3 * f + 1)], corners[size_t(3 * f + 2)]);
    }
    return m;
}

// The faces of this rank inside the job's spheres and boxes (all three corners, as geofilter
// selects), and the log lines of the counts over all ranks; refuses an empty region as
// geofilter does.
std::vector<int> select_local_faces(MPI_Comm comm, const FileJob& job, const LocalMesh& m, std::vector<std::string>& log) {
    std::vector<int> selected;
    auto take = [&](const std::function<bool(const Eigen::Vector3d&)>& inside, const std::string& what) {
        long long count = 0;
        for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
            bool all = true;
            for (int k = 0; k < 3 && all; ++k) all = inside(m.points.row(m.triangles(f, k)).transpose());
            if (all) {
                selected.push_back(int(f));
                ++count;
            }
        }
        MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG_LONG, MPI_SUM, comm);
        if (count == 0) {
            Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
            for (Eigen::Index i = 0; i < Eigen::Index(m.owned); ++i) {
                lo = lo.cwiseMin(m.points.row(i).transpose());
                hi = hi.cwiseMax(m.points.row(i).transpose());
            }
            MPI_Allreduce(MPI_IN_PLACE, lo.data(), 3, MPI_DOUBLE, MPI_MIN, comm);
            MPI_Allreduce(MPI_IN_PLACE, hi.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
            throw Error(what + " holds no face with all three vertices inside: the mesh spans (" + format_number(lo[0]) + ", " +
                        format_number(lo[1]) + ", " + format_number(lo[2]) + ") to (" + format_number(hi[0]) + ", " + format_number(hi[1]) + ", " + format_number(hi[2]) + ")");
        }
        log.push_back(what + ": " + std::to_string(count) + " faces");
    };
    for (const auto& s : job.spheres)
        take([&](const Eigen::Vector3d& p) { return (p - s.center).squaredNorm() <= s.radius * s.radius; },
             "--select-sphere " + format_number(s.center[0]) + "," + format_number(s.center[1]) + "," + format_number(s.center[2]) + "," + format_number(s.radius));
    for (const auto& b : job.boxes)
        take([&](const Eigen::Vector3d& p) { return (p.array() >= b.low.array()).all() && (p.array() <= b.high.array()).all(); },
             "--select-box " + format_number(b.low[0]) + "," + format_number(b.low[1]) + "," + format_number(b.low[2]) + "," + format_number(b.high[0]) + "," +
                 format_number(b.high[1]) + "," + format_number(b.high[2]));
    std::sort(selected.begin(), selected.end());
    selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
    return selected;
}

// The selection's ellipsoid: each rank's moments and extents, reduced.
FeatureEllipsoid measure_distributed_feature(MPI_Comm comm, const LocalMesh& m, const std::vector<int>& selected) {
    const Ranks ranks(comm);
    // About a point of the selection (the lowest rank's first selected corner), as geofilter.
    int holder = selected.empty() ? ranks.size : ranks.rank;
    MPI_Allreduce(MPI_IN_PLACE, &holder, 1, MPI_INT, MPI_MIN, comm);
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    if (holder == ranks.size)
        throw Error("useSelection is on but no faces are selected: select the feature (e.g. with the selection"
                    " tools or Conditional Face Selection), or turn useSelection off and give the frequency directly");
    if (ranks.rank == holder) origin = m.points.row(m.triangles(selected.front(), 0)).transpose();
    MPI_Bcast(origin.data(), 3, MPI_DOUBLE, holder, comm);
    SelectionMoments moments = selection_moments(m.points, m.triangles, selected, origin);
    double sums[14];
    sums[0] = moments.area;
    sums[1] = moments.face_count;
    for (int k = 0; k < 3; ++k) sums[2 + k] = moments.first[k];
    for (int k = 0; k < 9; ++k) sums[5 + k] = moments.second.data()[k];
    MPI_Allreduce(MPI_IN_PLACE, sums, 14, MPI_DOUBLE, MPI_SUM, comm);
    moments.area = sums[0];
    moments.face_count = int(sums[1]);
    for (int k = 0; k < 3; ++k) moments.first[k] = sums[2 + k];
    for (int k = 0; k < 9; ++k) moments.second.data()[k] = sums[5 + k];
    const FeatureFrame frame = feature_frame(moments);  // the same sums on every rank: the same frame
    Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
    extend_in_frame(frame, origin, m.points, m.triangles, selected, low, high);
    MPI_Allreduce(MPI_IN_PLACE, low.data(), 3, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, high.data(), 3, MPI_DOUBLE, MPI_MAX, comm);
    return ellipsoid_in_frame(moments, frame, origin, low, high);
}

// Each owned vertex's component centroid (area-weighted, as the core centres each component)
// and the number of components. Every rank labels the components of its own faces; labels
// that share a vertex are joined on rank 0, which sees only the labels and the joins (about
// the partition's boundary), never the mesh.
struct Components {
    std::vector<int> label;          // per owned vertex
    Eigen::MatrixXd label_centroid;  // per label
    int count = 0;
    Eigen::RowVector3d centroid(Eigen::Index vertex) const { return label_centroid.row(label[size_t(vertex)]); }
};

Components distributed_components(MPI_Comm comm, const LocalMesh& m, const Triangles& usable, const Eigen::VectorXd& local_mass) {
    const Ranks ranks(comm);
    const std::vector<int> label = connected_components(usable, m.points.rows());
    const int labels = component_count(label);
    long long offset = 0, mine = labels;
    MPI_Exscan(&mine, &offset, 1, MPI_LONG_LONG, MPI_SUM, comm);
    if (ranks.rank == 0) offset = 0;
    // Joins: every ghost's label here with its owner's label of it.
    std::vector<std::vector<long long>> joins_out(size_t(ranks.size));
    for (size_t g = 0; g < m.ghosts.size(); ++g) {
        auto& out = joins_out[size_t(owner_of(m.ghosts[g], m.vertices, ranks.size))];
        out.push_back(m.ghosts[g]);
        out.push_back(offset + label[size_t(m.owned) + g]);
    }
    const auto joins_in = exchange(comm, joins_out, MPI_LONG_LONG);
    std::vector<long long> joins;  // pairs of global labels
    for (const auto& part : joins_in)
        for (size_t i = 0; i < part.size(); i += 2) {
            joins.push_back(offset + label[size_t(part[i] - m.first_vertex)]);
            joins.push_back(part[i + 1]);
        }
    // Per label: the mass-weighted sum of positions and the mass, from this rank's faces.
    std::vector<double> sums(size_t(4 * labels), 0.0);
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
        double* s = &sums[size_t(4 * label[size_t(i)])];
        for (int k = 0; k < 3; ++k) s[k] += local_mass[i] * m.points(i, k);
        s[3] += local_mass[i];
    }
    int join_count = int(joins.size()), sum_count = int(sums.size());
    std::vector<int> join_counts(size_t(ranks.size)), sum_counts(size_t(ranks.size));
    MPI_Gather(&join_count, 1, MPI_INT, join_counts.data(), 1, MPI_INT, 0, comm);
    MPI_Gather(&sum_count, 1, MPI_INT, sum_counts.data(), 1, MPI_INT, 0, comm);
    std::vector<long long> all_joins;
    std::vector<double> all_sums;
    if (ranks.rank == 0) {
        all_joins.resize(size_t(std::accumulate(join_counts.begin(), join_counts.end(), 0)));
        all_sums.resize(size_t(std::accumulate(sum_counts.begin(), sum_counts.end(), 0)));
    }
    MPI_Gatherv(joins.data(), join_count, MPI_LONG_LONG, all_joins.data(), join_counts.data(),
                displacements(join_counts).data(), MPI_LONG_LONG, 0, comm);
    MPI_Gatherv(sums.data(), sum_count, MPI_DOUBLE, all_sums.data(), sum_counts.data(), displacements(sum_counts).data(),
                MPI_DOUBLE, 0, comm);
    // Rank 0: each label's component centroid (NaN where the component has no area).
    Components out;
    std::vector<double> centroids;
    if (ranks.rank == 0) {
        const Eigen::Index total = Eigen::Index(all_sums.size() / 4);
        std::vector<Eigen::Triplet<double>> couplings;
        couplings.reserve(all_joins.size() / 2);
        for (size_t i = 0; i < all_joins.size(); i += 2)
            couplings.emplace_back(int(all_joins[i]), int(all_joins[i + 1]), 1.0);
        SparseMatrix coupling(total, total);
        coupling.setFromTriplets(couplings.begin(), couplings.end());
        const std::vector<int> component = connected_components(coupling);
        Eigen::MatrixXd component_sums = Eigen::MatrixXd::Zero(component_count(component), 4);
        for (Eigen::Index l = 0; l < total; ++l)
            for (int k = 0; k < 4; ++k) component_sums(component[size_t(l)], k) += all_sums[size_t(4 * l + k)];
        for (Eigen::Index c = 0; c < component_sums.rows(); ++c) out.count += component_sums(c, 3) > 0;
        centroids.resize(size_t(3 * total));
        for (Eigen::Index l = 0; l < total; ++l)
            for (int k = 0; k < 3; ++k)
                centroids[size_t(3 * l + k)] = component_sums(component[size_t(l)], k) / component_sums(component[size_t(l)], 3);
    }
    MPI_Bcast(&out.count, 1, MPI_INT, 0, comm);
    std::vector<int> centroid_counts(sum_counts);
    for (int& c : centroid_counts) c = c / 4 * 3;
    std::vector<double> my_centroids(size_t(3 * labels));
    MPI_Scatterv(centroids.data(), centroid_counts.data(), displacements(centroid_counts).data(), MPI_DOUBLE,
                 my_centroids.data(), 3 * labels, MPI_DOUBLE, 0, comm);
    out.label.assign(label.begin(), label.begin() + m.owned);
    out.label_centroid = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(my_centroids.data(), labels, 3);
    return out;
}

// K (cotangent stiffness) and the lumped mass, rows in file order, each rank's rows its slice:
// each rank adds its faces' part (the core's own formula on its local mesh), PETSc moves the
// parts that belong to other ranks' rows.
void assemble(MPI_Comm comm, const LocalMesh& m, const Laplacian& local, Mat& k, Vec& mass) {
    std::vector<PetscInt> global(size_t(m.points.rows()));
    for (size_t i = 0; i < global.size(); ++i) global[i] = PetscInt(m.global(Eigen::Index(i)));
    Mat pattern;
    for (int pass = 0; pass < 2; ++pass) {
        Mat target;
        check_petsc(MatCreate(comm, &target), "assembling K");
        check_petsc(MatSetSizes(target, PetscInt(m.owned), PetscInt(m.owned), PETSC_DETERMINE, PETSC_DETERMINE), "assembling K");
        check_petsc(MatSetType(target, pass == 0 ? MATPREALLOCATOR : MATMPIAIJ), "assembling K");
        check_petsc(MatSetUp(target), "assembling K");
        if (pass == 1) check_petsc(MatPreallocatorPreallocate(pattern, PETSC_TRUE, target), "preallocating K");
        // Every row gets a stored diagonal, zero for a vertex without area, so that the pole
        // shifts (MatShift) need no new entries.
        for (long long i = 0; i < m.owned; ++i) {
            const PetscInt row = global[size_t(i)];
            const PetscScalar zero = 0;
            check_petsc(MatSetValues(target, 1, &row, 1, &row, &zero, ADD_VALUES), "assembling K");
        }
        for (Eigen::Index c = 0; c < local.stiffness.outerSize(); ++c)
            for (SparseMatrix::InnerIterator it(local.stiffness, c); it; ++it) {
                const PetscInt row = global[size_t(it.row())], col = global[size_t(c)];
                const PetscScalar value = it.value();
                check_petsc(MatSetValues(target, 1, &row, 1, &col, &value, ADD_VALUES), "assembling K");
            }
        check_petsc(MatAssemblyBegin(target, MAT_FINAL_ASSEMBLY), "assembling K");
        check_petsc(MatAssemblyEnd(target, MAT_FINAL_ASSEMBLY), "assembling K");
        if (pass == 0) pattern = target;
        else k = target;
    }
    MatDestroy(&pattern);
    check_petsc(VecCreateMPI(comm, PetscInt(m.owned), PETSC_DETERMINE, &mass), "assembling M");
    check_petsc(VecSetValues(mass, PetscInt(global.size()), global.data(), local.mass.data(), ADD_VALUES), "assembling M");
    check_petsc(VecAssemblyBegin(mass), "assembling M");
    check_petsc(VecAssemblyEnd(mass), "assembling M");
}

// Kt's rows moved to the ranks PT-Scotch assigns them (few couplings between ranks), and the
// index set of the file-order rows this rank now holds, in their new order.
struct Partitioned {
    Mat kt = nullptr;
    IS rows = nullptr;
    long coupling_entries = 0, entries = 0;
};

Partitioned partition_rows(MPI_Comm comm, Mat kt) {
    const Ranks ranks(comm);
    Partitioned out;
    Mat adjacency;
    check_petsc(MatConvert(kt, MATMPIADJ, MAT_INITIAL_MATRIX, &adjacency), "building the partition graph");
    MatPartitioning partitioner;
    check_petsc(MatPartitioningCreate(comm, &partitioner), "creating the partitioner");
    check_petsc(MatPartitioningSetAdjacency(partitioner, adjacency), "creating the partitioner");
    check_petsc(MatPartitioningSetType(partitioner, ranks.size > 1 ? MATPARTITIONINGPTSCOTCH : MATPARTITIONINGCURRENT),
                "choosing PT-Scotch");
    check_petsc(MatPartitioningSetFromOptions(partitioner), "reading the partitioner's options");
    IS target;
    check_petsc(MatPartitioningApply(partitioner, &target), "partitioning the mesh");
    MatPartitioningDestroy(&partitioner);
    MatDestroy(&adjacency);
    check_petsc(ISBuildTwoSided(target, nullptr, &out.rows), "moving the rows");
    ISDestroy(&target);
    check_petsc(ISSort(out.rows), "moving the rows");
    check_petsc(MatCreateSubMatrix(kt, out.rows, out.rows, MAT_INITIAL_MATRIX, &out.kt), "moving the rows");
    // PETSc keeps what a second extraction would reuse (this rank's rows again, every column
    // index gathered): never asked for here, and held through the factorisation otherwise.
    for (const char* kept : {"SubMatrix", "ISAllGather", "SubIScol", "isrow_d", "iscol_d", "iscol_o"})
        check_petsc(PetscObjectCompose(reinterpret_cast<PetscObject>(out.kt), kept, nullptr), "moving the rows");
    MatInfo whole, local;
    Mat diagonal_block, coupling_block;
    const PetscInt* unused = nullptr;
    check_petsc(MatGetInfo(out.kt, MAT_GLOBAL_SUM, &whole), "counting Kt's entries");
    if (ranks.size > 1) {
        check_petsc(MatMPIAIJGetSeqAIJ(out.kt, &diagonal_block, &coupling_block, &unused), "counting Kt's entries");
        check_petsc(MatGetInfo(coupling_block, MAT_LOCAL, &local), "counting Kt's entries");
        long coupling = long(local.nz_used);
        MPI_Allreduce(&coupling, &out.coupling_entries, 1, MPI_LONG, MPI_SUM, comm);
    }
    out.entries = long(whole.nz_used);
    return out;
}

// Every rank's part of one file's filter. Rank 0 passes its job and gets the output.
std::optional<RunOutput> filter_file_collectively(MPI_Comm comm, const FileJob* root_job, const EngineOptions* engine) {
    const Ranks ranks(comm);
    const auto t0 = std::chrono::steady_clock::now();
    const FileJob job = broadcast_job(comm, root_job);
    const FilterSpec& spec = *find_filter(job.preset);

    PlyLayout layout;
    LocalMesh m = read_local_mesh(comm, job, layout);
    std::optional<FeatureEllipsoid> feature;
    std::vector<std::string> selection_log;
    if (spec.parameter(param::use_selection) && job.values.at(param::use_selection) != 0) {
        const std::vector<int> selected = select_local_faces(comm, job, m, selection_log);
        feature = measure_distributed_feature(comm, m, selected);
    }
    // Lengths left to their default are fractions of the whole mesh's diagonal, as in geofilter.
    ParameterValues values = job.values;
    {
        double low[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, high[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (Eigen::Index i = 0; i < Eigen::Index(m.owned); ++i)
            for (int k = 0; k < 3; ++k) {
                low[k] = std::min(low[k], m.points(i, k));
                high[k] = std::max(high[k], m.points(i, k));
            }
        MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_DOUBLE, MPI_MIN, comm);
        MPI_Allreduce(MPI_IN_PLACE, high, 3, MPI_DOUBLE, MPI_MAX, comm);
        const double diagonal = std::sqrt((high[0] - low[0]) * (high[0] - low[0]) + (high[1] - low[1]) * (high[1] - low[1]) +
                                          (high[2] - low[2]) * (high[2] - low[2]));
        complete_lengths(spec, values, std::isfinite(diagonal) ? diagonal : 0.0);
    }
    // Every rank designs the same G from the same values and the same reduced measurement.
    RunOutput out = design_run(spec, values, feature);
    out.log.insert(out.log.begin(), selection_log.begin(), selection_log.end());
    FilterOptions options = filter_options(spec, job.values);
    detail::check_filter_options(out.transfer, options);

    // The usable faces, the core's K and M of them, summed over the ranks.
    long long counts[2] = {0, 0};  // usable faces, degenerate faces
    Triangles usable(Eigen::Index(std::count(m.usable.begin(), m.usable.end(), true)), 3);
    for (Eigen::Index f = 0, u = 0; f < m.triangles.rows(); ++f)
        if (m.usable[size_t(f)]) usable.row(u++) = m.triangles.row(f);
    counts[0] = usable.rows();
    counts[1] = m.triangles.rows() - usable.rows();
    MPI_Allreduce(MPI_IN_PLACE, counts, 2, MPI_LONG_LONG, MPI_SUM, comm);
    if (counts[0] == 0) throw Error("every face of the mesh has zero area: nothing to filter");
    Mat k = nullptr;
    Vec mass = nullptr;
    Components components;
    {  // this rank's faces' K and M, and its usable faces, are not needed past here
        const Laplacian local = cotan_laplacian(m.points, usable);
        assemble(comm, m, local, k, mass);
        components = distributed_components(comm, m, usable, local.mass);
    }
    usable.resize(0, 0);

    // Active vertices (with mass), their bounding box, and q = M^1/2 (p - centroid).
    Eigen::VectorXd owned_mass(Eigen::Index(m.owned));
    {
        const PetscScalar* values = nullptr;
        check_petsc(VecGetArrayRead(mass, &values), "reading M");
        std::copy(values, values + m.owned, owned_mass.data());
        VecRestoreArrayRead(mass, &values);
    }
    double box[6] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};  // min and -max
    long long active = 0;
    double total_mass = 0;
    Eigen::MatrixXd q = Eigen::MatrixXd::Zero(Eigen::Index(m.owned), 3);
    Eigen::VectorXd scale(Eigen::Index(m.owned));
    for (Eigen::Index i = 0; i < Eigen::Index(m.owned); ++i) {
        const double mi = owned_mass[i];
        scale[i] = mi > 0 ? 1 / std::sqrt(mi) : 0;
        if (!(mi > 0)) continue;
        ++active;
        total_mass += mi;
        for (int c = 0; c < 3; ++c) {
            box[c] = std::min(box[c], m.points(i, c));
            box[3 + c] = std::min(box[3 + c], -m.points(i, c));
            q(i, c) = std::sqrt(mi) * (m.points(i, c) - components.centroid(i)[c]);
        }
    }
    MPI_Allreduce(MPI_IN_PLACE, box, 6, MPI_DOUBLE, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, &active, 1, MPI_LONG_LONG, MPI_SUM, comm);
    MPI_Allreduce(MPI_IN_PLACE, &total_mass, 1, MPI_DOUBLE, MPI_SUM, comm);
    const double size = std::sqrt(std::pow(-box[3] - box[0], 2) + std::pow(-box[4] - box[1], 2) + std::pow(-box[5] - box[2], 2));

    // Kt = M^-1/2 K M^-1/2 (a vertex without area keeps an empty row: it stays where it is).
    Vec scale_vector;
    check_petsc(VecCreateMPIWithArray(comm, 1, PetscInt(m.owned), PETSC_DETERMINE, scale.data(), &scale_vector), "forming Kt");
    check_petsc(MatDiagonalScale(k, scale_vector, scale_vector), "forming Kt");
    VecDestroy(&scale_vector);
    scale.resize(0);
    // Nothing of the mesh is held through the factorisation, where every rank's memory peaks:
    // the records are read again for the output.
    m.vertex_records = {};
    m.face_slice = {};
    m.triangles.resize(0, 0);
    m.usable = {};
    m.points.resize(0, 0);
    VecDestroy(&mass);
    check_petsc(MatSetOption(k, MAT_SYMMETRIC, PETSC_TRUE), "marking Kt symmetric");
    Partitioned parts = partition_rows(comm, k);
    MatDestroy(&k);
    check_petsc(MatSetOption(parts.kt, MAT_SYMMETRIC, PETSC_TRUE), "marking Kt symmetric");
    check_petsc(MatSetOption(parts.kt, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "marking Kt symmetric");

    // q into the partition's order, column by column.
    PetscInt new_rows = 0;
    check_petsc(ISGetLocalSize(parts.rows, &new_rows), "moving q");
    Eigen::MatrixXd q_moved(new_rows, 3);
    Vec file_order, partition_order;
    VecScatter move;
    check_petsc(VecCreateMPIWithArray(comm, 1, PetscInt(m.owned), PETSC_DETERMINE, nullptr, &file_order), "moving q");
    check_petsc(VecCreateMPIWithArray(comm, 1, new_rows, PETSC_DETERMINE, nullptr, &partition_order), "moving q");
    check_petsc(VecScatterCreate(file_order, parts.rows, partition_order, nullptr, &move), "moving q");
    auto scatter = [&](Eigen::MatrixXd& from, Eigen::MatrixXd& to, ScatterMode mode) {
        Vec source = mode == SCATTER_FORWARD ? file_order : partition_order;
        Vec target = mode == SCATTER_FORWARD ? partition_order : file_order;
        for (int c = 0; c < 3; ++c) {
            check_petsc(VecPlaceArray(source, from.col(c).data()), "moving q");
            check_petsc(VecPlaceArray(target, to.col(c).data()), "moving q");
            check_petsc(VecScatterBegin(move, source, target, INSERT_VALUES, mode), "moving q");
            check_petsc(VecScatterEnd(move, source, target, INSERT_VALUES, mode), "moving q");
            VecResetArray(source);
            VecResetArray(target);
        }
    };
    scatter(q, q_moved, SCATTER_FORWARD);
    q.resize(0, 0);
    // Under Open MPI what the process frees stays its own unless given back (as on the rank-0 path).
    malloc_trim(0);
    out.report.seconds_assembly = seconds_since(t0);

    DistributedProblem problem;
    problem.pole_solver = job.pole_solver;
    problem.vertices = PetscInt(m.vertices);
    problem.allowed_error = options.tolerance * size * std::sqrt(total_mass);
    problem.max_iterations = options.max_iterations;
    problem.g = out.transfer;
    std::string factor_note;
    Eigen::MatrixXd solved_moved;
    try {
        solved_moved = filter_rows(comm, parts.kt, q_moved, problem, out.report, &factor_note);
    } catch (...) {
        ISDestroy(&parts.rows);
        VecScatterDestroy(&move);
        VecDestroy(&file_order);
        VecDestroy(&partition_order);
        throw;
    }
    Eigen::MatrixXd solved(Eigen::Index(m.owned), 3);
    scatter(solved_moved, solved, SCATTER_REVERSE);
    ISDestroy(&parts.rows);
    VecScatterDestroy(&move);
    VecDestroy(&file_order);
    VecDestroy(&partition_order);

    // Back out of the q frame, about each component's centroid; vertices without area stay.
    read_slices(comm, job, layout, m);
    for (Eigen::Index i = 0; i < Eigen::Index(m.owned); ++i)
        if (owned_mass[i] > 0) solved.row(i) = solved.row(i) / std::sqrt(owned_mass[i]) + components.centroid(i);
        else solved.row(i) = position_in_record(layout, m.vertex_records.data() + i * layout.vertex_stride).transpose();
    int finite = solved.allFinite() ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &finite, 1, MPI_INT, MPI_MIN, comm);
    if (!finite) throw Error("the filtered coordinates are not finite: the transfer function amplifies this mesh too much");

    // The input's vertex normals describe the unfiltered shape: recomputed as geofilter does
    // (area-weighted, over every face), each rank adding its faces' part to its ghosts' owners.
    Eigen::MatrixXd normals;
    if (layout.has_normals) {
        number_faces_locally(m);
        Eigen::MatrixXd filtered(Eigen::Index(m.owned + long(m.ghosts.size())), 3);
        filtered.topRows(solved.rows()) = solved;
        filtered.bottomRows(Eigen::Index(m.ghosts.size())) = ghost_rows(comm, m, solved);
        Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(filtered.rows(), 3);
        for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
            const Eigen::RowVector3d a = filtered.row(m.triangles(f, 0)), b = filtered.row(m.triangles(f, 1)),
                                     c = filtered.row(m.triangles(f, 2));
            const Eigen::RowVector3d n = (b - a).cross(c - a);
            for (int k = 0; k < 3; ++k) sums.row(m.triangles(f, k)) += n;
        }
        add_ghost_rows_to_owners(comm, m, sums);
        normals = sums.topRows(solved.rows());
        for (Eigen::Index i = 0; i < normals.rows(); ++i)
            if (normals.row(i).norm() > 0) normals.row(i).normalize();
    }

    // Each rank writes its slice of the vertices and copies its slice of the faces.
    const std::string header = layout.output_header();
    const long long vertex_stride = layout.output_vertex_stride();
    const std::vector<char> records = output_vertex_records(layout, m.vertex_records, solved, normals);
    m.vertex_records = {};
    MPI_File file;
    int code = MPI_File_open(comm, job.output.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL, &file);
    MPI_Allreduce(MPI_IN_PLACE, &code, 1, MPI_INT, MPI_MAX, comm);
    if (code != MPI_SUCCESS) throw Error("cannot write '" + job.output + "'");
    const long long total_bytes = long(header.size()) + m.vertices * vertex_stride + m.faces * layout.face_stride();
    int failed = MPI_File_set_size(file, total_bytes) != MPI_SUCCESS;
    auto write = [&](long long offset, const char* data, long long bytes) {
        for (long long done = 0; done < bytes && !failed;) {
            const int piece = int(std::min<long long>(bytes - done, 1 << 30));
            failed |= MPI_File_write_at(file, offset + done, data + done, piece, MPI_BYTE, MPI_STATUS_IGNORE) != MPI_SUCCESS;
            done += piece;
        }
    };
    if (ranks.rank == 0) write(0, header.data(), long(header.size()));
    write(long(header.size()) + m.first_vertex * vertex_stride, records.data(), long(records.size()));
    write(long(header.size()) + m.vertices * vertex_stride + m.first_face * layout.face_stride(), m.face_slice.records.data(),
          long(m.face_slice.records.size()));
    failed |= MPI_File_close(&file) != MPI_SUCCESS;
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, comm);
    if (failed) throw Error("cannot write '" + job.output + "': the disk may be full");

    out.report.active_vertices = int(active);
    out.report.components = components.count;
    if (counts[1] > 0)
        out.report.warnings.push_back(std::to_string(counts[1]) + " zero-area face(s) skipped: their cotangent weights are undefined");
    if (active < m.vertices)
        out.report.warnings.push_back(std::to_string(m.vertices - active) +
                                      " vertex/vertices belong to no usable face and were left where they are");
    out.report.seconds_total = seconds_since(t0);
    if (ranks.rank != 0) return std::nullopt;
    std::vector<std::string> lines = {
        "read by slices: each of the " + std::to_string(ranks.size) + " rank(s) read, checked and assembled its share of the " +
        std::to_string(m.vertices) + " vertices and " + std::to_string(m.faces) +
        " faces, and wrote its share of the result (vertex positions as double" +
        (layout.has_normals ? ", normals recomputed" : "") + "; exactly duplicated vertices are not looked for)"};
    std::string line = "distributed over " + std::to_string(ranks.size) + " rank(s)" +
                       (ranks.size > 1 ? " (PT-Scotch partition)" : "") + ": " +
                       format_number(100.0 * double(parts.coupling_entries) / double(std::max(parts.entries, 1L)), 3) +
                       "% of Kt's entries couple ranks" + factor_note;
    lines.push_back(line);
    if (engine && engine->log) engine->log->insert(engine->log->end(), lines.begin(), lines.end());
    log_filter_report(out, options);
    return out;
}

} // namespace

std::optional<RunOutput> filter_file_on_all_ranks(MPI_Comm comm, const cli::CliOptions& o, const ParameterValues& values,
                                                  const std::string& output, const EngineOptions& engine,
                                                  std::vector<std::string>& log) {
    const FilterSpec& spec = *o.preset;
    auto whole_mesh = [&](const std::string& why) {
        log.push_back("rank 0 reads the whole mesh: " + why);
        return std::optional<RunOutput>{};
    };
    if (spec.kind == FilterKind::Denoise) return whole_mesh("Denoise works on the whole mesh (its noise estimate, volume and bump pattern)");
    const bool has_feature = spec.parameter(param::use_selection) && values.at(param::use_selection) != 0;
    const std::optional<Operator> op = operator_from_values(spec, values, has_feature);
    if (!op || *op != Operator::Cotangent) return whole_mesh("the operator is not the cotangent Laplacian");
    if (spec.parameter(param::fix_boundary) && values.at(param::fix_boundary) != 0)
        return whole_mesh("--fix-boundary needs the whole boundary");
    if (o.select_stored) return whole_mesh("--select-stored reads the selection with the mesh");
    if (output.empty() || o.output.size() < 4 || (o.output.substr(o.output.size() - 4) != ".ply" && o.output.substr(o.output.size() - 4) != ".PLY"))
        return whole_mesh("the output is not a PLY file");
    std::string why_not;
    if (!slice_layout(o.input, why_not)) return whole_mesh(why_not);

    FileJob job;
    job.preset = spec.cli_name;
    job.input = o.input;
    job.output = output;
    job.values = values;
    job.spheres = o.spheres;
    job.boxes = o.boxes;
    job.pole_solver = engine.pole_solver;
    start_file_filter(comm);
    return filter_file_collectively(comm, &job, &engine);
}

void serve_file_filter(MPI_Comm comm) { filter_file_collectively(comm, nullptr, nullptr); }

} // namespace geofilter::mpi
