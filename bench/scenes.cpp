#include "bench/scenes.hpp"

#include "io/image_io.hpp"
#include "io/procedural.hpp"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>

namespace clraster::bench {

const char* const kInstancedProgram = R"(
clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_attribute(float4, placement)  /* per instance: x, y, z offset and scale */
clr_varying(float3, object_normal)
clr_uniform(float16, mvp)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  const float3 placed = v->in.position * v->in.placement.w + v->in.placement.xyz;
  v->position = clr_mul(v->uniforms->mvp, (float4)(placed, 1.0f));
  v->out.object_normal = v->in.normal;
}

void fragment_span(clr_span_fragment* f) {
  const clr_span_float3 n = f->in.object_normal;
  const clr_span_float length_of_normal = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  f->out.color.x = n.x / length_of_normal * 0.5f + 0.5f;
  f->out.color.y = n.y / length_of_normal * 0.5f + 0.5f;
  f->out.color.z = n.z / length_of_normal * 0.5f + 0.5f;
  f->out.color.w = 1.0f;
}
)";

const char* const kGlInstancedVertexShader = R"(#version 450 core
in vec3 position;
in vec3 normal;
in vec4 placement;
uniform mat4 mvp;
out vec3 object_normal;
void main() {
  gl_Position = mvp * vec4(position * placement.w + placement.xyz, 1.0);
  object_normal = normal;
}
)";

const char* const kGlInstancedFragmentShader = R"(#version 450 core
in vec3 object_normal;
out vec4 color;
void main() { color = vec4(normalize(object_normal) * 0.5 + 0.5, 1.0); }
)";

namespace {

// The picture size the scenes are made for: models without a camera of their own are framed for it.
constexpr float kDesignAspect = 1920.0f / 1080.0f;

// materials-256's number of parts.
constexpr std::uint32_t kMaterialParts = 256;

// engine-glb's model, and the package that installs the scenes' model files (scripts/setup.sh).
constexpr const char* kEngineModel = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
constexpr const char* kModelPackage = "assimp-testmodels";

io::Camera camera(glm::vec3 eye, glm::vec3 target, float fov_degrees, float near_plane, float far_plane) {
  io::Camera camera;
  camera.eye = eye;
  camera.target = target;
  camera.fov_degrees = fov_degrees;
  camera.near_plane = near_plane;
  camera.far_plane = far_plane;
  return camera;
}

// A trefoil: a closed tube of 500 rings of 50 vertices, 2 * 500 * 50 triangles. Its strands are
// 1.66 apart at their closest, so a tube of radius 0.6 does not meet itself.
io::Mesh knot() { return io::make_torus_knot(2, 3, 500, 50, 2, 1, 0.6f); }

// A mesh drawn with a built-in shading: a model without materials or parts.
io::Model model_of(io::Mesh mesh) {
  io::Model model;
  static_cast<io::Mesh&>(model) = std::move(mesh);
  return model;
}

// A 16 x 16 landscape: about four hills across, up to 0.8 high.
io::Mesh landscape(int cells) { return io::make_terrain(cells, cells, 16, 16, 0.8f, 7); }

// 16 quads at z = 0, from 1 away (see the camera below) almost five times the view's height and
// over twice its width at 16:9: every pixel gets 16 fragments.
io::Mesh layers() { return io::merge(std::vector<io::Mesh>(16, io::make_plane(1, 1, 4, 4))); }

// At 1920x1080 and 45 degrees a pixel is 2 * tan(22.5 degrees) / 1080 of the view distance, so
// from 2 away (see the camera below) a cell of 1.1 / 1024 is 0.700 pixel: 717 x 358 pixels of
// triangles of 0.245 square pixels each.
io::Mesh tiny_cells() { return io::make_plane(1024, 512, 1.1f, 0.55f); }

// The knot with texture coordinates projected from above, (u, v) = (x, z) / 2: the 1024-texel
// texture repeats three to four times across the knot, 3 to 4 texels a pixel at 1920x1080 (level
// of detail 1.6 to 2), more on the tube's steep sides.
io::Mesh textured_knot_mesh() {
  io::Mesh mesh = knot();
  mesh.texcoords.reserve(2 * mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    mesh.texcoords.push_back(mesh.positions[3 * v] / 2);
    mesh.texcoords.push_back(mesh.positions[3 * v + 2] / 2);
  }
  return mesh;
}

// A material whose base colour texture is a picture embedded as a PNG file, as a .glb file embeds
// one: 1024x1024 squares of 64 texels, light and coloured in turn, along lines of two texels, the
// coloured ones shading across the picture, so that every mipmap level has detail of its own.
io::Material pattern_material() {
  constexpr int kSide = 1024;
  Image pattern{kSide, kSide, std::vector<std::uint8_t>(std::size_t(kSide) * kSide * 4)};
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) {
      std::uint8_t* texel = &pattern.rgba[4 * (std::size_t(y) * kSide + x)];
      const bool line = x % 64 < 2 || y % 64 < 2;
      const bool coloured = (x / 64 + y / 64) % 2 != 0;
      texel[0] = static_cast<std::uint8_t>(line ? 40 : coloured ? 60 + x * 150 / kSide : 235);
      texel[1] = static_cast<std::uint8_t>(line ? 40 : coloured ? 110 : 225 - y * 60 / kSide);
      texel[2] = static_cast<std::uint8_t>(line ? 40 : coloured ? 210 - y * 150 / kSide : 190);
      texel[3] = 255;
    }
  }
  io::Material material;
  material.name = "pattern";
  io::MaterialTexture texture;
  texture.reference = "*0";
  texture.encoded = io::encode_png(pattern);
  texture.format_hint = "png";
  material.base_color_texture = texture;
  return material;
}

// The textured knot as one part with the pattern material.
io::Model textured_knot() {
  io::Model model = model_of(textured_knot_mesh());
  model.materials = {pattern_material()};
  model.parts = {{0, static_cast<std::uint32_t>(model.indices.size()), 0}};
  return model;
}

// The knot in kMaterialParts parts of consecutive triangles, as many as can be alike, each with a
// colour of its own from an 8 x 8 x 4 grid: the parts of a model of many materials, whose draws
// each shade a small piece of the picture.
io::Model knot_in_parts() {
  io::Model model = model_of(knot());
  const auto triangles = static_cast<std::uint32_t>(model.triangle_count());
  for (std::uint32_t i = 0; i < kMaterialParts; ++i) {
    const std::uint32_t first = 3 * (triangles * i / kMaterialParts);
    const std::uint32_t end = 3 * (triangles * (i + 1) / kMaterialParts);
    io::Material& material = model.materials.emplace_back();
    material.name = "part " + std::to_string(i);
    material.base_color_factor = {0.3f + 0.1f * float(i % 8), 0.3f + 0.1f * float(i / 8 % 8),
                                  0.3f + 0.2f * float(i / 64), 1.0f};
    model.parts.push_back({first, end - first, i});
  }
  return model;
}

// A sphere of 2 * 32 * 20 triangles (its poles' rings are triangles, not quads).
io::Model instanced_sphere() { return model_of(io::make_sphere(32, 21, 1.0f)); }

// A 64 x 64 grid of spheres of radius 0.035 over the plane z = 0, every other one a little larger.
std::vector<float> sphere_grid() {
  constexpr int kSide = 64;
  std::vector<float> placements;
  for (int row = 0; row < kSide; ++row) {
    for (int column = 0; column < kSide; ++column) {
      const float x = -3.0f + 6.0f * (float(column) + 0.5f) / kSide;
      const float y = -2.0f + 4.0f * (float(row) + 0.5f) / kSide;
      placements.insert(placements.end(), {x, y, 0.0f, (row + column) % 2 ? 0.04f : 0.035f});
    }
  }
  return placements;
}

// 64 cameras around a model, 8 elevations (-70 to 70 degrees, 20 apart) by 8 azimuths (45 apart)
// about the y axis, each at the distance at which `render` frames it in a square picture: the
// whole model in each view, the knot over 23% to 38% of it.
std::vector<io::Camera> orbit(const io::Model& model) {
  const io::Camera framed = io::fit_camera(io::bounding_sphere(model), 1.0f);
  const float distance = glm::length(framed.eye - framed.target);
  std::vector<io::Camera> cameras;
  for (int elevation = 0; elevation < 8; ++elevation) {
    for (int azimuth = 0; azimuth < 8; ++azimuth) {
      const float up = glm::radians(-70.0f + 20.0f * float(elevation));
      const float around = glm::radians(45.0f * float(azimuth));
      io::Camera& camera = cameras.emplace_back(framed);
      camera.eye = framed.target + distance * glm::vec3(std::cos(up) * std::sin(around), std::sin(up),
                                                        std::cos(up) * std::cos(around));
    }
  }
  return cameras;
}

// assimp's engine as the command line loads it.
io::Model engine() {
  std::vector<std::string> warnings;
  io::Model model = io::load_model(kEngineModel, warnings);
  // A warning would mean the scene is not drawn as it says.
  warnings.insert(warnings.end(), model.material_warnings.begin(), model.material_warnings.end());
  if (!warnings.empty()) {
    throw Error(std::string("benchmark scene engine-glb: ") + kEngineModel + ": " + warnings.front());
  }
  return model;
}

struct SceneDefinition {
  std::string name;
  io::Model (*model)();
  // None: framed as `render` frames a model by default (io::fit_camera), at kDesignAspect.
  std::optional<io::Camera> camera{};
  io::BuiltinShading shading = io::BuiltinShading::Normal;  // for scenes without parts
  const char* model_file = nullptr;                         // for a scene loaded from a file
  std::vector<float> (*instances)() = nullptr;              // for an instanced scene
  std::vector<io::Camera> (*views)(const io::Model&) = nullptr;  // for a scene of views
};

// A missing model file is an error, not a scene left out: a run that quietly drew fewer scenes
// would not compare with another.
void require_model_file(const SceneDefinition& scene) {
  if (scene.model_file && !std::filesystem::exists(scene.model_file)) {
    throw Error("benchmark scene " + scene.name + ": " + scene.model_file + " is missing (install the package " +
                kModelPackage + ", as scripts/setup.sh does)");
  }
}

const std::vector<SceneDefinition>& definitions() {
  using io::BuiltinShading;
  // The landscape is seen at 45 degrees from above with a narrow field of view, so that the
  // picture's far corners still fall on it: it fills the picture, and about a third of it is in
  // view.
  const io::Camera landscape_view = camera({0.0f, 7.4f, 6.9f}, {0.0f, 0.0f, -0.5f}, 30, 1.0f, 30.0f);
  // From above at an angle, framed closely as a scanned model would be: the knot covers 37% of the
  // picture.
  const io::Camera knot_view = camera({0.0f, 5.8f, 5.6f}, {0.0f, 0.0f, 0.7f}, 45, 3.0f, 12.0f);
  static const std::vector<SceneDefinition> scenes{
      {"model-50k", [] { return model_of(knot()); }, knot_view, BuiltinShading::Normal},
      {"terrain-1m", [] { return model_of(landscape(708)); }, landscape_view, BuiltinShading::Normal},
      {"terrain-4m", [] { return model_of(landscape(1415)); }, landscape_view, BuiltinShading::Normal},
      {"fill-16", [] { return model_of(layers()); }, camera({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}, 45, 0.5f, 2.0f),
       BuiltinShading::Overdraw},
      {"tiny-1m", [] { return model_of(tiny_cells()); }, camera({0.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 45, 1.0f, 3.0f),
       BuiltinShading::Normal},
      {"textured-50k", textured_knot, knot_view},
      {"materials-256", knot_in_parts, knot_view},
      {"engine-glb", engine, std::nullopt, BuiltinShading::Normal, kEngineModel},
      {"instanced-4k", instanced_sphere, camera({0.0f, -2.6f, 3.6f}, {0.0f, -0.2f, 0.0f}, 45, 1.0f, 10.0f),
       BuiltinShading::Normal, nullptr, sphere_grid},
      {.name = "views-64", .model = [] { return model_of(knot()); }, .views = orbit},
  };
  return scenes;
}

const SceneDefinition& definition(const std::string& name) {
  const std::vector<SceneDefinition>& scenes = definitions();
  const auto found =
      std::find_if(scenes.begin(), scenes.end(), [&](const SceneDefinition& scene) { return scene.name == name; });
  if (found == scenes.end()) {
    throw InvalidArgument("no benchmark scene is called '" + name + "' (scenes: " + scene_names_text() + ")");
  }
  return *found;
}

}  // namespace

DrawState Scene::state(int width, int height) const {
  return io::shading_state(shading, camera, static_cast<float>(width) / static_cast<float>(height));
}

int Scene::layer_width(int width) const { return draws_views() ? kViewSide : width; }
int Scene::layer_height(int height) const { return draws_views() ? kViewSide : height; }

int Scene::layer_columns() const {
  int columns = 1;  // the smallest square grid that holds the layers, as Framebuffer's
  while (columns * columns < layer_count()) ++columns;
  return columns;
}

int Scene::layer_rows() const { return (layer_count() + layer_columns() - 1) / layer_columns(); }

Rect Scene::layer_rect(int layer, int layer_width, int layer_height) const {
  return {layer % layer_columns() * layer_width, layer / layer_columns() * layer_height, layer_width, layer_height};
}

std::vector<View> Scene::view_matrices() const {
  std::vector<View> matrices;
  for (const io::Camera& view : views) {
    matrices.push_back({io::to_mat4(io::view_matrix(view)), io::to_mat4(io::projection_matrix(view, 1.0f))});
  }
  return matrices;
}

std::vector<DrawState> Scene::view_states(const DrawState& state, int width, int height) const {
  std::vector<DrawState> states;
  for (const View& view : view_matrices()) {
    DrawState& drawn = states.emplace_back(state);
    drawn.model_view = view.model_view;
    drawn.projection = view.projection;
    drawn.viewport = layer_rect(int(states.size()) - 1, width, height);
  }
  return states;
}

const std::vector<std::string>& scene_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const SceneDefinition& scene : definitions()) all.push_back(scene.name);
    return all;
  }();
  return names;
}

std::string scene_names_text() {
  std::string text;
  for (const std::string& name : scene_names()) text += (text.empty() ? "" : ", ") + name;
  return text;
}

std::vector<std::string> parse_scene_list(const std::string& list) {
  if (list.empty()) return scene_names();
  std::vector<std::string> names;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = list.find(',', start);
    names.push_back(list.substr(start, comma - start));
    require_model_file(definition(names.back()));
    if (comma == std::string::npos) return names;
    start = comma + 1;
  }
}

Scene make_scene(const std::string& name) {
  const SceneDefinition& defined = definition(name);
  require_model_file(defined);
  Scene scene{.name = defined.name, .model = defined.model(), .shading = defined.shading};
  if (defined.instances) scene.instances = defined.instances();
  if (defined.views) scene.views = defined.views(scene.model);
  scene.camera = defined.camera     ? *defined.camera
                 : scene.draws_views() ? scene.views.front()
                                       : io::fit_camera(io::bounding_sphere(scene.model), kDesignAspect);
  return scene;
}

}  // namespace clraster::bench
