// tinygltf's implementation (Debian libtinygltf-dev ships the header), compiled once here with
// the project's flags and sanitizers instead of linking Debian's shared build.
#define TINYGLTF_IMPLEMENTATION
#include "mesh/tiny_gltf.h"
