// What the front ends bind, by name, to the program they draw a model with: the built-in material
// program (programs/material.cl, `--shading material`, the Python package's shading="material")
// or a program of the user's (`--program`, clraster.Program). docs/cli.md documents this contract
// for users; the table behind it is in program_contract.cpp.
#pragma once

#include "clraster/clraster.hpp"
#include "io/camera.hpp"

#include <array>
#include <span>
#include <string>
#include <string_view>

namespace clraster::frontend {

// The material program (programs/material.cl, embedded at build time): `--shading material`.
extern const char* const kMaterialProgram;

// The per-vertex data the command line supplies, by attribute name.
inline constexpr const char* kPositionAttribute = "position";  // float3
inline constexpr const char* kNormalAttribute = "normal";      // float3
inline constexpr const char* kUvAttribute = "uv";              // float2: (0, 0) for models without texture coordinates
// The texture the command line binds: the drawn part's base colour texture, or a white one.
inline constexpr const char* kBaseColorTexture = "base_color_texture";

// The uniform values of one draw: those of the view, and the drawn part's base colour.
struct ProgramInputs {
  Mat4 mvp{};            // projection * model_view
  Mat4 model_view{};     // object (the model file's space) to eye space
  Mat4 normal_matrix{};  // the inverse transpose of model_view's upper 3x3, in its upper 3x3
  Mat4 projection{};     // eye to clip space
  std::array<float, 4> base_color{1, 1, 1, 1};       // the material's base colour factor (linear RGBA)
  std::array<float, 3> light_direction{0, 0, 1};     // toward the light, eye space: a headlight
  std::array<float, 2> viewport{};                   // the picture's width and height in pixels

  // The floats of the contract's uniform `name` (column-major for the float16 matrices). Throws
  // std::logic_error for a name the contract does not have.
  std::span<const float> uniform(std::string_view name) const;
};

// The view's inputs for a width x height picture of `camera`, with a white base colour. Matrices are
// computed in double and rounded once to float.
ProgramInputs view_inputs(const io::Camera& camera, int width, int height);
// The same from the camera's matrices (column-major), as front ends that take matrices have them:
// the same inputs when they are io::view_matrix and io::projection_matrix of the camera.
ProgramInputs view_inputs(const Mat4& model_view, const Mat4& projection, int width, int height);

// A program's source, and the file name its errors use.
struct ProgramSource {
  std::string text;
  std::string file_name;
};

// The source of a --program file. Throws InvalidArgument naming the file when it cannot be read.
ProgramSource read_program_file(const std::string& path);

// Who draws with the program, as check_contract's messages name it, and whether it binds uniforms
// and textures of the user's own besides the contract's.
struct ProgramHost {
  const char* name;
  bool binds_users_own;
};
inline constexpr ProgramHost kCommandLine{"the command line", false};
inline constexpr ProgramHost kPythonPackage{"clraster", true};  // clraster.Program's own uniforms and textures

// Reads the program's declarations (without compiling it, so that a program the host cannot serve
// is refused at once) and throws InvalidArgument, naming the file and the declaration's line, for
// the first one the host does not serve: an attribute it does not provide, a uniform or texture it
// does not provide unless it binds the user's own (the message lists what it provides), one of the
// contract's names declared with another type than the contract's or as an array, any buffer, and
// outputs other than exactly one float4 output (the picture). A malformed declaration throws
// InvalidArgument too, as Program's constructor would.
void check_contract(const ProgramSource& program, const ProgramHost& host = kCommandLine);

// Whether `name` is one of the contract's uniforms (those ProgramInputs::uniform gives).
bool provides_uniform(std::string_view name);

// Whether a program declares the base colour texture (then the command line loads the materials'
// textures).
bool declares_base_color_texture(const ProgramInterface& interface);

// Whether a program declares the attribute `name`.
bool declares_attribute(const ProgramInterface& interface, std::string_view name);

}  // namespace clraster::frontend
