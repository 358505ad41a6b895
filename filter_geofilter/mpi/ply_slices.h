// Binary PLY files read and written by slices: each rank reads the vertex and face records
// of its share at their offsets, and writes its share of the result at its own, so that no
// rank holds more of the mesh than its share.
#pragma once

#include "core/types.h"

#include <optional>
#include <string>
#include <vector>

namespace geofilter::mpi {

// A binary little-endian PLY of one vertex element of scalar properties, x, y and z among
// them, then one face element holding only a list of int or uint corners: records of fixed
// size, so that record i lies at a known offset.
struct PlyLayout {
    long long header_bytes = 0;
    long long vertex_count = 0, face_count = 0;
    long long vertex_stride = 0;
    long long position_offset[3] = {0, 0, 0};
    bool double_positions = false;
    long long count_bytes = 1, index_bytes = 4;
    bool signed_count = false, signed_index = true;
    std::string face_header;  // the face element's lines, written back as they were
    // Vertex properties other than x, y, z and the normals (which the filter makes stale:
    // written recomputed), copied to the output as they were: name lines and byte ranges.
    std::vector<std::string> carried_lines;
    std::vector<std::pair<long long, long long>> carried_bytes;  // offset, size
    bool has_normals = false;

    long long face_stride() const { return count_bytes + 3 * index_bytes; }
    long long faces_offset() const { return header_bytes + vertex_count * vertex_stride; }
    long long output_vertex_stride() const;
    std::string output_header() const;
};

// The layout of `path`, or nothing with the reason in `why_not` (another encoding, other
// elements, polygons that make the file's size disagree with fixed records, ...).
std::optional<PlyLayout> slice_layout(const std::string& path, std::string& why_not);

// Records [first, first + count) of `path`'s vertices: raw bytes. Throws Error.
std::vector<char> read_vertex_records(const std::string& path, const PlyLayout& layout, long long first, long long count);
Eigen::Vector3d position_in_record(const PlyLayout& layout, const char* record);

// Faces [first, first + count): raw records and their corners. Throws Error naming the face
// that is not a triangle or names a negative vertex.
struct FaceSlice {
    std::vector<char> records;
    std::vector<long long> corners;  // 3 per face
};
FaceSlice read_face_records(const std::string& path, const PlyLayout& layout, long long first, long long count);

// This slice's output vertex records: x, y, z as double, the normals as float if the input
// had normals, then the carried properties.
std::vector<char> output_vertex_records(const PlyLayout& layout, const std::vector<char>& input_records,
                                        const Eigen::MatrixXd& positions, const Eigen::MatrixXd& normals);

} // namespace geofilter::mpi
