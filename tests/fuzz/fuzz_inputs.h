// One fuzz input through Penumbra's readers: the first byte picks the reader ('s' scene
// file, 'j' job file read and expanded, 'g' glTF model, .glb when the rest starts with
// "glTF", 'o' OBJ mesh, 'p' PLY mesh, 'i' image file as a texture reads it: PNG, JPEG,
// Radiance HDR or OpenEXR told by its first bytes, 'x' OpenEXR as merge and compare read
// it: header, then pixels, then merge's checks), the rest is the file. Shared by the libFuzzer target (tools/dev/fuzz) and the seeded mutation loop in
// the test suite (test_fuzz.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace penumbra::fuzz {

// Writes the file into a private temporary folder and reads it. Returns "" when the
// input was read or refused with an InputError (both fine), else what went wrong (an
// exception that is not an InputError: bad input must always exit 2). Crashes, sanitizer
// reports and hangs are found by the caller's process and tools.
std::string readOne(const uint8_t* data, size_t size);

}  // namespace penumbra::fuzz
