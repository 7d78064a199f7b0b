#include "io/image_io.hpp"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

namespace clraster::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Opens the file ourselves rather than handing stb a path, so that failures carry the real
// errno reason ("No such file or directory", "Permission denied") instead of stb's generic one.
File open_or_throw(const std::string& path, const char* mode, const char* verb) {
  File file(std::fopen(path.c_str(), mode));
  if (!file) throw Error(std::string("cannot ") + verb + " " + path + ": " + std::strerror(errno));
  return file;
}

// Where stbi_write_png_to_func streams the encoded bytes; remembers whether any write failed.
struct PngSink {
  std::FILE* file;
  int error = 0;

  static void write(void* context, void* data, int size) {
    auto& sink = *static_cast<PngSink*>(context);
    if (sink.error == 0 && std::fwrite(data, 1, size, sink.file) != static_cast<std::size_t>(size)) {
      sink.error = errno;
    }
  }
};

using Pixels = std::unique_ptr<stbi_uc, decltype(&stbi_image_free)>;

// What stbi_load* decoded as four channels (null when it failed).
struct Decoded {
  Pixels pixels{nullptr, &stbi_image_free};
  int width = 0, height = 0;

  Image image() const { return Image{width, height, {pixels.get(), pixels.get() + std::size_t(width) * height * 4}}; }
};

}  // namespace

Image load_png(const std::string& path) {
  File file = open_or_throw(path, "rb", "read");
  Decoded decoded;
  int channels_in_file = 0;
  decoded.pixels.reset(stbi_load_from_file(file.get(), &decoded.width, &decoded.height, &channels_in_file, 4));
  if (!decoded.pixels) {
    // A read error (a directory, an I/O error) is the system's to explain; anything else is stb's.
    if (std::ferror(file.get())) throw Error("cannot read " + path + ": " + std::strerror(errno));
    throw Error("cannot decode " + path + ": " + stbi_failure_reason());
  }
  return decoded.image();
}

Image decode_image(std::span<const std::byte> encoded, const std::string& name) {
  if (encoded.size() > std::size_t{std::numeric_limits<int>::max()}) {
    throw Error("cannot decode " + name + ": " + std::to_string(encoded.size()) + " bytes are too many");
  }
  Decoded decoded;
  int channels_in_file = 0;
  decoded.pixels.reset(stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(encoded.data()),
                                             static_cast<int>(encoded.size()), &decoded.width, &decoded.height,
                                             &channels_in_file, 4));
  if (!decoded.pixels) throw Error("cannot decode " + name + ": " + stbi_failure_reason());
  return decoded.image();
}

// Throws InvalidArgument, for writing `what`, when the image's size and pixel data disagree.
void require_consistent(const Image& image, const std::string& what) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != std::size_t(image.width) * image.height * 4) {
    throw InvalidArgument("cannot write " + what + ": image of " + std::to_string(image.width) + "x" +
                          std::to_string(image.height) + " pixels has " + std::to_string(image.rgba.size()) +
                          " bytes of RGBA data");
  }
}

void save_png(const std::string& path, const Image& image) {
  require_consistent(image, path);
  File file = open_or_throw(path, "wb", "write");
  PngSink sink{file.get()};
  const int encoded = stbi_write_png_to_func(&PngSink::write, &sink, image.width, image.height, 4,
                                             image.rgba.data(), image.width * 4);
  if (std::fflush(file.get()) != 0 && sink.error == 0) sink.error = errno;
  if (sink.error != 0) throw Error("cannot write " + path + ": " + std::strerror(sink.error));
  if (!encoded) throw Error("cannot write " + path + ": PNG encoding failed");
}

std::vector<std::byte> encode_png(const Image& image) {
  require_consistent(image, "a PNG");
  std::vector<std::byte> encoded;
  const auto append = [](void* context, void* data, int size) {
    auto& bytes = *static_cast<std::vector<std::byte>*>(context);
    const auto* first = static_cast<const std::byte*>(data);
    bytes.insert(bytes.end(), first, first + size);
  };
  if (!stbi_write_png_to_func(append, &encoded, image.width, image.height, 4, image.rgba.data(), image.width * 4)) {
    throw Error("PNG encoding failed");
  }
  return encoded;
}

}  // namespace clraster::io
