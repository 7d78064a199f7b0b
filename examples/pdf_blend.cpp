// Blend modes beyond OpenGL's blend equations: the PDF blend modes, in a program's blend function.
//
//   pdf_blend [OUT.png]
//
// Six panels, one per mode of programs/pdf_blend.cl (multiply, screen, overlay, darken, colour
// dodge, difference), left to right from the top row. In each, an opaque orange disc is drawn
// first, then a translucent blue disc over it blended with the panel's mode: the orange disc and the
// grey background are the destination, the blue disc the source.
#include <clraster/clraster.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "io/image_io.hpp"

namespace {

constexpr int kPanelSize = 128;
constexpr int kColumns = 3;
constexpr int kRows = 2;  // kColumns * kRows modes, numbered as pdf_blend.cl's MODE_ values

// Colours as 8-bit values, so that the picture can be checked exactly (tests/test_examples.cpp).
constexpr std::array<float, 4> kBackground{191 / 255.0f, 191 / 255.0f, 191 / 255.0f, 1.0f};
constexpr std::array<float, 3> kOrange{230 / 255.0f, 120 / 255.0f, 40 / 255.0f};
constexpr std::array<float, 3> kBlue{40 / 255.0f, 150 / 255.0f, 200 / 255.0f};
constexpr float kBlueAlpha = 0.8f;

// A unit disc as a triangle fan: the centre, then 64 points around the rim, the first repeated.
std::vector<float> unit_disc() {
  constexpr int kSegments = 64;
  std::vector<float> xy = {0.0f, 0.0f};
  for (int i = 0; i <= kSegments; ++i) {
    const double angle = 2 * std::numbers::pi * i / kSegments;
    xy.push_back(static_cast<float>(std::cos(angle)));
    xy.push_back(static_cast<float>(std::sin(angle)));
  }
  return xy;
}

void render(const std::string& output) {
  clraster::Context context;
  const clraster::Buffer disc(context, unit_disc());
  const clraster::Program program = clraster::Program::load(context, CLRASTER_EXAMPLE_PROGRAMS "/pdf_blend.cl");
  clraster::Bindings bindings(program);
  bindings.set("radius", 0.55f);

  clraster::Framebuffer framebuffer(context, kColumns * kPanelSize, kRows * kPanelSize);
  framebuffer.clear(kBackground);

  clraster::DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.attributes = {{"position", &disc, clraster::AttributeType::Float2}};
  call.state.topology = clraster::Topology::TriangleFan;  // non-indexed: the buffer's vertices in order
  call.state.depth_test = false;                          // 2D: later draws go over earlier ones

  for (int mode = 0; mode < kColumns * kRows; ++mode) {
    // Each panel is a viewport: normalized device coordinates [-1, 1] cover just that square.
    // Window coordinates count rows from the bottom, so the first row of panels is the upper one.
    const int column = mode % kColumns, row = kRows - 1 - mode / kColumns;
    call.state.viewport = {column * kPanelSize, row * kPanelSize, kPanelSize, kPanelSize};
    bindings.set("mode", std::int32_t{mode});

    // The destination: an opaque disc, written as it is (blending off, the default BlendState).
    bindings.set("center", std::array<float, 2>{-0.25f, 0.15f})
        .set("fill", std::array<float, 4>{kOrange[0], kOrange[1], kOrange[2], 1.0f});
    call.state.blend[0] = {};
    framebuffer.draw(call);

    // The source: a translucent disc, premultiplied, blended by the program's blend function on
    // every channel (kProgramBlend: BlendEquation::Program for colour and alpha).
    bindings.set("center", std::array<float, 2>{0.25f, -0.15f})
        .set("fill", std::array<float, 4>{kBlue[0] * kBlueAlpha, kBlue[1] * kBlueAlpha, kBlue[2] * kBlueAlpha,
                                          kBlueAlpha});
    call.state.blend[0] = clraster::kProgramBlend;
    framebuffer.draw(call);
  }
  clraster::io::save_png(output, framebuffer.read_color());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "pdf_blend.png";
  try {
    render(output);
  } catch (const std::exception& error) {
    std::cerr << "pdf_blend: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
