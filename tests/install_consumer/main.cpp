// Draws one triangle through the installed library: the lower-left half of an 8x8 picture.
#include <clraster/clraster.hpp>
#include <cstdio>
int main() {
  clraster::Context context;
  const float positions[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
  clraster::VertexBuffer vertices(context, positions);
  clraster::Framebuffer target(context, 8, 8);
  clraster::DrawCall call{&vertices};
  call.state.shading = clraster::Shading::Constant;
  target.draw(call);
  const clraster::Image image = target.read_color();
  int covered = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) covered += image.rgba[i] != 0;
  std::printf("clraster %s: %d of 64 pixels covered\n", clraster::version(), covered);
  return covered == 32 ? 0 : 1;
}
