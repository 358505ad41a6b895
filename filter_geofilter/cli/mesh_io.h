// Reading and writing meshes for the command-line tool (PLY, OBJ, OFF, STL; XYZ for point
// clouds) with readers
// and writers of its own (mesh_io.cpp says why), so that the tool builds without MeshLab's
// sources. The rest of the tool sees the core's plain arrays.
#pragma once

#include "core/types.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace geofilter::cli {

// A file with vertices and no faces (PLY, OBJ, OFF) is a point cloud, as XYZ always is.
enum class MeshFormat { Ply, Obj, Off, Stl, Xyz };

// By the file name's extension, case-insensitively; nullopt for anything else.
std::optional<MeshFormat> format_of(const std::string& path);
const char* format_name(MeshFormat format);
const char* supported_formats();  // for messages: "PLY, OBJ, OFF, STL or XYZ (.ply, .obj, .off, .stl, .xyz)"

class MeshFile {
public:
    // Throws Error naming the file and the reason. STL stores every triangle with its
    // own three corners: those are welded (bit-identical positions merged) so that the
    // mesh is connected, as the Laplacian needs.
    static MeshFile read(const std::string& path);

    MeshFile(MeshFile&&) noexcept;
    MeshFile& operator=(MeshFile&&) noexcept;
    ~MeshFile();

    MeshFormat format() const;
    const Points& points() const;
    const Triangles& triangles() const;
    // The file carried MeshLab's (vcglib's) face flags (PLY "property int flags" on faces).
    bool has_stored_flags() const;
    // Faces whose stored flags have the selection bit; empty without stored flags.
    const std::vector<int>& stored_selection() const;
    // Per-vertex quality as the file stores it (PLY "property float quality" on vertices);
    // empty when the file has none.
    const std::vector<double>& vertex_quality() const;
    // What reading did that a user should know (welding, triangulated polygons, dropped flags).
    const std::vector<std::string>& notes() const;

    // Writes the mesh with `points` in place of the read ones. Written in the format that was
    // read, it keeps the attributes read with it (PLY: every scalar vertex and face property;
    // OFF: colours and texture coordinates); normals are recomputed. A PLY output
    // stores `selected_faces` as face flags when there are any. Throws Error.
    // A point cloud (no faces) is written with `cloud_normals` when given: PLY nx ny nz, OBJ vn
    // lines, XYZ's last three columns. Refuses a cloud as STL and a mesh as XYZ (the faces
    // would be lost).
    void write(const std::string& path, const Points& points, const std::vector<int>& selected_faces,
               const Points* cloud_normals = nullptr);

private:
    struct Data;
    explicit MeshFile(std::unique_ptr<Data> data);
    std::unique_ptr<Data> data_;
};

// Writes a mesh built by the core (e.g. the measured ellipsoid). Throws Error.
void write_mesh(const std::string& path, const Mesh& mesh);

} // namespace geofilter::cli
