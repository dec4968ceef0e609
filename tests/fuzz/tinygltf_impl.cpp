// tinygltf compiled from its header for the fuzz build, so that the sanitizers and the
// coverage instrumentation see inside it (the normal build links Debian's library).
// TINYGLTF_NO_STB_IMAGE(_WRITE) come from CMakeLists.txt, for every file of the target.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
