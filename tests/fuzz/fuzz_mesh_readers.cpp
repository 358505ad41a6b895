// libFuzzer entry: random files through the command-line tool's mesh readers. The first
// byte picks the format (the readers dispatch on the file name); the rest is the file.
#include "core/types.h"
#include "mesh_io.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    static const char* extensions[] = {".ply", ".obj", ".off", ".stl"};
    const std::string path = "/tmp/geofilter-fuzz-" + std::to_string(getpid()) + extensions[data[0] % 4];
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    std::fwrite(data + 1, 1, size - 1, f);
    std::fclose(f);
    try {
        const auto mesh = geofilter::cli::MeshFile::read(path);
        // Whatever was read must be a consistent mesh.
        for (Eigen::Index t = 0; t < mesh.triangles().rows(); ++t)
            for (int k = 0; k < 3; ++k)
                if (mesh.triangles()(t, k) < 0 || mesh.triangles()(t, k) >= mesh.points().rows()) std::abort();
    } catch (const geofilter::Error&) {
    }
    std::remove(path.c_str());
    return 0;
}
