#include "mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <unordered_map>

// Why these readers and writers are our own rather than a library's (docs/architecture.md,
// "Mesh files"): the tool must read and write PLY, OBJ, OFF and STL without MeshLab's
// sources, keep every face (non-manifold ones too) and the vertex order, read MeshLab's PLY
// face flags and vertex quality, weld STL corners, and refuse a broken file with a reason.
// Of Debian's libraries, CGAL 5.5's polygon-soup readers keep faces and order, but its PLY
// soup reader drops custom properties (flags, quality), its OBJ reader accepts an index one
// past the last vertex and gives no reason for a refusal; OpenMesh drops non-manifold faces;
// assimp splits and merges vertices. What is left is small enough to own and to fuzz
// (tests/fuzz/fuzz_mesh_readers.cpp).

namespace geofilter::cli {

namespace {

constexpr int kSelectedFlag = 0x20;  // vcglib's selection bit, as MeshLab stores face flags

MeshFormat require_format(const std::string& path) {
    const auto format = format_of(path);
    if (!format) throw Error("cannot tell the format of '" + path + "': use " + supported_formats());
    return *format;
}

std::string read_whole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read '" + path + "': no such file or no permission");
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.empty()) throw Error("cannot read '" + path + "': the file is empty or not a regular file");
    return bytes;
}

// Splits `text` into lines without '\r', with everything from `comment` on removed.
std::vector<std::string> lines_of(const std::string& text, char comment) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (comment) {
            const size_t c = line.find(comment);
            if (c != std::string::npos) line.erase(c);
        }
        if (!line.empty() && line.back() == '\r') line.pop_back();
        lines.push_back(line);
    }
    return lines;
}

bool blank(const std::string& line) {
    return std::all_of(line.begin(), line.end(), [](unsigned char c) { return std::isspace(c); });
}

std::string full_precision(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.17g", v);
    return buffer;
}

// Area-weighted vertex normals (unit; zero where no face has area), for the formats that
// store normals: the ones read with the input describe the shape before filtering.
Points vertex_normals(const Points& p, const Triangles& t) {
    Points n = Points::Zero(p.rows(), 3);
    for (Eigen::Index f = 0; f < t.rows(); ++f) {
        const Eigen::RowVector3d a = p.row(t(f, 0)), b = p.row(t(f, 1)), c = p.row(t(f, 2));
        const Eigen::RowVector3d fn = (b - a).cross(c - a);
        for (int k = 0; k < 3; ++k) n.row(t(f, k)) += fn;
    }
    for (Eigen::Index i = 0; i < n.rows(); ++i)
        if (n.row(i).norm() > 0) n.row(i).normalize();
    return n;
}

Eigen::RowVector3d face_normal(const Points& p, const Triangles& t, Eigen::Index f) {
    const Eigen::RowVector3d a = p.row(t(f, 0)), b = p.row(t(f, 1)), c = p.row(t(f, 2));
    const Eigen::RowVector3d n = (b - a).cross(c - a);
    return n.norm() > 0 ? Eigen::RowVector3d(n.normalized()) : n;
}

// Corners of polygons as triangles: a fan from each polygon's first corner. `source_face`
// tells, per triangle, which polygon of the file it came from (its attributes follow it).
struct FaceList {
    std::vector<std::array<int, 3>> triangles;
    std::vector<size_t> source_face;
    size_t polygons = 0, too_small = 0;

    void add(const std::vector<long>& corners, size_t face) {
        if (corners.size() < 3) {
            ++too_small;
            return;
        }
        if (corners.size() > 3) ++polygons;
        for (size_t k = 1; k + 1 < corners.size(); ++k) {
            triangles.push_back({int(corners[0]), int(corners[k]), int(corners[k + 1])});
            source_face.push_back(face);
        }
    }
};

// ---------------------------------------------------------------------------------------------
// PLY

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

std::optional<PlyType> ply_type(const std::string& name) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},      {"uchar", PlyType::Uint8},   {"uint8", PlyType::Uint8},
        {"short", PlyType::Int16},   {"int16", PlyType::Int16},    {"ushort", PlyType::Uint16}, {"uint16", PlyType::Uint16},
        {"int", PlyType::Int32},     {"int32", PlyType::Int32},    {"uint", PlyType::Uint32},   {"uint32", PlyType::Uint32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64}, {"float64", PlyType::Float64}};
    for (const auto& [n, t] : names)
        if (name == n) return t;
    return std::nullopt;
}

const char* ply_type_name(PlyType t) {
    static const char* names[] = {"char", "uchar", "short", "ushort", "int", "uint", "float", "double"};
    return names[int(t)];
}

size_t ply_size(PlyType t) {
    static const size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[int(t)];
}

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool is_list = false;
    PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
    std::string name;
    size_t count = 0;
    std::vector<PlyProperty> properties;
};

enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

[[noreturn]] void ply_fail(const std::string& path, const std::string& why) {
    throw Error("cannot read '" + path + "' as PLY: " + why);
}

// Values in the order the file holds them; every PLY scalar is exact as a double.
class PlyBody {
public:
    PlyBody(const std::string& bytes, size_t start, PlyEncoding encoding, const std::string& path)
        : bytes_(bytes), pos_(start), encoding_(encoding), path_(path) {}

    double scalar(PlyType t) {
        if (encoding_ == PlyEncoding::Ascii) return ascii_number();
        const size_t n = ply_size(t);
        if (bytes_.size() - pos_ < n) fail("the file ends before its last element");
        unsigned char raw[8];
        std::memcpy(raw, bytes_.data() + pos_, n);
        pos_ += n;
        if (encoding_ == PlyEncoding::BinaryBig) std::reverse(raw, raw + n);
        switch (t) {
        case PlyType::Int8: return double(int8_t(raw[0]));
        case PlyType::Uint8: return double(raw[0]);
        case PlyType::Int16: { int16_t v; std::memcpy(&v, raw, 2); return v; }
        case PlyType::Uint16: { uint16_t v; std::memcpy(&v, raw, 2); return v; }
        case PlyType::Int32: { int32_t v; std::memcpy(&v, raw, 4); return v; }
        case PlyType::Uint32: { uint32_t v; std::memcpy(&v, raw, 4); return v; }
        case PlyType::Float32: { float v; std::memcpy(&v, raw, 4); return v; }
        case PlyType::Float64: { double v; std::memcpy(&v, raw, 8); return v; }
        }
        return 0;
    }

    // The smallest number of bytes one item of `e` can take: a count that cannot fit in
    // what is left of the file is refused before anything is allocated for it.
    size_t min_item_bytes(const PlyElement& e) const {
        size_t n = 0;
        for (const auto& p : e.properties)
            n += encoding_ == PlyEncoding::Ascii ? 1 : ply_size(p.is_list ? p.count_type : p.type);
        return n;
    }
    size_t remaining() const { return bytes_.size() - pos_; }

    [[noreturn]] void fail(const std::string& why) const { ply_fail(path_, why); }

private:
    double ascii_number() {
        while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
        const size_t start = pos_;
        while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
        if (start == pos_) fail("the file ends before its last element");
        const std::string word = bytes_.substr(start, pos_ - start);
        char* end = nullptr;
        const double v = std::strtod(word.c_str(), &end);
        if (*end != '\0') fail("'" + word + "' is not a number");
        return v;
    }

    const std::string& bytes_;
    size_t pos_;
    PlyEncoding encoding_;
    const std::string& path_;
};

// An ASCII PLY may hold any number where an integer type is declared: out of range (or
// NaN) must not reach a cast, whose result would be undefined.
template <typename Int>
Int clamped(double v) {
    if (!(v == v)) return 0;
    return Int(std::clamp(v, double(std::numeric_limits<Int>::min()), double(std::numeric_limits<Int>::max())));
}

int property_index(const PlyElement& e, const std::string& name) {
    for (size_t i = 0; i < e.properties.size(); ++i)
        if (e.properties[i].name == name) return int(i);
    return -1;
}

} // namespace

// What a PLY element carries besides what the tool computes (positions, indices, normals,
// flags), written back with the type it was read with: colours, quality, texture
// coordinates, anything a scanner added.
struct CarriedColumns {
    std::vector<PlyProperty> properties;
    std::vector<std::vector<double>> values;  // per property, per item
};

// Everything a read file gives the tool (MeshFile::Data, visible to the readers below).
struct FileContents {
    MeshFormat format = MeshFormat::Ply;
    Points points;
    Triangles triangles;
    bool has_stored_flags = false;
    std::vector<int> stored_selection;
    std::vector<double> vertex_quality;
    std::vector<std::string> notes;
    // Written back only in the format that was read.
    bool vertex_normals = false, face_normals = false;
    CarriedColumns vertex_columns, face_columns;        // PLY
    std::string off_keyword = "OFF";                     // OFF: which optional fields
    std::vector<std::string> vertex_tail, face_tail;     // OFF: colours, texture coordinates
};

struct MeshFile::Data : FileContents {};

namespace {

using Data = FileContents;

void check_indices(const FaceList& faces, size_t vertices, const std::string& what) {
    for (size_t t = 0; t < faces.triangles.size(); ++t)
        for (int v : faces.triangles[t])
            if (v < 0 || size_t(v) >= vertices)
                throw Error(what + ": face " + std::to_string(faces.source_face[t]) + " uses vertex " + std::to_string(v) +
                            " of " + std::to_string(vertices));
}

void store_faces(Data& d, const FaceList& faces, const std::string& format_label) {
    d.triangles.resize(Eigen::Index(faces.triangles.size()), 3);
    for (size_t t = 0; t < faces.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) d.triangles(Eigen::Index(t), k) = faces.triangles[t][size_t(k)];
    if (faces.polygons > 0)
        d.notes.push_back("the file has polygons: " + std::to_string(faces.polygons) + " of its " + format_label +
                          " faces were split into triangles (a fan from each one's first corner), and triangles are written");
    if (faces.too_small > 0)
        d.notes.push_back("skipped " + std::to_string(faces.too_small) + " faces with fewer than three corners");
}

void read_ply(Data& d, const std::string& path, const std::string& bytes) {
    const auto fail = [&](const std::string& why) { ply_fail(path, why); };
    const size_t end_header = bytes.find("end_header");
    if (bytes.compare(0, 3, "ply") != 0 || end_header == std::string::npos) fail("no 'ply' ... 'end_header' header");
    const size_t body_start = bytes.find('\n', end_header);
    if (body_start == std::string::npos) fail("nothing after 'end_header'");
    std::optional<PlyEncoding> encoding;
    std::vector<PlyElement> elements;
    for (const std::string& line : lines_of(bytes.substr(0, end_header), 0)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "format") {
            std::string name;
            words >> name;
            if (name == "ascii") encoding = PlyEncoding::Ascii;
            else if (name == "binary_little_endian") encoding = PlyEncoding::BinaryLittle;
            else if (name == "binary_big_endian") encoding = PlyEncoding::BinaryBig;
            else fail("unknown format '" + name + "'");
        } else if (keyword == "element") {
            PlyElement e;
            long long count = -1;
            if (!(words >> e.name >> count) || count < 0) fail("bad line '" + line + "'");
            e.count = size_t(count);
            elements.push_back(e);
        } else if (keyword == "property") {
            if (elements.empty()) fail("a property before any element");
            PlyProperty p;
            std::string type;
            words >> type;
            if (type == "list") {
                std::string count_type;
                words >> count_type >> type;
                const auto ct = ply_type(count_type);
                if (!ct || *ct == PlyType::Float32 || *ct == PlyType::Float64) fail("bad list count type in '" + line + "'");
                p.is_list = true;
                p.count_type = *ct;
            }
            const auto t = ply_type(type);
            if (!t || !(words >> p.name)) fail("bad line '" + line + "'");
            p.type = *t;
            elements.back().properties.push_back(p);
        } else if (!keyword.empty() && keyword != "ply" && keyword != "comment" && keyword != "obj_info") {
            fail("unknown header line '" + line + "'");
        }
    }
    if (!encoding) fail("no 'format' line");

    PlyBody body(bytes, body_start + 1, *encoding, path);
    bool have_vertices = false, have_faces = false;
    FaceList faces;
    std::vector<std::vector<double>> face_values;  // per file face, the carried face columns
    std::vector<int> face_flags;
    for (const PlyElement& e : elements) {
        const size_t min_bytes = body.min_item_bytes(e);
        if (min_bytes > 0 && e.count > body.remaining() / min_bytes)
            fail("element '" + e.name + "' claims " + std::to_string(e.count) + " items, more than the file holds");
        const bool is_vertex = e.name == "vertex" && !have_vertices;
        const bool is_face = e.name == "face" && !have_faces;
        const int x = property_index(e, "x"), y = property_index(e, "y"), z = property_index(e, "z");
        int indices = property_index(e, "vertex_indices");
        if (indices < 0) indices = property_index(e, "vertex_index");
        const int flags = property_index(e, "flags");
        const int nx = property_index(e, "nx");
        if (is_vertex && (x < 0 || y < 0 || z < 0 || e.properties[size_t(x)].is_list || e.properties[size_t(y)].is_list ||
                          e.properties[size_t(z)].is_list))
            fail("its vertices have no x, y, z");
        if (is_face && (indices < 0 || !e.properties[size_t(indices)].is_list)) fail("its faces have no vertex_indices list");
        if (!is_vertex && !is_face && e.count > 0)
            d.notes.push_back("dropped the PLY element '" + e.name + "' (" + std::to_string(e.count) + " items): only vertices and faces are read");

        // Which properties go back into the file as they came.
        std::vector<int> carried;
        CarriedColumns& columns = is_vertex ? d.vertex_columns : d.face_columns;
        for (size_t i = 0; i < e.properties.size(); ++i) {
            const PlyProperty& p = e.properties[i];
            const bool computed = p.name == "x" || p.name == "y" || p.name == "z" || p.name == "nx" || p.name == "ny" ||
                                  p.name == "nz" || int(i) == indices || p.name == "flags";
            if ((is_vertex || is_face) && !computed && !p.is_list) {
                carried.push_back(int(i));
                columns.properties.push_back(p);
            } else if ((is_vertex || is_face) && !computed) {
                d.notes.push_back("dropped the list property '" + p.name + "' of the PLY " + e.name + "s");
            }
        }
        if (is_vertex) {
            have_vertices = true;
            d.points.resize(Eigen::Index(e.count), 3);
            d.vertex_normals = nx >= 0;
            columns.values.assign(carried.size(), std::vector<double>(e.count));
        }
        if (is_face) {
            have_faces = true;
            d.face_normals = nx >= 0;
            d.has_stored_flags = flags >= 0;
        }
        if (e.properties.empty()) continue;  // nothing to read, however many it claims

        std::vector<double> item(e.properties.size());
        std::vector<long> corners;
        for (size_t n = 0; n < e.count; ++n) {
            for (size_t i = 0; i < e.properties.size(); ++i) {
                const PlyProperty& p = e.properties[i];
                if (!p.is_list) {
                    item[i] = body.scalar(p.type);
                    continue;
                }
                const double count = body.scalar(p.count_type);
                if (!(count >= 0) || body.remaining() / (*encoding == PlyEncoding::Ascii ? 1 : ply_size(p.type)) < count)
                    fail("a list of " + full_precision(count) + " items does not fit in the file");
                corners.clear();
                for (size_t k = 0; k < size_t(count); ++k) {
                    const double v = body.scalar(p.type);
                    if (int(i) == indices) {
                        if (!(v >= 0 && v < 2147483647.0)) fail("face " + std::to_string(n) + " has the index " + full_precision(v));
                        corners.push_back(long(v));
                    }
                }
            }
            if (is_vertex) {
                d.points.row(Eigen::Index(n)) << item[size_t(x)], item[size_t(y)], item[size_t(z)];
                for (size_t c = 0; c < carried.size(); ++c) columns.values[c][n] = item[size_t(carried[c])];
            } else if (is_face) {
                faces.add(corners, n);
                std::vector<double> values;
                for (int c : carried) values.push_back(item[size_t(c)]);
                face_values.push_back(values);
                if (flags >= 0) face_flags.push_back(int(clamped<int32_t>(item[size_t(flags)])));
            }
        }
    }
    if (!have_vertices) fail("it has no vertex element");
    check_indices(faces, size_t(d.points.rows()), "cannot read '" + path + "' as PLY");
    store_faces(d, faces, "PLY");

    // Face values follow each triangle back to its polygon.
    d.face_columns.values.assign(d.face_columns.properties.size(), std::vector<double>(faces.triangles.size()));
    for (size_t t = 0; t < faces.triangles.size(); ++t)
        for (size_t c = 0; c < d.face_columns.properties.size(); ++c)
            d.face_columns.values[c][t] = face_values[faces.source_face[t]][c];
    for (size_t c = 0; c < d.vertex_columns.properties.size(); ++c)
        if (d.vertex_columns.properties[c].name == "quality") d.vertex_quality = d.vertex_columns.values[c];
    // Whatever else a file's flag words hold (deleted, visited, border bits of another
    // program's session) must not reach this session: only the selection bit is kept.
    if (d.has_stored_flags)
        for (size_t t = 0; t < faces.triangles.size(); ++t)
            if (face_flags[faces.source_face[t]] & kSelectedFlag) d.stored_selection.push_back(int(t));
}

template <typename T>
void put(std::string& out, T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));  // little-endian machines only, as Debian's amd64 and arm64 are
    out.append(raw, sizeof(T));
}

void put_as(std::string& out, PlyType t, double v) {
    switch (t) {
    case PlyType::Int8: put(out, clamped<int8_t>(v)); break;
    case PlyType::Uint8: put(out, clamped<uint8_t>(v)); break;
    case PlyType::Int16: put(out, clamped<int16_t>(v)); break;
    case PlyType::Uint16: put(out, clamped<uint16_t>(v)); break;
    case PlyType::Int32: put(out, clamped<int32_t>(v)); break;
    case PlyType::Uint32: put(out, clamped<uint32_t>(v)); break;
    case PlyType::Float32: put(out, float(v)); break;
    case PlyType::Float64: put(out, v); break;
    }
}

// Binary little-endian PLY: positions in double so that nothing the solver computed is lost.
std::string ply_text(const Data* d, const Points& p, const Triangles& t, const std::vector<int>& selected,
                     const Points* given_normals) {
    const bool vn = (d && d->vertex_normals) || given_normals, fn = d && d->face_normals;
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by geofilter\n";
    out += "element vertex " + std::to_string(p.rows()) + "\nproperty double x\nproperty double y\nproperty double z\n";
    if (vn) out += "property float nx\nproperty float ny\nproperty float nz\n";
    if (d)
        for (const auto& c : d->vertex_columns.properties) out += std::string("property ") + ply_type_name(c.type) + " " + c.name + "\n";
    out += "element face " + std::to_string(t.rows()) + "\nproperty list uchar int vertex_indices\n";
    if (!selected.empty()) out += "property int flags\n";
    if (fn) out += "property float nx\nproperty float ny\nproperty float nz\n";
    if (d)
        for (const auto& c : d->face_columns.properties) out += std::string("property ") + ply_type_name(c.type) + " " + c.name + "\n";
    out += "end_header\n";
    const Points normals = given_normals ? *given_normals : vn ? vertex_normals(p, t) : Points();
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        for (int k = 0; k < 3; ++k) put(out, p(i, k));
        if (vn)
            for (int k = 0; k < 3; ++k) put(out, float(normals(i, k)));
        if (d)
            for (size_t c = 0; c < d->vertex_columns.properties.size(); ++c)
                put_as(out, d->vertex_columns.properties[c].type, d->vertex_columns.values[c][size_t(i)]);
    }
    std::vector<bool> is_selected(size_t(t.rows()), false);
    for (int f : selected) is_selected[size_t(f)] = true;
    for (Eigen::Index f = 0; f < t.rows(); ++f) {
        put(out, uint8_t(3));
        for (int k = 0; k < 3; ++k) put(out, int32_t(t(f, k)));
        if (!selected.empty()) put(out, int32_t(is_selected[size_t(f)] ? kSelectedFlag : 0));
        if (fn) {
            const Eigen::RowVector3d n = face_normal(p, t, f);
            for (int k = 0; k < 3; ++k) put(out, float(n(k)));
        }
        if (d)
            for (size_t c = 0; c < d->face_columns.properties.size(); ++c)
                put_as(out, d->face_columns.properties[c].type, d->face_columns.values[c][size_t(f)]);
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// OBJ: positions and faces. Texture coordinates, normals and materials index their own
// lists per corner, which a shared-vertex mesh cannot keep: they are dropped, with a note.

// "12", "12/3", "12//4", "12/3/4": the position index, 0-based; negative counts back from
// the last vertex read so far.
long obj_corner(const std::string& corner, size_t vertices_so_far, const std::string& where) {
    char* end = nullptr;
    const long i = std::strtol(corner.c_str(), &end, 10);
    if (end == corner.c_str() || (*end != '\0' && *end != '/') || i == 0 || i > INT_MAX || i < -INT_MAX)
        throw Error(where + ": bad face corner '" + corner + "'");
    return i > 0 ? i - 1 : long(vertices_so_far) + i;
}

void read_obj(Data& d, const std::string& path, const std::string& bytes) {
    std::vector<Eigen::RowVector3d> points;
    FaceList faces;
    size_t face_count = 0;
    std::vector<std::string> dropped;
    const auto lines = lines_of(bytes, '#');
    for (size_t l = 0; l < lines.size(); ++l) {
        const std::string where = "cannot read '" + path + "' as OBJ: line " + std::to_string(l + 1);
        std::istringstream words(lines[l]);
        std::string keyword;
        if (!(words >> keyword)) continue;
        if (keyword == "v") {
            double x, y, z;
            if (!(words >> x >> y >> z)) throw Error(where + ": a vertex needs x y z");
            points.emplace_back(x, y, z);
        } else if (keyword == "f") {
            std::vector<long> corners;
            for (std::string corner; words >> corner;) corners.push_back(obj_corner(corner, points.size(), where));
            faces.add(corners, face_count++);
        } else if ((keyword == "vt" || keyword == "vn" || keyword == "usemtl" || keyword == "mtllib" || keyword == "l") &&
                   std::find(dropped.begin(), dropped.end(), keyword) == dropped.end()) {
            dropped.push_back(keyword);
        }
    }
    if (points.empty()) throw Error("cannot read '" + path + "' as OBJ: it has no vertices ('v' lines)");
    check_indices(faces, points.size(), "cannot read '" + path + "' as OBJ");
    d.points.resize(Eigen::Index(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) d.points.row(Eigen::Index(i)) = points[i];
    store_faces(d, faces, "OBJ");
    if (!dropped.empty()) {
        std::string list;
        for (const auto& k : dropped) list += (list.empty() ? "'" : ", '") + k + "'";
        d.notes.push_back("OBJ " + list + " lines are not carried: positions and faces are written");
    }
}

// A cloud's normals as vn lines, one per v line in the same order: with no faces to index
// them, readers (MeshLab among them) pair them with the vertices by order.
std::string obj_text(const Points& p, const Triangles& t, const Points* cloud_normals) {
    std::string out = "# written by geofilter\n";
    for (Eigen::Index i = 0; i < p.rows(); ++i)
        out += "v " + full_precision(p(i, 0)) + " " + full_precision(p(i, 1)) + " " + full_precision(p(i, 2)) + "\n";
    if (cloud_normals && t.rows() == 0)
        for (Eigen::Index i = 0; i < cloud_normals->rows(); ++i)
            out += "vn " + full_precision((*cloud_normals)(i, 0)) + " " + full_precision((*cloud_normals)(i, 1)) + " " +
                   full_precision((*cloud_normals)(i, 2)) + "\n";
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        out += "f " + std::to_string(t(f, 0) + 1) + " " + std::to_string(t(f, 1) + 1) + " " + std::to_string(t(f, 2) + 1) + "\n";
    return out;
}

// ---------------------------------------------------------------------------------------------
// OFF, ASCII: "[ST][C][N]OFF"; a vertex line is x y z [normal] [colour] [texture], a face
// line n i1..in [colour]. Colours and texture coordinates are carried as the file wrote
// them, normals recomputed.

std::vector<std::string> words_of(const std::string& line) {
    std::istringstream in(line);
    return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

std::string joined(const std::vector<std::string>& words, size_t from) {
    std::string out;
    for (size_t i = from; i < words.size(); ++i) out += " " + words[i];
    return out;
}

double off_number(const std::string& word, const std::string& where) {
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (word.empty() || *end != '\0') throw Error(where + ": '" + word + "' is not a number");
    return v;
}

void read_off(Data& d, const std::string& path, const std::string& bytes) {
    const std::string what = "cannot read '" + path + "' as OFF";
    std::vector<std::vector<std::string>> lines;
    for (const auto& line : lines_of(bytes, '#'))
        if (!blank(line)) lines.push_back(words_of(line));
    if (lines.empty()) throw Error(what + ": no 'OFF' header");
    std::string keyword = lines[0][0];
    if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0) throw Error(what + ": no 'OFF' header");
    const std::string prefix = keyword.substr(0, keyword.size() - 3);
    if (prefix != "" && prefix != "C" && prefix != "N" && prefix != "CN" && prefix != "NC" && prefix != "ST" &&
        prefix != "STC" && prefix != "STN" && prefix != "STCN" && prefix != "STNC")
        throw Error(what + ": the variant '" + keyword + "' is not read (only [ST][C][N]OFF, 3D, ASCII)");
    const bool normals = prefix.find('N') != std::string::npos, texture = prefix.find("ST") != std::string::npos;
    size_t next = 1;
    std::vector<std::string> counts(lines[0].begin() + 1, lines[0].end());
    if (counts.empty()) {
        if (lines.size() < 2) throw Error(what + ": no vertex and face counts");
        counts = lines[next++];
    }
    if (counts.size() > 0 && counts[0] == "BINARY") throw Error(what + ": binary OFF is not read");
    if (counts.size() < 2) throw Error(what + ": no vertex and face counts");
    const double nv = off_number(counts[0], what), nf = off_number(counts[1], what);
    if (!(nv >= 0 && nf >= 0) || nv + nf > double(lines.size() - next))
        throw Error(what + ": it announces " + counts[0] + " vertices and " + counts[1] + " faces, more lines than it has");
    d.off_keyword = keyword;
    d.points.resize(Eigen::Index(nv), 3);
    for (size_t i = 0; i < size_t(nv); ++i) {
        const auto& w = lines[next++];
        const std::string where = what + ": vertex " + std::to_string(i);
        const size_t fixed = 3 + (normals ? 3 : 0);
        if (w.size() < fixed + (texture ? 2 : 0)) throw Error(where + " has too few numbers");
        for (int k = 0; k < 3; ++k) d.points(Eigen::Index(i), k) = off_number(w[size_t(k)], where);
        d.vertex_tail.push_back(joined(w, fixed));
    }
    FaceList faces;
    for (size_t f = 0; f < size_t(nf); ++f) {
        const auto& w = lines[next++];
        const std::string where = what + ": face " + std::to_string(f);
        const double n = off_number(w[0], where);
        if (!(n >= 0) || n + 1 > double(w.size())) throw Error(where + " lists fewer corners than it announces");
        std::vector<long> corners;
        for (size_t k = 1; k <= size_t(n); ++k) {
            const double v = off_number(w[k], where);
            if (!(v >= 0 && v < 2147483647.0) || v != std::floor(v)) throw Error(where + " has the index " + w[k]);
            corners.push_back(long(v));
        }
        faces.add(corners, f);
        const std::string tail = joined(w, size_t(n) + 1);
        d.face_tail.resize(faces.triangles.size(), tail);
    }
    check_indices(faces, size_t(nv), what);
    store_faces(d, faces, "OFF");
}

std::string off_text(const Data* d, const Points& p, const Triangles& t, const Points* cloud_normals) {
    const std::string keyword = d ? d->off_keyword : "OFF";
    const bool normals = keyword.find('N') != std::string::npos;
    const Points n = !normals ? Points() : cloud_normals ? *cloud_normals : vertex_normals(p, t);
    std::string out = keyword + "\n" + std::to_string(p.rows()) + " " + std::to_string(t.rows()) + " 0\n";
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        out += full_precision(p(i, 0)) + " " + full_precision(p(i, 1)) + " " + full_precision(p(i, 2));
        if (normals) out += " " + full_precision(n(i, 0)) + " " + full_precision(n(i, 1)) + " " + full_precision(n(i, 2));
        if (d) out += d->vertex_tail[size_t(i)];
        out += "\n";
    }
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        out += "3 " + std::to_string(t(f, 0)) + " " + std::to_string(t(f, 1)) + " " + std::to_string(t(f, 2)) +
               (d ? d->face_tail[size_t(f)] : "") + "\n";
    return out;
}

// ---------------------------------------------------------------------------------------------
// XYZ: a point cloud as text, one point a line, "x y z" or "x y z nx ny nz" (the normals are
// read and not used: the cloud's Laplacian estimates its own, and those are written).

void read_xyz(Data& d, const std::string& path, const std::string& bytes) {
    std::vector<Eigen::RowVector3d> points;
    const auto lines = lines_of(bytes, '#');
    for (size_t l = 0; l < lines.size(); ++l) {
        if (blank(lines[l])) continue;
        const std::string where = "cannot read '" + path + "' as XYZ: line " + std::to_string(l + 1);
        const std::vector<std::string> w = words_of(lines[l]);
        if (w.size() != 3 && w.size() != 6)
            throw Error(where + " has " + std::to_string(w.size()) + " numbers: a point is x y z, or x y z nx ny nz");
        Eigen::RowVector3d x;
        for (int k = 0; k < 3; ++k) x[k] = off_number(w[size_t(k)], where);
        for (size_t k = 3; k < w.size(); ++k) off_number(w[k], where);
        if (w.size() == 6) d.vertex_normals = true;
        points.push_back(x);
    }
    if (points.empty()) throw Error("cannot read '" + path + "' as XYZ: it has no points");
    d.points.resize(Eigen::Index(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) d.points.row(Eigen::Index(i)) = points[i];
    d.triangles.resize(0, 3);
    if (d.vertex_normals) d.notes.push_back("the XYZ file's normals are not used: the cloud's are estimated and written");
}

std::string xyz_text(const Points& p, const Points* normals) {
    std::string out;
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        out += full_precision(p(i, 0)) + " " + full_precision(p(i, 1)) + " " + full_precision(p(i, 2));
        if (normals)
            out += " " + full_precision((*normals)(i, 0)) + " " + full_precision((*normals)(i, 1)) + " " +
                   full_precision((*normals)(i, 2));
        out += "\n";
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// STL: every triangle stores its own three corners. Binary when the size matches the count
// in the header exactly, ASCII ("solid ... vertex x y z ...") otherwise.

void read_stl(Data& d, const std::string& path, const std::string& bytes) {
    std::vector<std::array<float, 3>> corners;
    uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, sizeof count);
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * static_cast<uint64_t>(count)) {
        corners.reserve(size_t(count) * 3);
        for (uint32_t t = 0; t < count; ++t)
            for (int k = 0; k < 3; ++k) {
                std::array<float, 3> xyz;
                std::memcpy(xyz.data(), bytes.data() + 84 + 50 * size_t(t) + 12 + 12 * k, sizeof xyz);  // after the normal
                corners.push_back(xyz);
            }
    } else {
        std::istringstream text(bytes);
        std::string word;
        if (!(text >> word) || word != "solid")
            throw Error("cannot read '" + path + "' as STL: neither a binary STL (size does not match its triangle count)"
                        " nor an ASCII one (no 'solid')");
        while (text >> word) {
            if (word != "vertex") continue;
            std::array<float, 3> xyz;
            if (!(text >> xyz[0] >> xyz[1] >> xyz[2]))
                throw Error("cannot read '" + path + "' as STL: a vertex line lacks coordinates");
            corners.push_back(xyz);
        }
        if (corners.size() % 3 != 0)
            throw Error("cannot read '" + path + "' as STL: " + std::to_string(corners.size()) +
                        " vertices do not make whole triangles");
    }
    // Welding: the copies of one corner are the same float triplet, so exact comparison is
    // right (with -0 taken as 0). Vertices are numbered in the order they first appear.
    struct Key {
        std::array<uint32_t, 3> bits;
        bool operator==(const Key& o) const { return bits == o.bits; }
    };
    struct Hash {
        size_t operator()(const Key& k) const { return (size_t(k.bits[0]) * 73856093u) ^ (size_t(k.bits[1]) * 19349663u) ^ (size_t(k.bits[2]) * 83492791u); }
    };
    std::unordered_map<Key, int, Hash> index;
    std::vector<std::array<float, 3>> unique;
    std::vector<int> corner_vertex(corners.size());
    for (size_t c = 0; c < corners.size(); ++c) {
        Key key;
        for (int k = 0; k < 3; ++k) {
            const float v = corners[c][size_t(k)] == 0.0f ? 0.0f : corners[c][size_t(k)];
            std::memcpy(&key.bits[size_t(k)], &v, sizeof v);
        }
        const auto [it, added] = index.emplace(key, int(unique.size()));
        if (added) unique.push_back(corners[c]);
        corner_vertex[c] = it->second;
    }
    d.points.resize(Eigen::Index(unique.size()), 3);
    for (size_t i = 0; i < unique.size(); ++i)
        for (int k = 0; k < 3; ++k) d.points(Eigen::Index(i), k) = unique[i][size_t(k)];
    d.triangles.resize(Eigen::Index(corners.size() / 3), 3);
    for (size_t c = 0; c < corners.size(); ++c) d.triangles(Eigen::Index(c / 3), int(c % 3)) = corner_vertex[c];
    d.notes.push_back("STL has no shared vertices: welded its " + std::to_string(corners.size()) +
                      " triangle corners into " + std::to_string(unique.size()) + " vertices");
}

std::string stl_text(const Points& p, const Triangles& t) {
    std::string out = "binary STL written by geofilter";
    out.resize(80, ' ');
    put(out, uint32_t(t.rows()));
    for (Eigen::Index f = 0; f < t.rows(); ++f) {
        const Eigen::RowVector3d n = face_normal(p, t, f);
        for (int k = 0; k < 3; ++k) put(out, float(n(k)));
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k) put(out, float(p(t(f, c), k)));
        put(out, uint16_t(0));
    }
    return out;
}

// `d` is what was read when writing in the format that was read, else null: attributes are
// carried only within one format.
void save(const std::string& path, const Data* d, const Points& p, const Triangles& t, const std::vector<int>& selected,
          const Points* cloud_normals = nullptr) {
    const MeshFormat format = require_format(path);
    if (d && d->format != format) d = nullptr;
    if (t.rows() > 0) cloud_normals = nullptr;
    if (cloud_normals && cloud_normals->rows() != p.rows())
        throw Error("internal: " + std::to_string(cloud_normals->rows()) + " normals for " + std::to_string(p.rows()) + " points");
    if (format == MeshFormat::Stl && t.rows() == 0)
        throw Error("cannot write '" + path + "': STL stores triangles only and this is a point cloud; write PLY, OBJ or XYZ");
    if (format == MeshFormat::Xyz && t.rows() > 0)
        throw Error("cannot write '" + path + "': XYZ stores points only and would drop the mesh's " +
                    std::to_string(t.rows()) + " faces; write PLY, OBJ, OFF or STL");
    std::string text;
    switch (format) {
    case MeshFormat::Ply: text = ply_text(d, p, t, selected, cloud_normals); break;
    case MeshFormat::Obj: text = obj_text(p, t, cloud_normals); break;
    case MeshFormat::Off: text = off_text(d, p, t, cloud_normals); break;
    case MeshFormat::Stl: text = stl_text(p, t); break;
    case MeshFormat::Xyz: text = xyz_text(p, cloud_normals); break;
    }
    std::ofstream out(path, std::ios::binary);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
}

} // namespace

std::optional<MeshFormat> format_of(const std::string& path) {
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return std::nullopt;
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == "ply") return MeshFormat::Ply;
    if (ext == "obj") return MeshFormat::Obj;
    if (ext == "off") return MeshFormat::Off;
    if (ext == "stl") return MeshFormat::Stl;
    if (ext == "xyz") return MeshFormat::Xyz;
    return std::nullopt;
}

const char* format_name(MeshFormat format) {
    switch (format) {
    case MeshFormat::Ply: return "PLY";
    case MeshFormat::Obj: return "OBJ";
    case MeshFormat::Off: return "OFF";
    case MeshFormat::Stl: return "STL";
    case MeshFormat::Xyz: return "XYZ";
    }
    return "?";
}

const char* supported_formats() {
    return "PLY, OBJ, OFF or STL (.ply, .obj, .off, .stl), or XYZ (.xyz) for a point cloud";
}

MeshFile::MeshFile(std::unique_ptr<Data> data) : data_(std::move(data)) {}
MeshFile::MeshFile(MeshFile&&) noexcept = default;
MeshFile& MeshFile::operator=(MeshFile&&) noexcept = default;
MeshFile::~MeshFile() = default;

MeshFile MeshFile::read(const std::string& path) {
    auto d = std::make_unique<Data>();
    d->format = require_format(path);
    const std::string bytes = read_whole(path);
    switch (d->format) {
    case MeshFormat::Ply: read_ply(*d, path, bytes); break;
    case MeshFormat::Obj: read_obj(*d, path, bytes); break;
    case MeshFormat::Off: read_off(*d, path, bytes); break;
    case MeshFormat::Stl: read_stl(*d, path, bytes); break;
    case MeshFormat::Xyz: read_xyz(*d, path, bytes); break;
    }
    if (d->has_stored_flags)
        d->notes.push_back("stored face flags: " + std::to_string(d->stored_selection.size()) + " of " +
                           std::to_string(d->triangles.rows()) + " faces selected");
    return MeshFile(std::move(d));
}

MeshFormat MeshFile::format() const { return data_->format; }
const Points& MeshFile::points() const { return data_->points; }
const Triangles& MeshFile::triangles() const { return data_->triangles; }
bool MeshFile::has_stored_flags() const { return data_->has_stored_flags; }
const std::vector<int>& MeshFile::stored_selection() const { return data_->stored_selection; }
const std::vector<double>& MeshFile::vertex_quality() const { return data_->vertex_quality; }
const std::vector<std::string>& MeshFile::notes() const { return data_->notes; }

void MeshFile::write(const std::string& path, const Points& points, const std::vector<int>& selected_faces,
                     const Points* cloud_normals) {
    if (points.rows() != data_->points.rows())
        throw Error("internal: " + std::to_string(points.rows()) + " points for " + std::to_string(data_->points.rows()) +
                    " vertices");
    save(path, data_.get(), points, data_->triangles, require_format(path) == MeshFormat::Ply ? selected_faces : std::vector<int>(),
         cloud_normals);
}

void write_mesh(const std::string& path, const Mesh& mesh) { save(path, nullptr, mesh.points, mesh.triangles, {}); }

} // namespace geofilter::cli
