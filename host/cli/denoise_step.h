// `penumbra render --denoise` (SCENE_FORMAT.md "Output"): Open Image Denoise through the
// Python module's penumbra.denoise_exr, run as `PYTHON -m penumbra.denoise_exr`, where PYTHON
// is $PENUMBRA_PYTHON or else python3 from PATH. The C++ program links no denoiser: pyoidn
// (PyPI) is where OIDN with its CPU device comes from, so the Python side is its one home.
#pragma once

#include <filesystem>
#include <string>

namespace penumbra {

// Before rendering: throws InputError (exit 2) with one line naming what is missing (the
// interpreter, the penumbra module or pyoidn) and how to install it.
void checkDenoiser();

// After rendering: `noisy` (an EXR this command wrote) -> `output`, the same layers plus
// "denoised", written whole or not at all. Throws std::runtime_error with the denoiser's
// one-line message when it fails.
void denoiseExr(const std::filesystem::path& noisy, const std::filesystem::path& output);

}  // namespace penumbra
