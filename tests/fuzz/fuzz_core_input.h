// Turns arbitrary bytes into a mesh, a selection and filter parameters, and runs them
// through the same path every adapter uses. Shared by the libFuzzer target and the unit
// test that replays saved inputs, so a crash found once stays a test.
#pragma once

#include <cstddef>
#include <cstdint>

namespace geofilter::fuzz {

// Returns normally for any input; anything but a geofilter::Error escaping, or a result
// that breaks an invariant, aborts.
void run_core_on_bytes(const uint8_t* data, size_t size);

} // namespace geofilter::fuzz
