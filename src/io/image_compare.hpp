// Comparing two renderings of the same scene (clraster against the OpenGL oracle, or a run against
// a saved reference) pixel by pixel.
//
// A pixel is "covered" when any of its R, G, B channels is non-zero: the pictures compared are drawn
// over an opaque black background, so coverage differences show which pixels a rasterizer wrote.
#pragma once

#include <cstdint>
#include <string>

#include "clraster/clraster.hpp"

namespace clraster::io {

struct ImageComparison {
  int width = 0;
  int height = 0;
  std::uint64_t pixels = 0;
  std::uint64_t covered_a = 0;
  std::uint64_t covered_b = 0;
  std::uint64_t covered_either = 0;
  std::uint64_t covered_both = 0;
  std::uint64_t only_a = 0;  // covered in A, not in B
  std::uint64_t only_b = 0;
  double coverage_mismatch = 0;  // (only_a + only_b) / covered_either; 0 when nothing is covered
  // Covered in both, and some RGBA channel differs by more than the threshold.
  std::uint64_t colour_mismatch_pixels = 0;
  double colour_mismatch = 0;  // colour_mismatch_pixels / covered_both; 0 when covered_both is 0
  std::uint64_t differing_pixels = 0;  // any channel differs at all, covered or not
  int max_channel_diff = 0;
  double mean_abs_diff = 0;  // over all four channels of all pixels
  // Red channels differ. In overdraw pictures (Additive blending of Constant 1/255) red counts the
  // fragments drawn at the pixel, so this is the number of pixels drawn a different number of times.
  std::uint64_t count_mismatch_pixels = 0;
};

// Compares two RGBA8 images of the same size; `threshold` (0..255) is the largest channel difference
// of a covered pixel that still counts as the same colour. Throws clraster::InvalidArgument (a
// clraster::Error) when the sizes differ or the threshold is out of range.
ImageComparison compare_images(const Image& a, const Image& b, int threshold = 8);

// How close two renders of one scene must be: the conformance tests' thresholds, which the
// benchmarks hold their pictures to as well.
struct Tolerance {
  double max_coverage_mismatch = 0;  // (only_a + only_b) / covered_either
  double max_colour_mismatch = 0;    // pixels in both beyond `threshold` / covered_both
  int threshold = 0;
  std::uint64_t max_count_mismatch_pixels = 0;  // overdraw pictures: pixels whose red count differs
  bool exact = false;                           // every byte equal
};
inline constexpr Tolerance kExact{0, 0, 0, 0, true};
// The core pipeline's: clraster and OpenGL agree on all but 0.2% of the covered pixels, and on the
// colour (within 8/255) of all but 1% of those both cover.
inline constexpr Tolerance kNormalShading{0.002, 0.01, 8, ~0ull, false};

// compare_images at the tolerance's threshold (0 when exact), and whether that comparison is
// within the tolerance.
ImageComparison compare_images(const Image& a, const Image& b, const Tolerance& tolerance);
bool within(const ImageComparison& comparison, const Tolerance& tolerance);

// A picture of where A and B differ, the size of both. Legend:
//   grey (A's luminance at a quarter brightness)  pixels that agree (colour within the threshold)
//   magenta (255, 0, 255)                          covered only in A
//   cyan    (0, 255, 255)                          covered only in B
//   yellow  (I, I, 0)                              covered in both, colour differs by more than the
//                                                  threshold; I = 96 + 159 * max channel diff / 255
// Alpha is 255 everywhere. Throws as compare_images does.
Image diff_image(const Image& a, const Image& b, int threshold = 8);

// All fields of the comparison as one JSON object, keyed by the field names.
std::string to_json(const ImageComparison& comparison);

}  // namespace clraster::io
