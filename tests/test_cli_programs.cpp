// The command line's programmable rendering, run as a separate process: `--shading material` (each
// part with its material's base colour texture times factor, lit by a headlight) against the
// OpenGL backend's GLSL equivalent on assimp's textured samples, where images land on a model and
// what is drawn without them; `--program` with the bundled program, and the values the command
// line binds to what a program declares. Bad input is in test_cli.cpp.
#include "io/image_io.hpp"
#include "io/model_loader.hpp"
#include "support/cli_support.hpp"
#include "support/test_support.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kAssimpModels = "/usr/share/assimp/models";  // the assimp-testmodels package
const fs::path kMaterialProgram = fs::path(CLRASTER_PROGRAMS_DIR) / "material.cl";

// The issue's tolerance for texture filtering: within 2/255 on at least 99.5% of the pixels both
// pictures cover; coverage as the other tests of fitted models allow.
constexpr Tolerance kTextureFiltering{kNormalShading.max_coverage_mismatch, 0.005, 2, ~0ull, false};

template <typename Row>
  requires requires(const Row& row) { row.name; }
void PrintTo(const Row& row, std::ostream* stream) {
  *stream << row.name;
}

std::size_t part_count(const fs::path& model) {
  std::vector<std::string> warnings;
  return io::load_model(model.string(), warnings).parts.size();
}

std::uint64_t draws_in(const Rendered& rendered) { return json::parse(rendered.out).at("draws").get<std::uint64_t>(); }

// ---- assimp's textured samples against OpenGL --------------------------------------------------------

struct TexturedModel {
  const char* name;
  const char* path;  // under kAssimpModels
};

class MaterialShadingOfTexturedModel : public ::testing::TestWithParam<TexturedModel> {};

// Nothing on stderr (render() checks it): every texture was found and decoded.
TEST_P(MaterialShadingOfTexturedModel, AgreesWithOpenGlWithinTheTextureTolerance) {
  const fs::path model = kAssimpModels / GetParam().path;
  const std::vector<std::string> args = {model.string(), "--shading", "material", "--size", "256x192", "--stats"};
  const Rendered ours = render(std::string(GetParam().name) + "-clraster.png", args);
  std::vector<std::string> gl_args = args;
  gl_args.insert(gl_args.end(), {"--backend", "gl"});
  const Rendered gl = render(std::string(GetParam().name) + "-gl.png", gl_args);

  EXPECT_EQ(draws_in(ours), part_count(model)) << "one draw per part";
  EXPECT_EQ(draws_in(gl), part_count(model));
  ASSERT_GT(covered_pixel_count(gl.picture), 2000u);
  EXPECT_TRUE(images_match(ours.picture, gl.picture, kTextureFiltering));
}

INSTANTIATE_TEST_SUITE_P(
    Models, MaterialShadingOfTexturedModel,
    ::testing::Values(TexturedModel{"GltfWithImageFile", "glTF2/BoxTextured-glTF/BoxTextured.gltf"},
                      TexturedModel{"GlbWithEmbeddedImage", "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"},
                      TexturedModel{"GltfWithDataUri", "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"},
                      // Five materials with JPEG files named .\like.jpg, in six parts.
                      TexturedModel{"ObjWithJpegFiles", "OBJ/spider.obj"}),
    [](const auto& info) { return std::string(info.param.name); });

// ---- Where images land, and what is drawn without them -------------------------------------------------

// A square of side 2 in the z = 0 plane facing +z, texture coordinates (0, 0) at its bottom left and
// (1, 1) at its top right (when `with_uvs`), drawn with material "m" of quad.mtl, in a directory of
// its own. Seen from kFront, its normal points at the camera: the headlight lights it fully, so a
// pixel is exactly its texel times the base colour factor.
fs::path write_quad(const std::string& directory, const std::string& mtl, bool with_uvs = true) {
  const fs::path dir = scratch_directory() / directory;
  fs::create_directories(dir);
  std::ofstream(dir / "quad.mtl") << mtl;
  std::string obj = "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvn 0 0 1\nusemtl m\n";
  obj += with_uvs ? "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n"
                  : "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n";
  std::ofstream(dir / "quad.obj") << obj;
  return dir / "quad.obj";
}

const std::vector<std::string> kFront = {"--size", "64x64", "--eye", "0,0,3", "--target", "0,0,0"};

// Pixels (column, row from the top) on the quad: its upper and lower halves, and its centre.
constexpr std::array<int, 2> kUpper{32, 16}, kLower{32, 47}, kCentre{32, 32};

std::array<int, 3> rgb_at(const Image& image, std::array<int, 2> pixel) {
  const std::size_t i = 4 * (std::size_t(pixel[1]) * image.width + pixel[0]);
  return {image.rgba.at(i), image.rgba.at(i + 1), image.rgba.at(i + 2)};
}

// A 4x4 picture file: its upper two rows red, its lower two blue.
void write_red_over_blue(const fs::path& path) {
  Image image{4, 4, {}};
  for (int texel = 0; texel < 16; ++texel) {
    const bool upper = texel < 8;
    image.rgba.insert(image.rgba.end(), {std::uint8_t(upper ? 255 : 0), 0, std::uint8_t(upper ? 0 : 255), 255});
  }
  io::save_png(path.string(), image);
}

// The base colour factor of the materials below, and what a fully lit pixel of it is in RGBA8.
const std::string kFactor = "Kd 0.8 0.4 0.2\n";
constexpr std::array<int, 3> kFactorColour{204, 102, 51};

struct Backend {
  const char* name;
  std::vector<std::string> args;
};

class MaterialShadingOnBothBackends : public ::testing::TestWithParam<Backend> {
 protected:
  // `clraster render model --shading material` from kFront on this backend.
  Rendered render_front(const fs::path& model, const std::string& output) const {
    std::vector<std::string> args = {model.string(), "--shading", "material"};
    args.insert(args.end(), kFront.begin(), kFront.end());
    args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
    return render_with_warnings(std::string(GetParam().name) + "-" + output, args);
  }
};

TEST_P(MaterialShadingOnBothBackends, PutsTheImagesTopRowsAtTheTopOfTheModel) {
  const fs::path model = write_quad(std::string("oriented-") + GetParam().name, "newmtl m\nKd 1 1 1\nmap_Kd red-over-blue.png\n");
  write_red_over_blue(model.parent_path() / "red-over-blue.png");
  const Rendered result = render_front(model, "oriented.png");
  EXPECT_EQ(result.err, "");
  EXPECT_EQ(rgb_at(result.picture, kUpper), (std::array<int, 3>{255, 0, 0}));
  EXPECT_EQ(rgb_at(result.picture, kLower), (std::array<int, 3>{0, 0, 255}));
}

TEST_P(MaterialShadingOnBothBackends, MultipliesTheTextureByTheFactor) {
  const fs::path model = write_quad(std::string("factor-") + GetParam().name, "newmtl m\n" + kFactor + "map_Kd red-over-blue.png\n");
  write_red_over_blue(model.parent_path() / "red-over-blue.png");
  const Rendered result = render_front(model, "factor.png");
  EXPECT_EQ(result.err, "");
  EXPECT_EQ(rgb_at(result.picture, kUpper), (std::array<int, 3>{204, 0, 0}));
  EXPECT_EQ(rgb_at(result.picture, kLower), (std::array<int, 3>{0, 0, 51}));
}

TEST_P(MaterialShadingOnBothBackends, ModelWithoutTextureCoordinatesWarnsAndDrawsTheFactor) {
  const fs::path model = write_quad(std::string("no-uvs-") + GetParam().name,
                                    "newmtl m\n" + kFactor + "map_Kd red-over-blue.png\n", false);
  write_red_over_blue(model.parent_path() / "red-over-blue.png");
  const Rendered result = render_front(model, "no-uvs.png");
  EXPECT_EQ(result.err, "clraster: warning: material 'm': the model has no texture coordinates to map its base "
                        "colour texture " + (model.parent_path() / "red-over-blue.png").string() +
                            "; drawn with its base colour factor only\n");
  EXPECT_EQ(rgb_at(result.picture, kUpper), kFactorColour);
  EXPECT_EQ(rgb_at(result.picture, kLower), kFactorColour);
}

TEST_P(MaterialShadingOnBothBackends, MaterialWithoutATextureIsDrawnWithItsFactor) {
  const Rendered result = render_front(write_quad(std::string("untextured-") + GetParam().name, "newmtl m\n" + kFactor),
                                       "untextured.png");
  EXPECT_EQ(result.err, "");
  EXPECT_EQ(rgb_at(result.picture, kCentre), kFactorColour);
}

// An image file that cannot be used: one line naming it, and the part drawn with its factor.
struct UnusableImage {
  const char* name;
  const char* contents;  // null: no file at all
  const char* reason;
};

TEST_P(MaterialShadingOnBothBackends, UnusableImagesWarnAndLeaveTheFactor) {
  for (const UnusableImage& image : {UnusableImage{"missing", nullptr, "No such file or directory"},
                                     UnusableImage{"not-an-image", "these bytes are no picture", "cannot decode"}}) {
    SCOPED_TRACE(image.name);
    const std::string directory = std::string(image.name) + "-" + GetParam().name;
    const fs::path model = write_quad(directory, "newmtl m\n" + kFactor + "map_Kd picture.png\n");
    const fs::path picture = model.parent_path() / "picture.png";
    if (image.contents != nullptr) write_scratch_file(directory + "/picture.png", image.contents);
    const Rendered result = render_front(model, std::string(image.name) + ".png");
    EXPECT_TRUE(result.err.starts_with("clraster: warning: material 'm': ")) << result.err;
    EXPECT_TRUE(mentions(result.err, picture.string()));
    EXPECT_TRUE(mentions(result.err, image.reason));
    EXPECT_TRUE(result.err.ends_with("; drawn with its base colour factor only\n")) << result.err;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
    EXPECT_EQ(rgb_at(result.picture, kCentre), kFactorColour);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, MaterialShadingOnBothBackends,
                         ::testing::Values(Backend{"clraster", {}}, Backend{"gl", {"--backend", "gl"}}),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- --program -----------------------------------------------------------------------------------------

TEST(ProgramOption, TheBundledMaterialProgramDrawsAsMaterialShadingAndAsOpenGl) {
  const std::string model = (kAssimpModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb").string();
  const Rendered program = render("bundled-program.png", {model, "--program", kMaterialProgram.string(), "--size", "128x96"});
  const Rendered builtin = render("builtin-material.png", {model, "--shading", "material", "--size", "128x96"});
  const Rendered gl = render("gl-material.png", {model, "--shading", "material", "--size", "128x96", "--backend", "gl"});
  ASSERT_GT(covered_pixel_count(gl.picture), 1000u);
  EXPECT_TRUE(images_match(program.picture, builtin.picture, kExact));
  EXPECT_TRUE(images_match(program.picture, gl.picture, kTextureFiltering));
}

// Declares every name the command line provides and checks each value against what docs/cli.md
// says it is, for the textured quad seen from kFront: green where every check passes, red where one
// fails. The position goes through projection and model_view, not mvp, whose check it is.
constexpr const char* kContractCheck = R"(
clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_attribute(float2, uv)
clr_varying(float3, normal)
clr_varying(float2, uv)
clr_uniform(float16, mvp)
clr_uniform(float16, model_view)
clr_uniform(float16, normal_matrix)
clr_uniform(float16, projection)
clr_uniform(float4, base_color)
clr_uniform(float3, light_direction)
clr_uniform(float2, viewport)
clr_texture(base_color_texture)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->projection, clr_mul(v->uniforms->model_view, (float4)(v->in.position, 1.0f)));
  v->out.normal = v->in.normal;
  v->out.uv = v->in.uv;
}

float largest(float16 m) {
  const float4 a = fmax(fmax(m.s0123, m.s4567), fmax(m.s89ab, m.scdef));
  return fmax(fmax(a.x, a.y), fmax(a.z, a.w));
}
bool close_to(float16 a, float16 b) { return largest(fabs(a - b)) <= 1e-5f; }

void fragment(clr_fragment* f) {
  const float16 mv = f->uniforms->model_view, n = f->uniforms->normal_matrix, p = f->uniforms->projection;
  /* The view from (0, 0, 3) toward the origin, up +y: a translation by -3 along z. */
  const float16 view = (float16)(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -3, 1);
  /* The inverse transpose of model_view's upper 3x3 in normal_matrix's: n^T mv = I there. */
  const float16 nt_mv = (float16)(dot(n.s012, mv.s012), dot(n.s456, mv.s012), dot(n.s89a, mv.s012), 0,
                                  dot(n.s012, mv.s456), dot(n.s456, mv.s456), dot(n.s89a, mv.s456), 0,
                                  dot(n.s012, mv.s89a), dot(n.s456, mv.s89a), dot(n.s89a, mv.s89a), 0, 0, 0, 0, 1);
  const float16 identity = (float16)(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1);
  /* gluPerspective(45 degrees, 64 / 64, near, far): 1 / tan(22.5 degrees) on the diagonal. */
  const float focal = 2.41421356f;
  const bool ok = close_to(f->uniforms->mvp, clr_mul_matrix(p, mv)) && close_to(mv, view) && close_to(nt_mv, identity) &&
                  fabs(p.s0 - focal) < 1e-5f && fabs(p.s5 - focal) < 1e-5f && p.sb == -1.0f &&
                  all(f->uniforms->base_color == (float4)(0.8f, 0.4f, 0.2f, 1.0f)) &&
                  all(f->uniforms->light_direction == (float3)(0.0f, 0.0f, 1.0f)) &&
                  all(f->uniforms->viewport == (float2)(64.0f, 64.0f)) &&
                  all(fabs(f->in.normal - (float3)(0.0f, 0.0f, 1.0f)) < 1e-5f) &&
                  all(clr_texture_size(f->textures.base_color_texture, 0) == (int2)(4, 4)) &&
                  all(f->in.uv >= 0.0f) && all(f->in.uv <= 1.0f);
  f->out.color = ok ? (float4)(0.0f, 1.0f, 0.0f, 1.0f) : (float4)(1.0f, 0.0f, 0.0f, 1.0f);
}
)";

TEST(ProgramOption, BindsEveryNameItProvidesWithItsDocumentedValue) {
  const fs::path model = write_quad("contract", "newmtl m\n" + kFactor + "map_Kd red-over-blue.png\n");
  write_red_over_blue(model.parent_path() / "red-over-blue.png");
  std::vector<std::string> args = {model.string(), "--program", write_scratch_file("check.cl", kContractCheck).string()};
  args.insert(args.end(), kFront.begin(), kFront.end());
  const Image picture = render("contract.png", args).picture;
  ASSERT_EQ(picture.width, 64);
  std::uint64_t green = 0, other = 0;
  for (int row = 0; row < 64; ++row) {
    for (int column = 0; column < 64; ++column) {
      const std::array<int, 3> rgb = rgb_at(picture, {column, row});
      if (rgb == std::array<int, 3>{0, 255, 0}) ++green;
      else if (rgb != std::array<int, 3>{0, 0, 0}) ++other;
    }
  }
  EXPECT_GT(green, 1000u) << "the quad covers the middle of the picture";
  EXPECT_EQ(other, 0u) << "red pixels: a value is not what docs/cli.md says";
}

}  // namespace
}  // namespace clraster::test
