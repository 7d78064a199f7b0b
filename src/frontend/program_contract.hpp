// What the command line binds, by name, to the program it draws a model with: the built-in material
// program (programs/material.cl, `--shading material`) or a `--program` file. docs/cli.md documents
// this contract for users; the table behind it is in program_contract.cpp.
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

// A program's source, and the file name its errors use.
struct ProgramSource {
  std::string text;
  std::string file_name;
};

// The source of a --program file. Throws InvalidArgument naming the file when it cannot be read.
ProgramSource read_program_file(const std::string& path);

// Reads the program's declarations (without compiling it, so that a program the command line cannot
// serve is refused at once) and throws InvalidArgument, naming the file and the declaration's line,
// for the first one the command line does not serve: an attribute, uniform or texture it does not
// provide (the message lists what it provides), one declared with another type than the contract's
// or as an array, any buffer, and outputs other than exactly one float4 output (the picture). A
// malformed declaration throws InvalidArgument too, as Program's constructor would.
void check_contract(const ProgramSource& program);

// Whether a program declares the base colour texture (then the command line loads the materials'
// textures).
bool declares_base_color_texture(const ProgramInterface& interface);

// Whether a program declares the attribute `name`.
bool declares_attribute(const ProgramInterface& interface, std::string_view name);

}  // namespace clraster::frontend
