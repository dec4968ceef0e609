// tinygltf compiled from its header for the fuzz build, so that the sanitizers and the
// coverage instrumentation see inside it (the normal build links Debian's library).
// Images are never decoded (load_gltf.cpp installs its own image callback).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
