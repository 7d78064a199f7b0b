// Reading and writing pictures as files (stb_image / stb_image_write).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "clraster/clraster.hpp"

namespace clraster::io {

// Reads any image file stb_image understands (PNG, JPEG, BMP, TGA, ...) as RGBA8, rows top to
// bottom. Throws clraster::Error naming the path and why it could not be read or decoded.
clraster::Image load_png(const std::string& path);

// The same from an image file's bytes in memory (an image embedded in a model file). Throws
// clraster::Error naming `name` and why the bytes could not be decoded.
clraster::Image decode_image(std::span<const std::byte> encoded, const std::string& name);

// Writes an RGBA8 image as PNG, replacing the file atomically (write_file_atomically). Throws
// clraster::InvalidArgument when the image's size and pixel data disagree, and clraster::Error
// naming the path and the system's reason when the file cannot be written.
void save_png(const std::string& path, const clraster::Image& image);

// Replaces the file at `path` with `bytes`, or leaves it untouched: the bytes are written to a
// temporary file beside it, synced and renamed over it; on any failure the temporary file is
// removed. Throws clraster::Error naming the path and the system's reason.
void write_file_atomically(const std::string& path, std::span<const std::byte> bytes);

// The same PNG file's bytes, in memory (as a model file embeds an image). Throws InvalidArgument for
// an inconsistent image.
std::vector<std::byte> encode_png(const clraster::Image& image);

}  // namespace clraster::io
