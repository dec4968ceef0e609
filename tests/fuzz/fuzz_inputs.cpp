// The fuzz target's body: one input through the scene, job-file, glTF or mesh-file reader,
// exactly as `penumbra render`, `penumbra batch`, `merge` and `compare` read them
// (loadScene, loadJobFile, readMeshFile, readImageFile, readExrHeader and readExr).
#include "fuzz_inputs.h"

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <fstream>

#include "batch/job_file.h"
#include "core/errors.h"
#include "image/image.h"
#include "image/image_file.h"
#include "scene/load.h"
#include "scene/mesh_file.h"

namespace penumbra::fuzz {
namespace {

namespace fs = std::filesystem;

// A folder of this process's own, removed at exit.
struct Folder {
    fs::path path = fs::temp_directory_path() / ("penumbra-fuzz-" + std::to_string(::getpid()));
    Folder() { fs::create_directories(path); }
    ~Folder() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

const fs::path& folder() {
    static const Folder dir;
    return dir.path;
}

// Images of up to 2^20 pixels: the readers' limits are checked from the header either way
// (tests cover the real limits), and a mutant that forges a large size is refused in
// microseconds instead of decoding for seconds, so the fuzzer explores more inputs.
constexpr uint64_t kFuzzMaxPixels = uint64_t(1) << 20;

void readImage(const fs::path& file) { readImageFile(file, file.string(), ColorDecode::Srgb, kFuzzMaxPixels); }

// As `penumbra merge` and `compare` read an EXR: the header's checks first, then pixels.
void readExrAsMergeInput(const fs::path& file) {
    Image header = readExrHeader(file);
    if (uint64_t(header.width) * header.height > kFuzzMaxPixels) return;
    checkMergeHeaders({header}, {file.string()});
    Image image = readExr(file);
    mergeImages({image}, {file.string()});
}

}  // namespace

std::string readOne(const uint8_t* data, size_t size) {
    if (size == 0) return "";
    const char kind = char(data[0]);
    std::string body(reinterpret_cast<const char*>(data + 1), size - 1);
    const char* name = kind == 'j'   ? "jobs.json"
                       : kind == 'g' ? (body.rfind("glTF", 0) == 0 ? "model.glb" : "model.gltf")
                       : kind == 'o' ? "mesh.obj"
                       : kind == 'p' ? "mesh.ply"
                       : kind == 'i' ? "image.img"
                       : kind == 'x' ? "image.exr"
                                     : "scene.json";
    fs::path file = folder() / name;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << body;
    try {
        if (kind == 'j') {
            loadJobFile(file);
        } else if (kind == 'o' || kind == 'p') {
            readMeshFile(file, file.string());
        } else if (kind == 'i') {
            readImage(file);
        } else if (kind == 'x') {
            readExrAsMergeInput(file);
        } else {
            loadScene(file);
        }
    } catch (const InputError&) {
        return "";
    } catch (const std::exception& e) {
        return std::string("not an InputError: ") + e.what();
    }
    return "";
}

}  // namespace penumbra::fuzz
