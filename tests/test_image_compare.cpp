// compare_images, diff_image and the PNG files, on small images whose answers are worked out by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/image_compare.hpp"
#include "io/image_io.hpp"

namespace {

using clraster::Image;
using clraster::io::compare_images;
using clraster::io::diff_image;
using Rgba = std::array<std::uint8_t, 4>;

constexpr Rgba kBackground{0, 0, 0, 255};

Image filled(int width, int height, Rgba colour = kBackground) {
  Image image{width, height, {}};
  for (int i = 0; i < width * height; ++i) image.rgba.insert(image.rgba.end(), colour.begin(), colour.end());
  return image;
}

void set(Image& image, int x, int y, Rgba colour) {
  std::copy(colour.begin(), colour.end(), image.rgba.begin() + (std::size_t(y) * image.width + x) * 4);
}

Rgba get(const Image& image, int x, int y) {
  const auto* p = &image.rgba[(std::size_t(y) * image.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

// The message of the clraster::Error that `action` throws; fails the test when it throws none.
std::string error_message(const std::function<void()>& action) {
  try {
    action();
  } catch (const clraster::Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected a clraster::Error";
  return {};
}

// A fresh directory per test under gtest's temporary directory.
std::filesystem::path scratch_dir() {
  const auto* test = testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::path(testing::TempDir()) /
             ("clraster_image_io_" + std::to_string(getpid()) + "_" + test->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(CompareImages, IdenticalImagesAgreeEverywhere) {
  Image a = filled(3, 2);
  set(a, 1, 1, {10, 20, 30, 255});
  const auto c = compare_images(a, a);
  EXPECT_EQ(c.width, 3);
  EXPECT_EQ(c.height, 2);
  EXPECT_EQ(c.pixels, 6u);
  EXPECT_EQ(c.covered_a, 1u);
  EXPECT_EQ(c.covered_both, 1u);
  EXPECT_EQ(c.only_a + c.only_b + c.differing_pixels + c.colour_mismatch_pixels + c.count_mismatch_pixels,
            0u);
  EXPECT_EQ(c.coverage_mismatch, 0.0);
  EXPECT_EQ(c.colour_mismatch, 0.0);
  EXPECT_EQ(c.max_channel_diff, 0);
  EXPECT_EQ(c.mean_abs_diff, 0.0);
}

TEST(CompareImages, CoverageOnlyInAAndOnlyInB) {
  // x:       0            1              2            3
  // A:   (200,0,0)    (0,0,50)       background   (0,0,0,0): alpha only, not covered
  // B:   background   (0,0,50)       (0,10,0)     background
  Image a = filled(4, 1);
  Image b = filled(4, 1);
  set(a, 0, 0, {200, 0, 0, 255});
  set(a, 1, 0, {0, 0, 50, 255});
  set(b, 1, 0, {0, 0, 50, 255});
  set(b, 2, 0, {0, 10, 0, 255});
  set(a, 3, 0, {0, 0, 0, 0});
  const auto c = compare_images(a, b);
  EXPECT_EQ(c.covered_a, 2u);
  EXPECT_EQ(c.covered_b, 2u);
  EXPECT_EQ(c.covered_either, 3u);
  EXPECT_EQ(c.covered_both, 1u);
  EXPECT_EQ(c.only_a, 1u);
  EXPECT_EQ(c.only_b, 1u);
  EXPECT_DOUBLE_EQ(c.coverage_mismatch, 2.0 / 3.0);
  EXPECT_EQ(c.colour_mismatch_pixels, 0u);  // the one pixel covered by both is equal
  EXPECT_EQ(c.differing_pixels, 3u);        // x = 0, 2 and the alpha of x = 3
  EXPECT_EQ(c.count_mismatch_pixels, 1u);   // only x = 0 differs in red
  EXPECT_EQ(c.max_channel_diff, 255);       // the alpha at x = 3
  EXPECT_DOUBLE_EQ(c.mean_abs_diff, (200.0 + 10.0 + 255.0) / 16.0);
}

TEST(CompareImages, ColourThresholdIsInclusive) {
  // Both pixels covered in both images: x = 0 differs by exactly the threshold (8) in green, x = 1 by
  // one more in blue, x = 2 is equal.
  Image a = filled(3, 1, {100, 100, 100, 255});
  Image b = a;
  set(b, 0, 0, {100, 108, 100, 255});
  set(b, 1, 0, {100, 100, 91, 255});
  const auto c = compare_images(a, b, 8);
  EXPECT_EQ(c.covered_both, 3u);
  EXPECT_EQ(c.colour_mismatch_pixels, 1u);
  EXPECT_DOUBLE_EQ(c.colour_mismatch, 1.0 / 3.0);
  EXPECT_EQ(c.differing_pixels, 2u);
  EXPECT_EQ(c.max_channel_diff, 9);
  EXPECT_DOUBLE_EQ(c.mean_abs_diff, (8.0 + 9.0) / 12.0);
  EXPECT_EQ(c.count_mismatch_pixels, 0u);
  EXPECT_EQ(c.coverage_mismatch, 0.0);

  EXPECT_EQ(compare_images(a, b, 7).colour_mismatch_pixels, 2u);
  EXPECT_EQ(compare_images(a, b, 9).colour_mismatch_pixels, 0u);
}

TEST(CompareImages, CountsRedDifferencesAsFragmentCountMismatches) {
  // Overdraw pictures: red = number of fragments. One pixel drawn twice instead of once.
  Image a = filled(2, 2, {1, 0, 0, 255});
  Image b = a;
  set(b, 1, 0, {2, 0, 0, 255});
  const auto c = compare_images(a, b);
  EXPECT_EQ(c.count_mismatch_pixels, 1u);
  EXPECT_EQ(c.colour_mismatch_pixels, 0u);  // 1 is within the threshold
}

TEST(CompareImages, ToleranceBoundsAreInclusive) {
  using clraster::io::kExact;
  using clraster::io::kNormalShading;
  using clraster::io::within;
  // 1000 pixels covered in A, 2 of them not in B; of the 998 covered in both, 9 are 9 apart in red
  // (0.9%) and 1 exactly 8 apart in green.
  Image a = filled(100, 10, {100, 100, 100, 255});
  Image b = a;
  set(b, 0, 0, kBackground);
  set(b, 1, 0, kBackground);
  for (int x = 0; x < 9; ++x) set(b, x, 1, {109, 100, 100, 255});
  set(b, 0, 2, {100, 108, 100, 255});
  const auto c = compare_images(a, b, kNormalShading);
  EXPECT_DOUBLE_EQ(c.coverage_mismatch, 0.002);
  EXPECT_EQ(c.colour_mismatch_pixels, 9u);
  EXPECT_TRUE(within(c, kNormalShading)) << clraster::io::to_json(c);
  EXPECT_FALSE(within(c, {0.0019, 0.01, 8, ~0ull, false}));
  EXPECT_FALSE(within(c, {0.002, 0.009, 8, ~0ull, false}));
  EXPECT_FALSE(within(c, {0.002, 0.01, 8, 10, false})) << "11 pixels differ in red";
  EXPECT_TRUE(within(c, {0.002, 0.01, 8, 11, false}));
  // Exact: the comparison is made at threshold 0, and any differing byte fails it.
  EXPECT_EQ(compare_images(a, b, kExact).colour_mismatch_pixels, 10u);
  EXPECT_FALSE(within(compare_images(a, b, kExact), kExact));
  EXPECT_TRUE(within(compare_images(a, a, kExact), kExact));
}

TEST(CompareImages, SizeMismatchNamesBothSizes) {
  const std::string message = error_message([] { compare_images(filled(4, 3), filled(3, 4)); });
  EXPECT_NE(message.find("4x3"), std::string::npos) << message;
  EXPECT_NE(message.find("3x4"), std::string::npos) << message;
}

TEST(CompareImages, RejectsThresholdOutsideByteRange) {
  EXPECT_THROW(compare_images(filled(1, 1), filled(1, 1), -1), clraster::InvalidArgument);
  EXPECT_THROW(compare_images(filled(1, 1), filled(1, 1), 256), clraster::InvalidArgument);
}

TEST(CompareImages, JsonHoldsEveryField) {
  Image a = filled(2, 1);
  Image b = filled(2, 1);
  set(a, 0, 0, {50, 50, 50, 255});
  const auto json = nlohmann::json::parse(clraster::io::to_json(compare_images(a, b)));
  EXPECT_EQ(json.size(), 16u);
  EXPECT_EQ(json["width"], 2);
  EXPECT_EQ(json["only_a"], 1);
  EXPECT_EQ(json["coverage_mismatch"], 1.0);
  EXPECT_EQ(json["max_channel_diff"], 50);
  EXPECT_DOUBLE_EQ(json["mean_abs_diff"].get<double>(), 150.0 / 8.0);
}

TEST(DiffImage, MarksEachKindOfDifference) {
  // x = 0: only in A; 1: only in B; 2: colour differs by 255; 3: agrees; 4: differs within threshold.
  Image a = filled(5, 1, {200, 200, 200, 255});
  Image b = a;
  set(a, 1, 0, kBackground);
  set(b, 0, 0, kBackground);
  set(b, 2, 0, {200, 200, 200, 0});
  set(b, 4, 0, {204, 200, 200, 255});
  const Image d = diff_image(a, b, 8);
  ASSERT_EQ(d.width, 5);
  ASSERT_EQ(d.height, 1);
  EXPECT_EQ(get(d, 0, 0), (Rgba{255, 0, 255, 255}));
  EXPECT_EQ(get(d, 1, 0), (Rgba{0, 255, 255, 255}));
  EXPECT_EQ(get(d, 2, 0), (Rgba{255, 255, 0, 255}));  // 96 + 159 * 255 / 255
  const std::uint8_t grey = (77 * 200 + 150 * 200 + 29 * 200) >> 10;  // A's luma / 4 = 50
  EXPECT_EQ(get(d, 3, 0), (Rgba{grey, grey, grey, 255}));
  EXPECT_EQ(get(d, 4, 0), (Rgba{grey, grey, grey, 255}));
}

TEST(DiffImage, ColourIntensityGrowsWithTheDifference) {
  Image a = filled(2, 1, {100, 100, 100, 255});
  Image b = a;
  set(b, 0, 0, {110, 100, 100, 255});
  set(b, 1, 0, {100, 100, 200, 255});
  const Image d = diff_image(a, b, 8);
  EXPECT_EQ(get(d, 0, 0), (Rgba{102, 102, 0, 255}));  // 96 + 159 * 10 / 255 = 102
  EXPECT_EQ(get(d, 1, 0), (Rgba{158, 158, 0, 255}));  // 96 + 159 * 100 / 255 = 158
}

TEST(Png, RoundTripKeepsEveryPixel) {
  Image image{7, 5, {}};
  for (int i = 0; i < 7 * 5 * 4; ++i) image.rgba.push_back(std::uint8_t(i * 37 + 11));
  const std::string path = (scratch_dir() / "round_trip.png").string();
  clraster::io::save_png(path, image);
  const Image loaded = clraster::io::load_png(path);
  EXPECT_EQ(loaded.width, 7);
  EXPECT_EQ(loaded.height, 5);
  EXPECT_EQ(loaded.rgba, image.rgba);
}

TEST(Png, LoadingAMissingFileNamesThePath) {
  const std::string path = (scratch_dir() / "missing.png").string();
  const std::string message = error_message([&] { clraster::io::load_png(path); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("No such file"), std::string::npos) << message;
}

TEST(Png, LoadingANonImageNamesThePath) {
  const std::string path = (scratch_dir() / "not_an_image.png").string();
  std::ofstream(path) << "this is text, not a picture\n";
  const std::string message = error_message([&] { clraster::io::load_png(path); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
}

TEST(Png, SavingIntoAMissingDirectoryNamesThePath) {
  const std::string path = "/nonexistent-dir/x.png";
  const std::string message = error_message([&] { clraster::io::save_png(path, filled(2, 2)); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("No such file"), std::string::npos) << message;
}

TEST(Png, SavingInconsistentImageIsRejected) {
  const std::string path = (scratch_dir() / "bad.png").string();
  EXPECT_THROW(clraster::io::save_png(path, Image{4, 4, std::vector<std::uint8_t>(10)}),
               clraster::InvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
