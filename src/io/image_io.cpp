#include "io/image_io.hpp"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

void save_png(const std::string& path, const Image& image) {
  require_consistent(image, path);
  write_file_atomically(path, encode_png(image));
}

namespace {

void write_all(int fd, std::span<const std::byte> bytes, const std::function<void(int)>& fail) {
  for (std::size_t written = 0; written < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(n < 0 ? errno : EIO);
    written += static_cast<std::size_t>(n);
  }
}

}  // namespace

// The bytes go to a new file beside `path` (same directory, so the rename cannot cross file
// systems), are flushed to the disk, and replace `path` in one rename: a reader sees the old file or
// the new one, never a part, and a failure at any step leaves the old one as it was. A path that is
// not a regular file (/dev/stdout, a FIFO) is written in place: there is no file to keep.
void write_file_atomically(const std::string& path, std::span<const std::byte> bytes) {
  const auto fail = [&](int error) { throw Error("cannot write " + path + ": " + std::strerror(error)); };
  struct stat existing {};
  const bool exists = ::stat(path.c_str(), &existing) == 0;
  if (exists && S_ISDIR(existing.st_mode)) fail(EISDIR);
  if (exists && !S_ISREG(existing.st_mode)) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) fail(errno);
    write_all(fd, bytes, [&](int error) {
      ::close(fd);
      fail(error);
    });
    if (::close(fd) != 0) fail(errno);
    return;
  }
  static std::atomic<unsigned> sequence{0};
  std::string temporary = path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(sequence++);
  // O_EXCL: never someone else's file; mode 0666 less the umask, as a plain open would create it.
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail(errno);
  const auto abandon = [&](int error) {
    ::close(fd);
    ::unlink(temporary.c_str());
    fail(error);
  };
  // A file being replaced keeps its permissions.
  if (exists && ::fchmod(fd, existing.st_mode & 07777) != 0) abandon(errno);
  write_all(fd, bytes, abandon);
  if (::fsync(fd) != 0) abandon(errno);
  if (::close(fd) != 0) {
    ::unlink(temporary.c_str());
    fail(errno);
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    fail(error);
  }
}

}  // namespace clraster::io
