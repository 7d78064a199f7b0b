// clraster: the command-line renderer. Parses the command line (CLI11) and hands over to the
// subcommands in render_command.cpp, compare_command.cpp and bench_command.cpp.
#include "bench/runner.hpp"
#include "bench/scenes.hpp"
#include "cli/commands.hpp"
#include "cli/isolated_render.hpp"
#include "io/format.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <charconv>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <iostream>
#include <map>
#include <vector>

namespace {

using namespace clraster;
using namespace clraster::cli;

const std::string kSizeHelp = "Picture size WIDTHxHEIGHT, each 1.." + std::to_string(kMaxFramebufferSize);

// One side of --size: an integer (too large to represent counts as too large), else nothing.
std::optional<long long> parse_side(std::string_view text) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || end != text.data() + text.size()) return std::nullopt;
  if (error == std::errc::result_out_of_range) return std::numeric_limits<long long>::max();
  if (error != std::errc()) return std::nullopt;
  return value;
}

// "1920x1080" -> width, height in 1..kMaxFramebufferSize.
void parse_size(const std::string& text, int& width, int& height) {
  const std::size_t x = text.find_first_of("xX");
  const std::optional<long long> w = x == std::string::npos ? std::nullopt : parse_side(std::string_view(text).substr(0, x));
  const std::optional<long long> h = x == std::string::npos ? std::nullopt : parse_side(std::string_view(text).substr(x + 1));
  if (!w || !h) throw UsageError("--size: expected WIDTHxHEIGHT, e.g. 1920x1080, got '" + text + "'");
  if (*w < 1 || *h < 1 || *w > kMaxFramebufferSize || *h > kMaxFramebufferSize) {
    throw UsageError("--size " + text + " is out of range: each side must be 1.." +
                          std::to_string(kMaxFramebufferSize));
  }
  width = static_cast<int>(*w);
  height = static_cast<int>(*h);
}

// The options of the clraster context that render and bench share.
void add_context_options(CLI::App* command, int& device, std::size_t& memory_cap_mib, int& tile_size) {
  command->add_option("--device", device, "OpenCL device index (see `clraster devices`; default: $CLRASTER_DEVICE, else 0)")
      ->check(CLI::Range(0, 1 << 20));
  command->add_option("--memory-cap", memory_cap_mib, "Cap on the pipeline's intermediate buffers, MiB")
      ->check(CLI::Range(std::size_t{kMinMemoryCap >> 20}, std::size_t{1} << 20))
      ->capture_default_str();
  command->add_option("--tile-size", tile_size,
                      "Pixels per tile side: 8, 16 or 32 (default: the device's, 32 on CPUs, 16 on GPUs)")
      ->check(CLI::IsMember(std::vector<int>(kTileSizes.begin(), kTileSizes.end())));
}

// CLI11 takes "-3,1,2" after "--eye" for an option name; joining such a value to its option
// ("--eye=-3,1,2") lets both spellings work.
std::vector<std::string> join_negative_values(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::vector<std::string> joined;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& next = i + 1 < args.size() ? args[i + 1] : std::string();
    const bool negative_number = next.size() > 1 && next[0] == '-' &&
                                 (std::isdigit(static_cast<unsigned char>(next[1])) || next[1] == '.');
    if (args[i].rfind("--", 0) == 0 && args[i].find('=') == std::string::npos && negative_number) {
      joined.push_back(args[i] + "=" + next);
      ++i;
    } else {
      joined.push_back(args[i]);
    }
  }
  std::reverse(joined.begin(), joined.end());  // CLI11 parses a vector from its back
  return joined;
}

}  // namespace

namespace clraster::cli {
namespace {

// The length of the character at text[i] when it is safe to print as it is: printable ASCII, a
// newline or a tab, or a well-formed UTF-8 sequence (no overlong form, surrogate or code point past
// U+10FFFF) that is not a C1 control (U+0080..U+009F); 0 for anything else.
std::size_t printable_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u; };
  const auto continued = [&](std::size_t count) {
    for (std::size_t k = 1; k <= count; ++k) {
      if ((byte(k) & 0xc0) != 0x80) return false;
    }
    return true;
  };
  const unsigned lead = byte(0), second = byte(1);
  if (lead < 0x80) return (lead >= 0x20 && lead != 0x7f) || lead == '\n' || lead == '\t' ? 1 : 0;
  if (lead >= 0xc2 && lead <= 0xdf) return continued(1) && !(lead == 0xc2 && second < 0xa0) ? 2 : 0;
  if (lead >= 0xe0 && lead <= 0xef) {
    return continued(2) && !(lead == 0xe0 && second < 0xa0) && !(lead == 0xed && second > 0x9f) ? 3 : 0;
  }
  if (lead >= 0xf0 && lead <= 0xf4) {
    return continued(3) && !(lead == 0xf0 && second < 0x90) && !(lead == 0xf4 && second > 0x8f) ? 4 : 0;
  }
  return 0;
}

}  // namespace

std::string printable(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    if (const std::size_t length = printable_length(text, i); length > 0) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      const auto byte = static_cast<unsigned char>(text[i++]);
      out += {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
    }
  }
  return out;
}

// The exit code of `command`, or of the exception it throws, which is printed.
int exit_code_of(const std::function<int()>& command) {
  try {
    return command();
  } catch (const UsageError& error) {
    std::cerr << "clraster: error: " << printable(error.what()) << '\n';
    return 2;
  } catch (const BuildError& error) {
    // A program's what() holds the compiler's errors already, in FILE:LINE:COLUMN form
    // (docs/programs.md): printed as they are, under the first line. Other builds (the pipeline's
    // own kernels) say only which program failed: the compiler's log follows.
    std::cerr << "clraster: error: " << printable(error.what()) << '\n';
    if (std::string_view(error.what()).find('\n') == std::string_view::npos) std::cerr << printable(error.log()) << '\n';
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "clraster: error: " << printable(error.what()) << '\n';
    return 1;
  }
}

}  // namespace clraster::cli

int main(int argc, char** argv) {
  CLI::App app{"clraster: a programmable graphics pipeline in OpenCL kernels, on any OpenCL device.", "clraster"};
  app.set_version_flag("--version", std::string("clraster ") + clraster::version());
  app.require_subcommand(1);

  RenderOptions render_options;
  std::string size = "1280x720", eye, target, up;
  float near_plane = 0, far_plane = 0;
  std::size_t memory_cap_mib = kDefaultMemoryCap >> 20;
  CLI::App* render = app.add_subcommand("render", "Render a model file (or the built-in demo scene) to a PNG picture");
  render->add_option("model", render_options.model, "Model file: OBJ, glTF 2.0 (.gltf/.glb), PLY, STL, OFF, ... "
                                                     "(default: the built-in demo scene)");
  render->add_option("-o,--output", render_options.output, "PNG file to write")->required();
  render->add_option("--size", size, kSizeHelp)->capture_default_str();
  render->add_option("--eye", eye, "Camera position X,Y,Z (default: fitted to the scene's bounding sphere)");
  render->add_option("--target", target, "Point the camera looks at X,Y,Z (default: the bounding sphere's centre)");
  render->add_option("--up", up, "Camera up direction X,Y,Z (default: 0,1,0)");
  render->add_option("--fov", render_options.fov_degrees, "Vertical field of view in degrees, in (0, 180)")
      ->capture_default_str();
  CLI::Option* near_option = render->add_option("--near", near_plane, "Near plane distance (default: fitted)");
  CLI::Option* far_option = render->add_option("--far", far_plane, "Far plane distance (default: fitted)");
  CLI::Option* shading =
      render
          ->add_option("--shading", render_options.shading,
                       "normal: object-space normal as colour; lambert: grey lit by a headlight; depth: view "
                       "distance as grey, near white; overdraw: red = fragments per pixel, no depth test; "
                       "material: the model's materials (base colour texture times factor) lit by a headlight")
          ->transform(CLI::CheckedTransformer(std::map<std::string, ShadingOption>{{"normal", ShadingOption::Normal},
                                                                                   {"lambert", ShadingOption::Lambert},
                                                                                   {"depth", ShadingOption::Depth},
                                                                                   {"overdraw", ShadingOption::Overdraw},
                                                                                   {"material", ShadingOption::Material}},
                                              CLI::ignore_case))
          ->option_text("normal|lambert|depth|overdraw|material (default: normal)");
  render
      ->add_option("--program", render_options.program,
                   "Draw with this OpenCL C program file instead of a --shading mode (docs/cli.md says what it "
                   "can declare); not with --shading")
      ->excludes(shading)
      ->option_text("FILE.cl");
  render->add_option("--cull", render_options.cull, "Face culling: none, back or front")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, CullMode>{{"none", CullMode::None}, {"back", CullMode::Back}, {"front", CullMode::Front}},
          CLI::ignore_case))
      ->option_text("none|back|front (default: none)");
  render->add_option("--frames", render_options.frames, "Timed frames after one warm-up frame")
      ->check(CLI::Range(0, 100000));
  render->add_flag("--stats", render_options.stats, "Print one JSON line of statistics and timings");
  render->add_option("--backend", render_options.backend, "clraster, or gl: the same scene with the system's OpenGL")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Backend>{{"clraster", Backend::Clraster}, {"gl", Backend::Gl}},
                                          CLI::ignore_case))
      ->option_text("clraster|gl (default: clraster)");
  add_context_options(render, render_options.device, memory_cap_mib, render_options.tile_size);
  CLI::Option* time_limit = render->add_option("--time-limit", render_options.time_limit_seconds,
                     "Stop the render when its frames (after programs are built) take longer than this many seconds: "
                     "a program that loops for ever ends in an error (default: no limit)")
      ->option_text("SECONDS");
  std::size_t model_memory_mib = 0;
  double model_seconds = 0;
  CLI::Option* model_memory =
      render
          ->add_option("--model-memory-limit", model_memory_mib,
                       "Memory the model file's loader may use, MiB (default: " +
                           std::to_string(io::kLoadMemoryPerFileByte) + " times the file's size, at least " +
                           std::to_string(io::kLoadMemoryFloor >> 20) + ")")
          ->check(CLI::Range(std::size_t{64}, std::size_t{1} << 24));  // assimp's OBJ reader alone takes 16 MiB
  CLI::Option* model_time =
      render
          ->add_option("--model-time-limit", model_seconds,
                       "Time the model file's loader may take, seconds (default: " +
                           std::to_string(io::kLoadTimePerMiB.count()) + " per MiB of the file, at least " +
                           std::to_string(io::kLoadTimeFloor.count()) + ")")
          ->check(CLI::Range(0.001, 1e6));

  CompareOptions compare_options;
  CLI::App* compare = app.add_subcommand("compare", "Print, as JSON, how far two pictures differ");
  compare->add_option("a", compare_options.a, "First picture")->required();
  compare->add_option("b", compare_options.b, "Second picture")->required();
  compare->add_option("--threshold", compare_options.threshold,
                      "Largest channel difference that still counts as the same colour")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  compare->add_option("--diff", compare_options.diff_output, "Also write a picture of the differences");

  BenchOptions bench_options;
  std::string bench_size = "1920x1080";
  std::size_t bench_memory_cap_mib = kDefaultMemoryCap >> 20;
  CLI::App* bench = app.add_subcommand(
      "bench", "Time fixed scenes (procedural meshes, and assimp's engine model) drawn by clraster and by Mesa's "
               "OpenGL (llvmpipe) in turn, and check that both draw the same pictures");
  bench->add_option("--scenes", bench_options.scenes,
                    "Comma-separated scenes to run, of " + bench::scene_names_text() + " (default: all)")
      ->option_text("NAME,...");
  const std::string view_size = std::to_string(bench::kViewSide) + "x" + std::to_string(bench::kViewSide);
  bench->add_option("--size", bench_size, kSizeHelp + " (views-64's 64 views are " + view_size + " at any size)")
      ->capture_default_str();
  bench
      ->add_option("--frames", bench_options.frames,
                   "Timed frames of each renderer per scene, after " + std::to_string(bench::kWarmupFrames) +
                       " warm-up frames")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  bench->add_flag("--json", bench_options.json, "Print one JSON object instead of the table");
  add_context_options(bench, bench_options.device, bench_memory_cap_mib, bench_options.tile_size);
  bench->add_option("--pictures", bench_options.pictures,
                    "Write each scene's pictures into this directory: SCENE-clraster.png, SCENE-llvmpipe.png and "
                    "SCENE-diff.png")
      ->option_text("DIR");

  CLI::App* devices = app.add_subcommand("devices", "List the OpenCL devices");

  // CLI11 would call an unknown command a missing one; name it instead.
  const std::vector<CLI::App*> commands = app.get_subcommands({});
  if (argc > 1 && argv[1][0] != '-' &&
      std::none_of(commands.begin(), commands.end(), [&](CLI::App* c) { return c->get_name() == argv[1]; })) {
    std::string names;
    for (const CLI::App* command : commands) names += (names.empty() ? "" : ", ") + command->get_name();
    std::cerr << "clraster: error: unknown command '" << printable(argv[1]) << "' (commands: " << names << "; see --help)\n";
    return 2;
  }
  try {
    app.parse(join_negative_values(argc, argv));
  } catch (const CLI::CallForHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return app.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return app.exit(version);
  } catch (const CLI::ParseError& error) {
    std::cerr << "clraster: error: " << printable(error.what()) << " (see clraster --help)\n";
    return 2;
  }

  // What each command returns; a render of a user's program or with a time limit in a process of its own.
  const auto command = [&]() -> int {
    if (*render) {
      parse_size(size, render_options.width, render_options.height);
      const auto vector_option = [](const std::string& text, const char* name) {
        return as_usage_error([&] { return io::parse_vec3(text, name); });
      };
      if (!eye.empty()) render_options.eye = vector_option(eye, "--eye");
      if (!target.empty()) render_options.target = vector_option(target, "--target");
      if (!up.empty()) render_options.up = vector_option(up, "--up");
      if (*near_option) render_options.near_plane = near_plane;
      if (*far_option) render_options.far_plane = far_plane;
      // The camera's own numbers, before any work: a fitted camera is checked as a whole later.
      as_usage_error([&] {
        io::validate_lens(render_options.fov_degrees, render_options.near_plane, render_options.far_plane);
      });
      render_options.memory_cap = memory_cap_mib << 20;
      if (*model_memory) render_options.model_limits.memory_bytes = model_memory_mib << 20;
      if (*model_time) {
        render_options.model_limits.time = std::chrono::milliseconds(static_cast<std::int64_t>(model_seconds * 1000));
      }
      return cli::render(render_options);
    }
    if (*compare) return cli::compare(compare_options);
    if (*bench) {
      parse_size(bench_size, bench_options.width, bench_options.height);
      bench_options.memory_cap = bench_memory_cap_mib << 20;
      return cli::bench(bench_options);
    }
    if (*devices) return cli::devices();
    return 0;
  };
  return exit_code_of([&] {
    const bool limited = time_limit->count() > 0;
    if (!*render || (render_options.program.empty() && !limited)) return command();
    if (limited && !(render_options.time_limit_seconds > 0 && render_options.time_limit_seconds <= 1e6)) {
      throw UsageError("--time-limit: expected seconds in (0, 1000000], got " +
                       io::format_number(render_options.time_limit_seconds));
    }
    const std::optional<double> seconds =
        limited ? std::optional<double>(render_options.time_limit_seconds) : std::nullopt;
    return run_isolated(seconds, [&](const std::function<void()>& start_clock) {
      render_options.frames_starting = start_clock;
      return exit_code_of(command);
    });
  });
}

