#include "mesh_io.h"

#include <vcg/complex/complex.h>
#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/algorithms/update/normal.h>
#include <wrap/io_trimesh/export.h>
#include <wrap/io_trimesh/import.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <iterator>
#include <sstream>

namespace geofilter::cli {

namespace {

class CliVertex;
class CliFace;
struct CliUsedTypes
    : public vcg::UsedTypes<vcg::Use<CliVertex>::AsVertexType, vcg::Use<CliFace>::AsFaceType> {};
// Double precision so that a PLY written by the tool loses nothing the solver computed.
// Colour, quality and texture coordinates are carried so that filtering a coloured scan
// does not strip it; BitFlags on faces is where PLY's stored selection arrives.
class CliVertex : public vcg::Vertex<CliUsedTypes, vcg::vertex::Coord3d, vcg::vertex::Normal3d, vcg::vertex::Color4b,
                                     vcg::vertex::Qualityd, vcg::vertex::TexCoord2d, vcg::vertex::BitFlags> {};
class CliFace : public vcg::Face<CliUsedTypes, vcg::face::VertexRef, vcg::face::Normal3d, vcg::face::Color4b,
                                 vcg::face::Qualityd, vcg::face::BitFlags> {};
class CliMesh : public vcg::tri::TriMesh<std::vector<CliVertex>, std::vector<CliFace>> {
public:
    // This vcglib's ~TriMesh leaves the attributes that importers add (OBJ materials) behind:
    // LeakSanitizer reports them. Free them here.
    ~CliMesh() { ClearAttributes(); }
};

using Importer = vcg::tri::io::Importer<CliMesh>;
using Exporter = vcg::tri::io::Exporter<CliMesh>;
using IoMask = vcg::tri::io::Mask;

int export_capability(MeshFormat format) {
    switch (format) {
    case MeshFormat::Ply: return vcg::tri::io::ExporterPLY<CliMesh>::GetExportMaskCapability();
    case MeshFormat::Obj: return vcg::tri::io::ExporterOBJ<CliMesh>::GetExportMaskCapability();
    case MeshFormat::Off: return vcg::tri::io::ExporterOFF<CliMesh>::GetExportMaskCapability();
    case MeshFormat::Stl: return vcg::tri::io::ExporterSTL<CliMesh>::GetExportMaskCapability();
    }
    return 0;
}

MeshFormat require_format(const std::string& path) {
    const auto format = format_of(path);
    if (!format) throw Error("cannot tell the format of '" + path + "': use " + supported_formats());
    return *format;
}

void require_readable(const std::string& path) {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw Error("cannot read '" + path + "': no such file or no permission");
    char c;
    if (!probe.get(c)) throw Error("cannot read '" + path + "': the file is empty or not a regular file");
}

// The vcglib of the MeshLab 2020.09 sources refuses the first vertex of an OBJ face list
// (its GoodObjIndex rejects the 0 that SplitToken made of "1"; MeshLab issue #791, fixed
// after that tree was cut): every face around vertex 1 is silently dropped, and Debian's
// meshlabserver aborts on an assertion. A fixed vcglib accepts index 0 here.
bool obj_importer_drops_first_vertex() {
    int index = 0;
    return !vcg::tri::io::ImporterOBJ<CliMesh>::GoodObjIndex(index, 1);
}

std::string strip_cr(std::string line) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return line;
}

// A copy of the OBJ `path` that this importer reads whole: a duplicate of the first vertex is
// put in front, so positive face indices move up by one (relative ones already count from
// the end). Material libraries are pointed at the original's folder. Returns the copy's path.
std::string obj_copy_with_leading_vertex(const std::string& path) {
    std::ifstream in(path);
    std::string first_vertex;
    for (std::string line; std::getline(in, line);)
        if (line.rfind("v ", 0) == 0 || line.rfind("v\t", 0) == 0) {
            first_vertex = strip_cr(line);
            break;
        }
    if (first_vertex.empty()) return path;  // no vertices: nothing to lose, let vcglib report it
    char name[] = "/tmp/geofilter-obj-XXXXXX.obj";
    const int fd = mkstemps(name, 4);
    if (fd < 0) throw Error("cannot read '" + path + "': no room for a temporary copy in /tmp");
    close(fd);
    std::ofstream out(name);
    out << first_vertex << '\n';
    in.clear();
    in.seekg(0);
    const std::string folder = std::filesystem::absolute(path).parent_path().string();
    for (std::string line; std::getline(in, line);) {
        line = strip_cr(line);
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "f") {
            out << 'f';
            for (std::string corner; words >> corner;) {
                const size_t slash = corner.find('/');
                const long index = std::strtol(corner.substr(0, slash).c_str(), nullptr, 10);
                out << ' ' << (index > 0 ? std::to_string(index + 1) : corner.substr(0, slash))
                    << (slash == std::string::npos ? "" : corner.substr(slash));
            }
            out << '\n';
        } else if (keyword == "mtllib") {
            std::string library;
            std::getline(words >> std::ws, library);
            out << "mtllib " << (library.empty() || library[0] == '/' ? library : folder + "/" + library) << '\n';
        } else {
            out << line << '\n';
        }
    }
    if (!out) {
        std::remove(name);
        throw Error("cannot read '" + path + "': could not write a temporary copy in /tmp");
    }
    return name;
}

// Whatever else a file's flag words hold (deleted, visited, border bits of another
// program's session) must not reach this session: only the selection bit is kept.
std::vector<int> keep_only_selection_flags(CliMesh& m) {
    std::vector<int> selected;
    for (auto& v : m.vert) v.Flags() = 0;
    for (size_t i = 0; i < m.face.size(); ++i) {
        const bool was_selected = m.face[i].IsS();
        m.face[i].Flags() = 0;
        if (was_selected) {
            m.face[i].SetS();
            selected.push_back(int(i));
        }
    }
    return selected;
}

void save(CliMesh& m, const std::string& path, int mask) {
    const MeshFormat format = require_format(path);
    mask &= export_capability(format);
    if (mask & (IoMask::IOM_VERTNORMAL | IoMask::IOM_FACENORMAL)) {
        // The normals read with the input describe the shape before filtering.
        vcg::tri::UpdateNormal<CliMesh>::PerFaceNormalized(m);
        vcg::tri::UpdateNormal<CliMesh>::PerVertexAngleWeighted(m);
    }
    const int err = Exporter::Save(m, path.c_str(), mask);
    if (err != 0) throw Error("cannot write '" + path + "': " + Exporter::ErrorMsg(err));
}

} // namespace

struct MeshFile::Data {
    MeshFormat format;
    CliMesh mesh;
    int load_mask = 0;
    Points points;
    Triangles triangles;
    bool has_stored_flags = false;
    std::vector<int> stored_selection;
    std::vector<double> vertex_quality;
    std::vector<std::string> notes;
};

std::optional<MeshFormat> format_of(const std::string& path) {
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return std::nullopt;
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == "ply") return MeshFormat::Ply;
    if (ext == "obj") return MeshFormat::Obj;
    if (ext == "off") return MeshFormat::Off;
    if (ext == "stl") return MeshFormat::Stl;
    return std::nullopt;
}

const char* format_name(MeshFormat format) {
    switch (format) {
    case MeshFormat::Ply: return "PLY";
    case MeshFormat::Obj: return "OBJ";
    case MeshFormat::Off: return "OFF";
    case MeshFormat::Stl: return "STL";
    }
    return "?";
}

const char* supported_formats() { return "PLY, OBJ, OFF or STL (.ply, .obj, .off, .stl)"; }

namespace {

// STL is read here rather than by vcglib: this vcglib's STL importer runs strlen over the
// unterminated 80-byte header (AddressSanitizer: stack-buffer-overflow) and trusts the
// triangle count of a truncated binary file. Binary when the size matches the count in
// the header exactly, ASCII ("solid ... vertex x y z ...") otherwise.
void read_stl(CliMesh& m, const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::vector<vcg::Point3f> corners;
    uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, sizeof count);
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * static_cast<uint64_t>(count)) {
        corners.reserve(size_t(count) * 3);
        for (uint32_t t = 0; t < count; ++t) {
            const char* facet = bytes.data() + 84 + 50 * size_t(t);
            for (int k = 0; k < 3; ++k) {
                float xyz[3];
                std::memcpy(xyz, facet + 12 + 12 * k, sizeof xyz);  // skip the stored normal
                corners.emplace_back(xyz[0], xyz[1], xyz[2]);
            }
        }
    } else {
        std::istringstream text(std::string(bytes.begin(), bytes.end()));
        std::string word;
        if (!(text >> word) || word != "solid")
            throw Error("cannot read '" + path + "' as STL: neither a binary STL (size does not match its triangle count)"
                        " nor an ASCII one (no 'solid')");
        while (text >> word) {
            if (word != "vertex") continue;
            float x, y, z;
            if (!(text >> x >> y >> z)) throw Error("cannot read '" + path + "' as STL: a vertex line lacks coordinates");
            corners.emplace_back(x, y, z);
        }
        if (corners.size() % 3 != 0)
            throw Error("cannot read '" + path + "' as STL: " + std::to_string(corners.size()) +
                        " vertices do not make whole triangles");
    }
    auto vi = vcg::tri::Allocator<CliMesh>::AddVertices(m, corners.size());
    for (const auto& c : corners) (vi++)->P() = vcg::Point3d(c[0], c[1], c[2]);
    auto fi = vcg::tri::Allocator<CliMesh>::AddFaces(m, corners.size() / 3);
    for (size_t t = 0; t < corners.size() / 3; ++t, ++fi)
        for (int k = 0; k < 3; ++k) fi->V(k) = &m.vert[3 * t + k];
}

} // namespace

MeshFile::MeshFile(std::unique_ptr<Data> data) : data_(std::move(data)) {}
MeshFile::MeshFile(MeshFile&&) noexcept = default;
MeshFile& MeshFile::operator=(MeshFile&&) noexcept = default;
MeshFile::~MeshFile() = default;

MeshFile MeshFile::read(const std::string& path) {
    auto d = std::make_unique<Data>();
    d->format = require_format(path);
    require_readable(path);
    CliMesh& m = d->mesh;
    const bool shifted_obj = d->format == MeshFormat::Obj && obj_importer_drops_first_vertex();
    const std::string source = shifted_obj ? obj_copy_with_leading_vertex(path) : path;
    int err = 0;
    if (d->format == MeshFormat::Stl) {
        read_stl(m, path);
        d->load_mask = 0;
    } else {
        err = Importer::Open(m, source.c_str(), d->load_mask);
    }
    if (source != path) std::remove(source.c_str());
    if (err != 0 && Importer::ErrorCritical(err))
        throw Error("cannot read '" + path + "' as " + format_name(d->format) + ": " + Importer::ErrorMsg(err));
    if (source != path && m.vn > 0) {
        // The leading duplicate: no face may use it, or the shift went wrong.
        for (const auto& f : m.face)
            for (int k = 0; k < 3; ++k)
                if (f.cV(k) == &m.vert[0])
                    throw Error("internal: reading '" + path + "' through a shifted copy went wrong (face uses vertex 0)");
        vcg::tri::Allocator<CliMesh>::DeleteVertex(m, m.vert[0]);
        vcg::tri::Allocator<CliMesh>::CompactEveryVector(m);
    }

    if (d->format == MeshFormat::Stl) {
        const int corners = m.vn;
        // Exact comparison is right here: the copies of one corner are the same float triplet.
        vcg::tri::Clean<CliMesh>::RemoveDuplicateVertex(m, false);
        vcg::tri::Allocator<CliMesh>::CompactEveryVector(m);
        d->notes.push_back("STL has no shared vertices: welded its " + std::to_string(corners) + " triangle corners into " +
                           std::to_string(m.vn) + " vertices");
    }
    d->has_stored_flags = (d->load_mask & IoMask::IOM_FACEFLAGS) != 0;
    d->stored_selection = keep_only_selection_flags(m);
    if (d->has_stored_flags)
        d->notes.push_back("stored face flags: " + std::to_string(d->stored_selection.size()) + " of " +
                           std::to_string(m.fn) + " faces selected");
    if (d->load_mask & IoMask::IOM_BITPOLYGONAL)
        d->notes.push_back("the file has polygons: vcglib split them into triangles, and triangles are written");
    // Flags are this session's business: they are written back only as the selection.
    // Polygons would be rebuilt from faux edges, which needs adjacency this mesh type lacks.
    d->load_mask &= ~(IoMask::IOM_FACEFLAGS | IoMask::IOM_VERTFLAGS | IoMask::IOM_BITPOLYGONAL);

    d->points.resize(Eigen::Index(m.vert.size()), 3);
    for (size_t i = 0; i < m.vert.size(); ++i)
        for (int k = 0; k < 3; ++k) d->points(Eigen::Index(i), k) = m.vert[i].P()[k];
    d->triangles.resize(Eigen::Index(m.face.size()), 3);
    for (size_t i = 0; i < m.face.size(); ++i)
        for (int k = 0; k < 3; ++k) d->triangles(Eigen::Index(i), k) = int(vcg::tri::Index(m, m.face[i].V(k)));
    if (d->load_mask & IoMask::IOM_VERTQUALITY)
        for (const auto& v : m.vert) d->vertex_quality.push_back(v.Q());
    return MeshFile(std::move(d));
}

MeshFormat MeshFile::format() const { return data_->format; }
const Points& MeshFile::points() const { return data_->points; }
const Triangles& MeshFile::triangles() const { return data_->triangles; }
bool MeshFile::has_stored_flags() const { return data_->has_stored_flags; }
const std::vector<int>& MeshFile::stored_selection() const { return data_->stored_selection; }
const std::vector<double>& MeshFile::vertex_quality() const { return data_->vertex_quality; }
const std::vector<std::string>& MeshFile::notes() const { return data_->notes; }

void MeshFile::write(const std::string& path, const Points& points, const std::vector<int>& selected_faces) {
    CliMesh& m = data_->mesh;
    if (points.rows() != Eigen::Index(m.vert.size()))
        throw Error("internal: " + std::to_string(points.rows()) + " points for " + std::to_string(m.vert.size()) +
                    " vertices");
    for (size_t i = 0; i < m.vert.size(); ++i)
        m.vert[i].P() = vcg::Point3d(points(Eigen::Index(i), 0), points(Eigen::Index(i), 1), points(Eigen::Index(i), 2));
    for (auto& f : m.face) f.ClearS();
    for (int i : selected_faces) m.face[size_t(i)].SetS();
    int mask = data_->load_mask;
    if (!selected_faces.empty() && require_format(path) == MeshFormat::Ply) mask |= IoMask::IOM_FACEFLAGS;
    save(m, path, mask);
}

void write_mesh(const std::string& path, const Mesh& mesh) {
    CliMesh m;
    auto vi = vcg::tri::Allocator<CliMesh>::AddVertices(m, size_t(mesh.points.rows()));
    for (Eigen::Index i = 0; i < mesh.points.rows(); ++i, ++vi)
        vi->P() = vcg::Point3d(mesh.points(i, 0), mesh.points(i, 1), mesh.points(i, 2));
    auto fi = vcg::tri::Allocator<CliMesh>::AddFaces(m, size_t(mesh.triangles.rows()));
    for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i, ++fi)
        for (int k = 0; k < 3; ++k) fi->V(k) = &m.vert[size_t(mesh.triangles(i, k))];
    save(m, path, IoMask::IOM_VERTCOORD | IoMask::IOM_FACEINDEX);
}

} // namespace geofilter::cli
