// Replays tests/fuzz/regressions/readers/ through the command-line tool's mesh readers,
// the same way fuzz_mesh_readers does: first byte = format, the rest = file contents.
#include "core/types.h"
#include "mesh_io.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

TEST(ReaderRegressions, EverySavedFileIsReadOrRefusedCleanly) {
    const std::filesystem::path dir(GEOFILTER_READER_REGRESSIONS);
    ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
    const char* extensions[] = {".ply", ".obj", ".off", ".stl"};
    int replayed = 0, read = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        std::ifstream in(entry.path(), std::ios::binary);
        const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (bytes.empty()) continue;
        const std::filesystem::path file = std::filesystem::temp_directory_path() /
            ("geofilter-reader-" + std::to_string(getpid()) + extensions[static_cast<unsigned char>(bytes[0]) % 4]);
        std::ofstream(file, std::ios::binary).write(bytes.data() + 1, static_cast<std::streamsize>(bytes.size() - 1));
        SCOPED_TRACE(entry.path().filename().string());
        try {
            const auto mesh = geofilter::cli::MeshFile::read(file.string());
            EXPECT_LT(mesh.triangles().maxCoeff(), mesh.points().rows());
            ++read;
        } catch (const geofilter::Error&) {
        }
        std::filesystem::remove(file);
        ++replayed;
    }
    EXPECT_GT(replayed, 0);
    EXPECT_GE(read, 4) << "the four seeds (one per format) must read";
}
