#include "ply_slices.h"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace geofilter::mpi {

namespace {

// Bytes of a PLY scalar type, 0 if the name is not one.
int type_bytes(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

bool is_signed(const std::string& t) { return t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32"; }

std::string io_error(const std::string& path) { return "cannot read '" + path + "': " + std::strerror(errno); }

std::vector<char> read_bytes(const std::string& path, long long offset, long long size) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(io_error(path));
    std::vector<char> bytes(static_cast<size_t>(size));
    in.seekg(offset);
    in.read(bytes.data(), std::streamsize(size));
    if (!in) throw Error("cannot read '" + path + "': it ends before its header says");
    return bytes;
}

long long integer_at(const char* p, long long bytes, bool is_signed_type) {
    switch (bytes) {
    case 1: return is_signed_type ? (long long)int8_t(p[0]) : (long long)uint8_t(p[0]);
    case 2: { int16_t s; uint16_t u; std::memcpy(&s, p, 2); std::memcpy(&u, p, 2); return is_signed_type ? s : u; }
    default: { int32_t s; uint32_t u; std::memcpy(&s, p, 4); std::memcpy(&u, p, 4); return is_signed_type ? s : u; }
    }
}

} // namespace

long long PlyLayout::output_vertex_stride() const {
    long long stride = 3 * 8 + (has_normals ? 3 * 4 : 0);
    for (const auto& [offset, size] : carried_bytes) stride += size;
    return stride;
}

std::string PlyLayout::output_header() const {
    std::string h = "ply\nformat binary_little_endian 1.0\ncomment written by geofilter-mpi\n";
    h += "element vertex " + std::to_string(vertex_count) + "\nproperty double x\nproperty double y\nproperty double z\n";
    if (has_normals) h += "property float nx\nproperty float ny\nproperty float nz\n";
    for (const auto& line : carried_lines) h += line + "\n";
    h += face_header + "end_header\n";
    return h;
}

std::optional<PlyLayout> slice_layout(const std::string& path, std::string& why_not) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        why_not = "the input cannot be opened here";
        return std::nullopt;
    }
    std::string line;
    std::getline(in, line);
    if (line != "ply" && line != "ply\r") {
        why_not = "the input is not a PLY file";
        return std::nullopt;
    }
    PlyLayout layout;
    struct Element {
        std::string name;
        long long count = 0;
        std::vector<std::string> lines;
        std::vector<std::vector<std::string>> properties;
    };
    std::vector<Element> elements;
    std::string format;
    bool ended = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') {
            why_not = "the header has CR-LF line ends";
            return std::nullopt;
        }
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string word; words >> word;) w.push_back(word);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "end_header") {
            ended = true;
            break;
        }
        if (w[0] == "format" && w.size() >= 2) format = w[1];
        else if (w[0] == "element" && w.size() == 3) elements.push_back({w[1], std::atoll(w[2].c_str()), {line}, {}});
        else if (w[0] == "property" && !elements.empty()) {
            elements.back().lines.push_back(line);
            elements.back().properties.push_back(std::vector<std::string>(w.begin() + 1, w.end()));
        }
    }
    if (!ended) {
        why_not = "the input's PLY header has no end";
        return std::nullopt;
    }
    layout.header_bytes = static_cast<long long>(in.tellg());
    if (format != "binary_little_endian") {
        why_not = "the input is " + (format.empty() ? std::string("PLY of no format") : format + " PLY") +
                  ", not binary little-endian";
        return std::nullopt;
    }
    if (elements.size() != 2 || elements[0].name != "vertex" || elements[1].name != "face") {
        why_not = "the input holds other elements than vertices then faces";
        return std::nullopt;
    }
    const Element& vertices = elements[0];
    const Element& faces = elements[1];
    layout.vertex_count = vertices.count;
    layout.face_count = faces.count;
    if (layout.vertex_count <= 0 || layout.face_count <= 0) {
        why_not = "the input has no vertices or no faces";
        return std::nullopt;
    }
    int found = 0;
    std::string position_type;
    for (size_t i = 0; i < vertices.properties.size(); ++i) {
        const auto& p = vertices.properties[i];
        const int bytes = p.size() == 2 ? type_bytes(p[0]) : 0;
        if (bytes == 0) {
            why_not = "a vertex property is a list or of an unknown type";
            return std::nullopt;
        }
        const std::string& name = p[1];
        const int axis = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
        if (axis >= 0) {
            if (position_type.empty()) position_type = p[0];
            if (p[0] != position_type || (bytes != 4 && bytes != 8) || (p[0] != "float" && p[0] != "float32" && bytes == 4)) {
                why_not = "the vertex positions are not all float or all double";
                return std::nullopt;
            }
            layout.position_offset[axis] = layout.vertex_stride;
            ++found;
        } else if (name == "nx" || name == "ny" || name == "nz") {
            layout.has_normals = true;
        } else {
            layout.carried_lines.push_back(vertices.lines[i + 1]);
            layout.carried_bytes.emplace_back(layout.vertex_stride, bytes);
        }
        layout.vertex_stride += bytes;
    }
    if (found != 3) {
        why_not = "the vertices lack x, y or z";
        return std::nullopt;
    }
    layout.double_positions = type_bytes(position_type) == 8;
    if (faces.properties.size() != 1 || faces.properties[0].size() != 4 || faces.properties[0][0] != "list") {
        why_not = "the faces hold more than their corner list";
        return std::nullopt;
    }
    const auto& list = faces.properties[0];
    layout.count_bytes = type_bytes(list[1]);
    layout.index_bytes = type_bytes(list[2]);
    layout.signed_count = is_signed(list[1]);
    layout.signed_index = is_signed(list[2]);
    if (layout.count_bytes == 0 || layout.count_bytes > 4 || layout.index_bytes == 0 || layout.index_bytes > 4 ||
        list[2] == "float" || list[2] == "float32" || list[1] == "float" || list[1] == "float32") {
        why_not = "the corner list's types are not integers";
        return std::nullopt;
    }
    for (const auto& l : faces.lines) layout.face_header += l + "\n";
    struct stat st {};
    if (stat(path.c_str(), &st) != 0 ||
        static_cast<long long>(st.st_size) != layout.faces_offset() + layout.face_count * layout.face_stride()) {
        why_not = "the file's size is not that of triangles only (polygons, or trailing data)";
        return std::nullopt;
    }
    return layout;
}

std::vector<char> read_vertex_records(const std::string& path, const PlyLayout& layout, long long first, long long count) {
    return read_bytes(path, layout.header_bytes + first * layout.vertex_stride, count * layout.vertex_stride);
}

Eigen::Vector3d position_in_record(const PlyLayout& layout, const char* record) {
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k) {
        if (layout.double_positions) {
            double v;
            std::memcpy(&v, record + layout.position_offset[k], 8);
            p[k] = v;
        } else {
            float v;
            std::memcpy(&v, record + layout.position_offset[k], 4);
            p[k] = v;
        }
    }
    return p;
}

FaceSlice read_face_records(const std::string& path, const PlyLayout& layout, long long first, long long count) {
    FaceSlice slice;
    slice.records = read_bytes(path, layout.faces_offset() + first * layout.face_stride(), count * layout.face_stride());
    slice.corners.resize(static_cast<size_t>(3 * count));
    for (long long f = 0; f < count; ++f) {
        const char* record = slice.records.data() + f * layout.face_stride();
        const long long corners = integer_at(record, layout.count_bytes, layout.signed_count);
        if (corners != 3)
            throw Error("face " + std::to_string(first + f) + " has " + std::to_string(corners) +
                        " corners: GeoFilter filters triangle meshes (MeshLab: Polygonal and Quad Mesh > Triangulate)");
        for (int k = 0; k < 3; ++k)
            slice.corners[size_t(3 * f + k)] =
                integer_at(record + layout.count_bytes + k * layout.index_bytes, layout.index_bytes, layout.signed_index);
    }
    return slice;
}

std::vector<char> output_vertex_records(const PlyLayout& layout, const std::vector<char>& input_records,
                                        const Eigen::MatrixXd& positions, const Eigen::MatrixXd& normals) {
    const long long stride = layout.output_vertex_stride();
    std::vector<char> out(static_cast<size_t>(stride * positions.rows()));
    for (Eigen::Index i = 0; i < positions.rows(); ++i) {
        char* record = out.data() + i * stride;
        for (int k = 0; k < 3; ++k) {
            const double v = positions(i, k);
            std::memcpy(record + 8 * k, &v, 8);
        }
        long long at = 24;
        if (layout.has_normals)
            for (int k = 0; k < 3; ++k, at += 4) {
                const float v = float(normals(i, k));
                std::memcpy(record + at, &v, 4);
            }
        const char* source = input_records.data() + i * layout.vertex_stride;
        for (const auto& [offset, size] : layout.carried_bytes) {
            std::memcpy(record + at, source + offset, size_t(size));
            at += size;
        }
    }
    return out;
}

} // namespace geofilter::mpi
