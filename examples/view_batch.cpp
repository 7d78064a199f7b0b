// Many pictures of one model in one draw: views into a layered framebuffer.
//
//   view_batch [OUT.png]
//
// A torus knot from 16 cameras around it (4 elevations by 4 azimuths), 160x160 each, as a dataset
// generator would take them: one layered framebuffer of 16 layers, one draw with 16 views, each view
// its camera. Every layer is read back and the 16 pictures are laid out in a 4x4 contact sheet,
// layer 0 at the top left, row by row.
#include <clraster/clraster.hpp>

#include <cmath>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/procedural.hpp"

namespace {

constexpr int kSide = 160;  // of each picture
constexpr int kColumns = 4, kRows = 4;

// Camera k: azimuth k % 4 quarter turns plus 30 degrees, elevation from -50 to 40 degrees.
clraster::io::Camera camera(int k) {
  const float azimuth = std::acos(-1.0f) / 180.0f * (30.0f + 90.0f * static_cast<float>(k % kColumns));
  const float elevation = std::acos(-1.0f) / 180.0f * (-50.0f + 30.0f * static_cast<float>(k / kColumns));
  clraster::io::Camera c;
  c.eye = {5.0f * std::cos(elevation) * std::sin(azimuth), 5.0f * std::sin(elevation),
           5.0f * std::cos(elevation) * std::cos(azimuth)};
  c.near_plane = 1.0f;
  c.far_plane = 10.0f;
  return c;
}

void render(const std::string& output) {
  namespace io = clraster::io;
  clraster::Context context;
  const io::Mesh knot = io::make_torus_knot(2, 3, 256, 16, 1.0f, 0.45f, 0.3f);
  const clraster::VertexBuffer vertices(context, knot.positions, knot.normals);
  const clraster::IndexBuffer indices(context, knot.indices);

  clraster::Framebuffer batch(context, kSide, kSide, kColumns * kRows);
  batch.clear({0, 0, 0, 1});
  clraster::DrawCall call{&vertices, &indices};
  call.state.shading = clraster::Shading::Normal;
  for (int k = 0; k < kColumns * kRows; ++k) {
    const io::Camera c = camera(k);
    call.views.push_back({io::to_mat4(io::view_matrix(c)), io::to_mat4(io::projection_matrix(c, 1.0f)), nullptr});
  }
  batch.draw(call);  // all 16 pictures in one submission

  clraster::Image sheet{kColumns * kSide, kRows * kSide, std::vector<std::uint8_t>(std::size_t(kColumns * kSide) * kRows * kSide * 4)};
  for (int k = 0; k < kColumns * kRows; ++k) {
    const clraster::Image picture = batch.read_color(0, k);
    for (int y = 0; y < kSide; ++y) {
      const std::size_t row = std::size_t(k / kColumns * kSide + y) * std::size_t(sheet.width) + std::size_t(k % kColumns * kSide);
      std::copy_n(&picture.rgba[std::size_t(y) * kSide * 4], kSide * 4, &sheet.rgba[row * 4]);
    }
  }
  io::save_png(output, sheet);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "view_batch.png";
  try {
    render(output);
  } catch (const std::exception& error) {
    std::cerr << "view_batch: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
