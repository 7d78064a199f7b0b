#include "io/image_compare.hpp"

#include <algorithm>
#include <cstdlib>

#include <nlohmann/json.hpp>

namespace clraster::io {
namespace {

std::string size_text(const Image& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void check_comparable(const Image& a, const Image& b, int threshold) {
  for (const Image* image : {&a, &b}) {
    if (image->width < 0 || image->height < 0 ||
        image->rgba.size() != std::size_t(image->width) * image->height * 4) {
      throw InvalidArgument("image of " + size_text(*image) + " pixels has " +
                            std::to_string(image->rgba.size()) + " bytes of RGBA data");
    }
  }
  if (a.width != b.width || a.height != b.height) {
    throw InvalidArgument("cannot compare images of different sizes: " + size_text(a) + " and " +
                          size_text(b));
  }
  if (threshold < 0 || threshold > 255) {
    throw InvalidArgument("colour threshold " + std::to_string(threshold) + " is outside 0..255");
  }
}

bool is_covered(const std::uint8_t* pixel) { return (pixel[0] | pixel[1] | pixel[2]) != 0; }

// How one pixel of A relates to the same pixel of B; both compare_images and diff_image are built on it.
struct PixelDiff {
  bool covered_a;
  bool covered_b;
  bool red_differs;
  int max_channel_diff = 0;
  int abs_diff_sum = 0;  // over the four channels

  PixelDiff(const std::uint8_t* a, const std::uint8_t* b)
      : covered_a(is_covered(a)), covered_b(is_covered(b)), red_differs(a[0] != b[0]) {
    for (int c = 0; c < 4; ++c) {
      const int diff = std::abs(int(a[c]) - int(b[c]));
      max_channel_diff = std::max(max_channel_diff, diff);
      abs_diff_sum += diff;
    }
  }

  bool colour_mismatch(int threshold) const { return covered_a && covered_b && max_channel_diff > threshold; }
};

double ratio(std::uint64_t part, std::uint64_t whole) {
  return whole == 0 ? 0.0 : double(part) / double(whole);
}

}  // namespace

ImageComparison compare_images(const Image& a, const Image& b, int threshold) {
  check_comparable(a, b, threshold);
  ImageComparison result;
  result.width = a.width;
  result.height = a.height;
  result.pixels = std::uint64_t(a.width) * a.height;

  std::uint64_t abs_diff_total = 0;
  for (std::size_t i = 0; i < a.rgba.size(); i += 4) {
    const PixelDiff pixel(&a.rgba[i], &b.rgba[i]);
    result.covered_a += pixel.covered_a;
    result.covered_b += pixel.covered_b;
    result.covered_either += pixel.covered_a || pixel.covered_b;
    result.covered_both += pixel.covered_a && pixel.covered_b;
    result.only_a += pixel.covered_a && !pixel.covered_b;
    result.only_b += pixel.covered_b && !pixel.covered_a;
    result.colour_mismatch_pixels += pixel.colour_mismatch(threshold);
    result.differing_pixels += pixel.max_channel_diff > 0;
    result.count_mismatch_pixels += pixel.red_differs;
    result.max_channel_diff = std::max(result.max_channel_diff, pixel.max_channel_diff);
    abs_diff_total += pixel.abs_diff_sum;
  }
  result.coverage_mismatch = ratio(result.only_a + result.only_b, result.covered_either);
  result.colour_mismatch = ratio(result.colour_mismatch_pixels, result.covered_both);
  result.mean_abs_diff = ratio(abs_diff_total, result.pixels * 4);
  return result;
}

ImageComparison compare_images(const Image& a, const Image& b, const Tolerance& tolerance) {
  return compare_images(a, b, tolerance.exact ? 0 : tolerance.threshold);
}

bool within(const ImageComparison& c, const Tolerance& tolerance) {
  return tolerance.exact ? c.differing_pixels == 0
                         : c.coverage_mismatch <= tolerance.max_coverage_mismatch &&
                               c.colour_mismatch <= tolerance.max_colour_mismatch &&
                               c.count_mismatch_pixels <= tolerance.max_count_mismatch_pixels;
}

Image diff_image(const Image& a, const Image& b, int threshold) {
  check_comparable(a, b, threshold);
  Image picture{a.width, a.height, std::vector<std::uint8_t>(a.rgba.size())};
  for (std::size_t i = 0; i < a.rgba.size(); i += 4) {
    const PixelDiff pixel(&a.rgba[i], &b.rgba[i]);
    std::uint8_t* out = &picture.rgba[i];
    if (pixel.covered_a != pixel.covered_b) {
      const bool only_a = pixel.covered_a;
      out[0] = only_a ? 255 : 0;
      out[1] = only_a ? 0 : 255;
      out[2] = 255;
    } else if (pixel.colour_mismatch(threshold)) {
      const auto intensity = std::uint8_t(96 + 159 * pixel.max_channel_diff / 255);
      out[0] = out[1] = intensity;
      out[2] = 0;
    } else {
      // Rec. 601 luma weights in 8-bit fixed point (77 + 150 + 29 = 256), then a quarter of it so
      // that the marked pixels stand out against the scene.
      const std::uint8_t* source = &a.rgba[i];
      out[0] = out[1] = out[2] = std::uint8_t((77 * source[0] + 150 * source[1] + 29 * source[2]) >> 10);
    }
    out[3] = 255;
  }
  return picture;
}

std::string to_json(const ImageComparison& c) {
  const nlohmann::json json = {
      {"width", c.width},
      {"height", c.height},
      {"pixels", c.pixels},
      {"covered_a", c.covered_a},
      {"covered_b", c.covered_b},
      {"covered_either", c.covered_either},
      {"covered_both", c.covered_both},
      {"only_a", c.only_a},
      {"only_b", c.only_b},
      {"coverage_mismatch", c.coverage_mismatch},
      {"colour_mismatch_pixels", c.colour_mismatch_pixels},
      {"colour_mismatch", c.colour_mismatch},
      {"differing_pixels", c.differing_pixels},
      {"max_channel_diff", c.max_channel_diff},
      {"mean_abs_diff", c.mean_abs_diff},
      {"count_mismatch_pixels", c.count_mismatch_pixels},
  };
  return json.dump();
}

}  // namespace clraster::io
