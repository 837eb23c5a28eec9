// tinygltf as sepal compiles it (offline/mesh/tiny_gltf_impl.cpp holds the implementation):
// every file that includes it must see the same configuration. Images are never decoded:
// sepal reads meshes only.
#pragma once
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
