// What the test suites share: one clraster context per test process (programs are built once and
// reused across tests), rendering the same scene with clraster and with the OpenGL oracle, and
// image assertions that leave the reference, the result and a diff picture behind when they fail.
#pragma once

#include "clraster/clraster.hpp"

#include <CL/opencl.hpp>
#include "io/image_compare.hpp"
#include "io/mesh.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clraster::test {

// The context every test of the process shares (default options, device from CLRASTER_DEVICE).
Context& shared_context();
// The same with the work-group shape given: the shared context for WorkGroupShape::Device, else one
// more context, shared too, with the GPU shapes whatever the device (ContextOptions::work_group_shape).
Context& shared_context(WorkGroupShape shape);

// The generated stage program of the built-in normal-shading program: what kernel unit tests
// append their test kernels to, so they call the stages' real functions.
std::string builtin_stage_program();

// `source` built for the shared context's device with the options the pipeline's own programs get
// (memoized by the context's program cache). Kernel unit tests call it from SetUp, not from
// SetUpTestSuite: a program that fails to build then fails each of its tests, where an exception in
// SetUpTestSuite would only skip them.
cl::Program build_test_program(const std::string& name, const std::string& source);

// Renders one draw of `mesh` into a width x height framebuffer cleared to opaque black and depth 1.
struct RenderResult {
  Image image;
  DrawStats stats;
};
RenderResult render_clraster(Context& context, const io::Mesh& mesh, const DrawState& state, int width, int height,
                             Topology topology = Topology::TriangleList);
Image render_gl(const io::Mesh& mesh, const DrawState& state, int width, int height,
                Topology topology = Topology::TriangleList);

// How a draw of a scene reads its mesh.
enum class IndexFormat {
  Uint32,
  Uint16,
  None,  // non-indexed: the mesh's vertices are laid out in index order and drawn in turn
};

// One draw of a multi-draw scene. The mesh's indices are read with state.topology (a strip or fan
// is its index sequence); first and count are in indices, or in vertices when non-indexed.
struct SceneDraw {
  const io::Mesh* mesh = nullptr;
  DrawState state{};
  IndexFormat index_format = IndexFormat::Uint32;
  std::uint32_t first = 0;
  std::uint32_t count = kAllElements;
};

// How clraster is given a scene's draws: one Framebuffer::draw call each, or all of them as one
// frame (Framebuffer::draw of a span), which rasterizes draws together.
enum class Submission { OneByOne, Frame };

// Renders the draws in order into one width x height framebuffer cleared to opaque black and
// depth 1, with clraster or with the OpenGL oracle. Each mesh is uploaded once per render, however
// many draws use it.
Image render_scene_clraster(Context& context, std::span<const SceneDraw> draws, int width, int height,
                            Submission submission = Submission::OneByOne);
Image render_scene_gl(std::span<const SceneDraw> draws, int width, int height);

// Pixels with a non-zero R, G or B channel (drawn over an opaque black background), as
// io::compare_images counts them.
std::uint64_t covered_pixel_count(const Image& image);

// ---- Exact scenes ---------------------------------------------------------------------------------
// Both renderers snap window positions to 1/256 pixel. A vertex placed on that grid, with identity
// matrices, lands on the same fixed-point position in both, so their coverage can be compared
// exactly. Window-space meshes below are in pixels, y up, pixel centres at (i + 0.5, j + 0.5).

inline constexpr double kSubpixel = 1.0 / 256;

// Moves every vertex's x and y to the nearest point offset + k * step (step a multiple of kSubpixel).
void snap_to_grid(io::Mesh& window_mesh, double step, double offset = 0);

// The window-space mesh in normalized device coordinates of `viewport`, for identity matrices:
// both renderers map it back to within 1e-4 pixel of where it was, far from the ties of snapping
// halfway between two 1/256 positions, so a mesh on the 1/256 grid is snapped to the same
// positions by both. (With a power-of-two viewport the way back is exact, ties included.)
io::Mesh window_to_ndc(io::Mesh window_mesh, const Rect& viewport);

// `count` triangles of io::make_random_triangles (random windings and sizes, corners up to
// max_size pixels apart) inside the window rectangle `area`, snapped to the grid offset + k * step.
// Inside, because llvmpipe clips triangles at the edges of the viewport, and the vertices that
// clipping makes move the edges by up to about 1/5000 pixel: enough to flip pixel centres that lie
// that close to an edge, in one renderer and not in the other.
io::Mesh random_window_triangles(int count, std::uint64_t seed, const Rect& area, float max_size,
                                 double step = kSubpixel, double offset = 0);

// ---- Grids as strips ------------------------------------------------------------------------------

// The vertices of a grid mesh (io::make_plane, io::make_terrain) by column and row, found from their
// positions rather than from the generators' vertex order: columns along +x, rows along
// `row_direction` (+y for a plane, -z for a terrain), the directions in which the grid's triangles
// are counter-clockwise seen from their front.
struct GridVertices {
  int columns = 0;
  int rows = 0;
  std::vector<std::uint32_t> ids;  // row-major

  std::uint32_t at(int column, int row) const { return ids[std::size_t(row) * columns + column]; }
};
GridVertices grid_vertices(const io::Mesh& grid, const std::array<float, 3>& row_direction);

// The band between rows `row` and `row` + 1 as a triangle strip: (upper, lower) pairs from left to
// right, so that the strip's triangles keep the grid's front face.
std::vector<std::uint32_t> band_strip(const GridVertices& grid, int row);

// All bands as one strip, joined by repeating the last index of a band and the first of the next:
// the joining triangles have no area, and every band starts at an even position.
std::vector<std::uint32_t> grid_strip(const GridVertices& grid);

// Constant 1/255 red, added up without a depth test: the red channel counts each pixel's fragments.
DrawState overdraw_counter();

// How close two renders of a scene must be (io/image_compare.hpp, shared with the benchmarks).
using io::kExact;
using io::kNormalShading;
using io::Tolerance;

// Compares result against reference within the tolerance. On failure writes
// <test-output>/<test name>/{reference,result,diff}.png and adds a gtest failure that names them.
::testing::AssertionResult images_match(const Image& result, const Image& reference, const Tolerance& tolerance);

// The directory failing tests write their pictures to (created on demand).
std::string output_directory();

}  // namespace clraster::test
