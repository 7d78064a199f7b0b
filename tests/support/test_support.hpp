// What the test suites share: one clraster context per test process (programs are built once and
// reused across tests), rendering the same scene with clraster and with the OpenGL oracle, and
// image assertions that leave the reference, the result and a diff picture behind when they fail.
#pragma once

#include "clraster/clraster.hpp"
#include "io/image_compare.hpp"
#include "io/mesh.hpp"

#include <gtest/gtest.h>

#include <string>

namespace clraster::test {

// The context every test of the process shares (default options, device from CLRASTER_DEVICE).
Context& shared_context();

// Renders one draw of `mesh` into a width x height framebuffer cleared to opaque black and depth 1.
struct RenderResult {
  Image image;
  DrawStats stats;
};
RenderResult render_clraster(Context& context, const io::Mesh& mesh, const DrawState& state, int width, int height,
                             Topology topology = Topology::TriangleList);
Image render_gl(const io::Mesh& mesh, const DrawState& state, int width, int height,
                Topology topology = Topology::TriangleList);

// How close two renders of a scene must be.
struct Tolerance {
  double max_coverage_mismatch = 0;  // (only_a + only_b) / covered_either
  double max_colour_mismatch = 0;    // pixels in both beyond `threshold` / covered_both
  int threshold = 0;
  std::uint64_t max_count_mismatch_pixels = 0;  // overdraw pictures: pixels whose red count differs
  bool exact = false;                           // every byte equal
};
inline constexpr Tolerance kExact{0, 0, 0, 0, true};
inline constexpr Tolerance kNormalShading{0.002, 0.01, 8, ~0ull, false};

// Compares result against reference within the tolerance. On failure writes
// <test-output>/<test name>/{reference,result,diff}.png and adds a gtest failure that names them.
::testing::AssertionResult images_match(const Image& result, const Image& reference, const Tolerance& tolerance);

// The directory failing tests write their pictures to (created on demand).
std::string output_directory();

}  // namespace clraster::test
