// Conformance on real models: files of Debian's assimp-testmodels in every format the loader
// reads, framed by the command line's fitted camera, rendered by clraster and by OpenGL and held
// to the thresholds: Normal shading (coverage within 0.2%, colours within 8/255 on 99% of
// the pixels both cover) and overdraw (fragment counts equal on all but 0.1% of the pixels). Then
// the issue's own check, through the command line exactly as a user runs it.
#include "io/camera.hpp"
#include "io/model_loader.hpp"
#include "support/test_support.hpp"

#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

// Installed by the assimp-testmodels package (scripts/setup.sh).
const fs::path kModels = "/usr/share/assimp/models";

constexpr int kWidth = 640;
constexpr int kHeight = 480;

struct Model {
  const char* name;  // the test case's name
  const char* path;  // under kModels
};

// Every format, small and large (2CylinderEngine: 121,000 triangles), open surfaces (the sphere
// with a hole shows its inside), and glTF scenes whose meshes are placed by node transforms.
const Model kModelFiles[] = {
    {"GltfBinaryEngineWithNodeTransforms", "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"},
    {"GltfSpheresPlacedByNodes", "glTF2/ClearCoat-glTF/ClearCoatTest.gltf"},
    {"GltfBinaryBox", "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"},
    {"ObjSpider", "OBJ/spider.obj"},
    {"ObjWuson", "OBJ/WusonOBJ.obj"},
    {"ObjRegression01", "OBJ/regr01.obj"},
    {"PlyWuson", "PLY/Wuson.ply"},
    {"StlBinarySpider", "STL/Spider_binary.stl"},
    {"StlSphereWithAHole", "STL/sphereWithHole.stl"},
    {"Stl3dsMaxExport", "STL/3DSMaxExport.STL"},
    {"OffWuson", "OFF/Wuson.off"},
};

void PrintTo(const Model& model, std::ostream* stream) { *stream << model.path; }

// Each model is loaded once per process (gtest_discover_tests runs each case in its own anyway).
const io::Mesh& model(const Model& file) {
  static std::map<std::string, io::Mesh> loaded;
  auto found = loaded.find(file.path);
  if (found == loaded.end()) {
    std::vector<std::string> warnings;
    found = loaded.emplace(file.path, io::load_model((kModels / file.path).string(), warnings)).first;
  }
  return found->second;
}

// The command line's default view: io::fit_camera around the model's bounding sphere.
DrawState fitted_view(const io::Mesh& mesh) {
  const float aspect = static_cast<float>(kWidth) / kHeight;
  const io::Camera camera = io::fit_camera(io::bounding_sphere(mesh), aspect);
  DrawState state;
  state.model_view = io::to_mat4(io::view_matrix(camera));
  state.projection = io::to_mat4(io::projection_matrix(camera, aspect));
  return state;
}

class ModelTest : public ::testing::TestWithParam<Model> {
 protected:
  // Renders the model with both renderers and holds clraster to OpenGL's picture, which must show
  // the model over a fair part of the frame.
  void expect_matches_gl(const DrawState& state, const Tolerance& tolerance) {
    const io::Mesh& mesh = model(GetParam());
    const Image reference = render_gl(mesh, state, kWidth, kHeight);
    ASSERT_GT(covered_pixel_count(reference), std::uint64_t{kWidth} * kHeight / 50) << "the model barely shows";
    EXPECT_TRUE(images_match(render_clraster(shared_context(), mesh, state, kWidth, kHeight).image, reference,
                             tolerance));
  }
};

TEST_P(ModelTest, NormalShadingMatchesGl) { expect_matches_gl(fitted_view(model(GetParam())), kNormalShading); }

// Every fragment counted, hidden ones included (no culling, no depth test).
TEST_P(ModelTest, FragmentCountsMatchGl) {
  DrawState state = overdraw_counter();
  const DrawState view = fitted_view(model(GetParam()));
  state.model_view = view.model_view;
  state.projection = view.projection;
  const Tolerance overdraw{1.0, 1.0, 0, std::uint64_t{kWidth} * kHeight / 1000, false};
  expect_matches_gl(state, overdraw);
}

INSTANTIATE_TEST_SUITE_P(Models, ModelTest, ::testing::ValuesIn(kModelFiles),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- The command line ----------------------------------------------------------------------------

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout; stderr goes to the test's own
};

// Runs the built `clraster` executable (CLRASTER_CLI_PATH) with `args`.
CommandResult run_clraster(const std::vector<std::string>& args) {
  std::string command = CLRASTER_CLI_PATH;
  for (const std::string& arg : args) command += " '" + arg + "'";  // no argument here holds a quote
  CommandResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) result.out.append(buffer, n);
  const int status = ::pclose(pipe);
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

class CommandLineTest : public ::testing::TestWithParam<Model> {};

// The "done when": `clraster render MODEL -o a.png`, the same with `--backend gl`, and
// `clraster compare a.png b.png` reporting coverage and colour mismatches within the thresholds.
TEST_P(CommandLineTest, RenderAndCompareAgainstGlWithinTheThresholds) {
  const fs::path directory = fs::path(output_directory()) / "command-line" / GetParam().name;
  fs::create_directories(directory);
  const std::string model_path = (kModels / GetParam().path).string();
  const std::string ours = (directory / "a.png").string();
  const std::string theirs = (directory / "b.png").string();
  ASSERT_EQ(run_clraster({"render", model_path, "-o", ours}).exit_code, 0);
  ASSERT_EQ(run_clraster({"render", model_path, "-o", theirs, "--backend", "gl"}).exit_code, 0);
  const CommandResult compared = run_clraster({"compare", ours, theirs});
  ASSERT_EQ(compared.exit_code, 0) << compared.out;

  const nlohmann::json comparison = nlohmann::json::parse(compared.out);
  EXPECT_GT(comparison.at("covered_b").get<std::uint64_t>(), comparison.at("pixels").get<std::uint64_t>() / 50)
      << comparison;
  EXPECT_LE(comparison.at("coverage_mismatch").get<double>(), kNormalShading.max_coverage_mismatch) << comparison;
  EXPECT_LE(comparison.at("colour_mismatch").get<double>(), kNormalShading.max_colour_mismatch) << comparison;
}

INSTANTIATE_TEST_SUITE_P(Models, CommandLineTest,
                         ::testing::Values(kModelFiles[0], kModelFiles[4], kModelFiles[7]),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clraster::test
