// libFuzzer entry: random meshes and parameters into the core (scripts/fuzz.sh runs it).
#include "fuzz_core_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    geofilter::fuzz::run_core_on_bytes(data, size);
    return 0;
}
