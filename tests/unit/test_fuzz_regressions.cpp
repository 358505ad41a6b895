// Replays every input in tests/fuzz/regressions/ (crashes the fuzzer found, and a few
// seeds), so that a fixed crash stays fixed in the ordinary test run.
#include "fuzz_core_input.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

TEST(FuzzRegressions, EverySavedInputRunsCleanly) {
    const std::filesystem::path dir(GEOFILTER_FUZZ_REGRESSIONS);
    ASSERT_TRUE(std::filesystem::is_directory(dir)) << dir;
    int replayed = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (!entry.is_regular_file() || entry.path().extension() == ".md") continue;
        std::ifstream in(entry.path(), std::ios::binary);
        const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        SCOPED_TRACE(entry.path().filename().string());
        geofilter::fuzz::run_core_on_bytes(bytes.data(), bytes.size());  // aborts on a broken invariant
        ++replayed;
    }
    EXPECT_GT(replayed, 0) << "no saved inputs in " << dir;
}
