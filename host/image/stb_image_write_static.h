// stb_image_write, compiled into the file that includes this (once per file, as its
// implementation): static, so the copies in several files, and the one a library such as
// tinygltf may bring, can never clash; its own warnings off. png.cpp writes the project's PNGs
// with it; tests include it to make image files for the readers.
#pragma once

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image_write.h>
#pragma GCC diagnostic pop
