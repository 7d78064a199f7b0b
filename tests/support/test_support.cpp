#include "support/test_support.hpp"

#include "io/image_io.hpp"
#include "oracle/gl_renderer.hpp"

#include <filesystem>
#include <sstream>

namespace clraster::test {

Context& shared_context() {
  static Context context;
  return context;
}

RenderResult render_clraster(Context& context, const io::Mesh& mesh, const DrawState& state, int width, int height,
                             Topology topology) {
  const VertexBuffer vertices(context, mesh.positions, mesh.normals);
  const IndexBuffer indices(context, mesh.indices);
  Framebuffer framebuffer(context, width, height);
  framebuffer.clear({0, 0, 0, 1}, 1.0f);
  DrawCall call{&vertices, &indices};
  call.state = state;
  call.state.topology = topology;
  RenderResult result;
  result.stats = framebuffer.draw(call);
  result.image = framebuffer.read_color();
  return result;
}

Image render_gl(const io::Mesh& mesh, const DrawState& state, int width, int height, Topology topology) {
  const oracle::GlMesh gl_mesh(mesh.positions, mesh.normals, mesh.indices);
  oracle::GlRenderer gl(width, height);
  gl.clear({0, 0, 0, 1}, 1.0f);
  DrawState gl_state = state;
  gl_state.topology = topology;
  gl.draw(gl_mesh, 0, kAllElements, gl_state);
  return gl.read_color();
}

std::string output_directory() { return CLRASTER_TEST_OUTPUT_DIR; }

::testing::AssertionResult images_match(const Image& result, const Image& reference, const Tolerance& tolerance) {
  const io::ImageComparison c = io::compare_images(result, reference, tolerance.exact ? 0 : tolerance.threshold);
  const bool ok = tolerance.exact ? c.differing_pixels == 0
                                  : c.coverage_mismatch <= tolerance.max_coverage_mismatch &&
                                        c.colour_mismatch <= tolerance.max_colour_mismatch &&
                                        c.count_mismatch_pixels <= tolerance.max_count_mismatch_pixels;
  if (ok) return ::testing::AssertionSuccess();

  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(output_directory()) /
                              (std::string(test->test_suite_name()) + "." + test->name());
  std::filesystem::create_directories(dir);
  io::save_png((dir / "reference.png").string(), reference);
  io::save_png((dir / "result.png").string(), result);
  io::save_png((dir / "diff.png").string(), io::diff_image(result, reference, tolerance.threshold));
  return ::testing::AssertionFailure() << "images differ: " << io::to_json(c) << "\n  pictures in " << dir.string();
}

}  // namespace clraster::test
