#include "fuzz_core_input.h"

#include "run_filter.h"
#include "shapes.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <vector>

namespace geofilter::fuzz {

namespace {

// A byte reader that never fails: past the end it yields zeros.
class Bytes {
public:
    Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
    uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
    int integer(int lo, int hi) {
        if (hi <= lo) return lo;
        return lo + static_cast<int>((byte() | (byte() << 8)) % static_cast<unsigned>(hi - lo + 1));
    }
    // Mostly tame numbers, sometimes the values that break naive code.
    double number(double scale) {
        switch (byte() % 16) {
        case 0: return std::numeric_limits<double>::quiet_NaN();
        case 1: return std::numeric_limits<double>::infinity();
        case 2: return -std::numeric_limits<double>::infinity();
        case 3: return 0.0;
        case 4: return -1.0;
        case 5: return 1e300;
        case 6: return 1e-300;
        default: return scale * (integer(-1000, 1000) / 100.0);
        }
    }

private:
    const uint8_t* data_;
    size_t size_;
    size_t pos_ = 0;
};

// memcmp of n bytes; an empty matrix may have a null data pointer, which memcmp must not see.
bool same_bytes(const void* a, const void* b, size_t n) { return n == 0 || std::memcmp(a, b, n) == 0; }

[[noreturn]] void fail(const char* what) {
    std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
    std::abort();
}

} // namespace

void run_core_on_bytes(const uint8_t* data, size_t size) {
    Bytes in(data, size);
    const auto& table = filter_table();
    const FilterSpec& spec = table[static_cast<size_t>(in.byte()) % table.size()];

    // Start from a real surface (so that most inputs reach the solvers) and damage it.
    Mesh mesh;
    switch (in.byte() % 4) {
    case 0: mesh = icosphere(in.integer(0, 2), 1.0); break;
    case 1: mesh = grid(in.integer(1, 8), 1.0); break;
    case 2: mesh = cylinder(in.integer(1, 6), in.integer(3, 10), 0.5, 1.0); break;
    default: mesh = torus(in.integer(3, 10), in.integer(3, 8), 1.0, 0.3); break;
    }
    const double scale = std::pow(10.0, in.integer(-6, 6));
    mesh.points *= scale;
    for (int edits = in.integer(0, 12); edits > 0 && mesh.triangles.rows() > 0; --edits) {
        switch (in.byte() % 4) {
        case 0: mesh.points(in.integer(0, int(mesh.points.rows()) - 1), in.byte() % 3) = in.number(scale); break;
        case 1: mesh.triangles(in.integer(0, int(mesh.triangles.rows()) - 1), in.byte() % 3) =
                    in.integer(-2, int(mesh.points.rows()) + 2);
                break;
        case 2: {  // collapse a face onto one vertex
            const int f = in.integer(0, int(mesh.triangles.rows()) - 1);
            mesh.triangles(f, 1) = mesh.triangles(f, 0);
            break;
        }
        default: mesh.triangles.conservativeResize(in.integer(0, int(mesh.triangles.rows())), 3); break;
        }
    }
    std::vector<int> selected;
    for (int k = in.integer(0, 6); k > 0; --k) selected.push_back(in.integer(-1, int(mesh.triangles.rows())));

    ParameterValues values = default_values(spec, !selected.empty());
    for (const ParameterSpec& p : spec.parameters) {
        if (in.byte() % 3 != 0) continue;  // keep most defaults: they reach deeper
        switch (p.type) {
        case ParameterType::Float: values[p.name] = in.number(p.default_value != 0 ? p.default_value : 1.0); break;
        case ParameterType::Length: values[p.name] = in.number(p.default_value != 0 ? p.default_value : 0.05); break;
        case ParameterType::Bool: values[p.name] = in.byte() % 2; break;
        case ParameterType::Int: values[p.name] = in.integer(-5, 400); break;
        case ParameterType::Enum: values[p.name] = in.integer(-1, int(p.choices.size())); break;
        }
    }
    // Bounded work per input.
    values[param::max_iterations] = std::min(values[param::max_iterations], 300.0);

    // Copies taken before the call, compared bit for bit after it (memcmp, so that a NaN
    // rewritten with another payload, or -0 for 0, counts as a change): the core must never
    // write through its input, whatever it refuses or computes.
    const Points points_before = mesh.points;
    const Triangles triangles_before = mesh.triangles;
    const std::vector<int> selected_before = selected;
    try {
        const RunOutput out = run_filter(spec, values, {mesh.points, mesh.triangles, selected, {}});
        if (spec.kind != FilterKind::Measure) {
            if (out.points.rows() != mesh.points.rows()) fail("output has another vertex count");
            if (!out.points.allFinite()) fail("output has non-finite coordinates");
        }
    } catch (const Error&) {
        // A refusal: fine, as long as it left the input alone (checked below).
    }
    if (mesh.points.rows() != points_before.rows() ||
        !same_bytes(points_before.data(), mesh.points.data(), sizeof(double) * size_t(points_before.size())))
        fail("the input vertex coordinates were modified");
    if (mesh.triangles.rows() != triangles_before.rows() ||
        !same_bytes(triangles_before.data(), mesh.triangles.data(), sizeof(int) * size_t(triangles_before.size())))
        fail("the input faces were modified");
    if (selected != selected_before) fail("the input selection was modified");
}

} // namespace geofilter::fuzz
