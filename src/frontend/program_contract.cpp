#include "frontend/program_contract.hpp"

#include <algorithm>
#include <string>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace clraster::frontend {
namespace {

struct ProvidedAttribute {
  const char* name;
  const char* type;
};

constexpr ProvidedAttribute kAttributes[] = {
    {kPositionAttribute, "float3"},
    {kNormalAttribute, "float3"},
    {kUvAttribute, "float2"},
};

struct ProvidedUniform {
  const char* name;
  const char* type;
  std::span<const float> (*value)(const ProgramInputs& inputs);
};

constexpr ProvidedUniform kUniforms[] = {
    {"mvp", "float16", [](const ProgramInputs& in) { return std::span<const float>(in.mvp); }},
    {"model_view", "float16", [](const ProgramInputs& in) { return std::span<const float>(in.model_view); }},
    {"normal_matrix", "float16", [](const ProgramInputs& in) { return std::span<const float>(in.normal_matrix); }},
    {"projection", "float16", [](const ProgramInputs& in) { return std::span<const float>(in.projection); }},
    {"base_color", "float4", [](const ProgramInputs& in) { return std::span<const float>(in.base_color); }},
    {"light_direction", "float3", [](const ProgramInputs& in) { return std::span<const float>(in.light_direction); }},
    {"viewport", "float2", [](const ProgramInputs& in) { return std::span<const float>(in.viewport); }},
};

// "attributes position (float3), ...; uniforms mvp (float16), ...; texture base_color_texture; one
// float4 output": everything the contract provides, for error messages.
std::string provided_names() {
  std::string text = "attributes ";
  for (const ProvidedAttribute& a : kAttributes) text += std::string(a.name) + " (" + a.type + "), ";
  text.replace(text.size() - 2, 2, "; uniforms ");
  for (const ProvidedUniform& u : kUniforms) text += std::string(u.name) + " (" + u.type + "), ";
  text.replace(text.size() - 2, 2, "; texture ");
  return text + kBaseColorTexture + "; one float4 output";
}

std::string declared_at(const std::string& file_name, const ProgramVariable& variable) {
  return "program " + file_name + " (line " + std::to_string(variable.line) + ") declares ";
}

// Checks one declaration against the contract's name of that kind: `provided_type` is null when the
// contract has no such name (textures have the type "texture").
void check_declaration(const std::string& program, const std::string& host, const char* kind,
                       const ProgramVariable& declared, const char* provided_type) {
  if (provided_type == nullptr) {
    throw InvalidArgument(declared_at(program, declared) + kind + " '" + declared.name + "', which " + host +
                          " does not provide (it provides " + provided_names() + ")");
  }
  if (declared.array_size != 0) {
    throw InvalidArgument(declared_at(program, declared) + kind + " '" + declared.name + "' as an array of " +
                          std::to_string(declared.array_size) + "; " + host + " provides one " + provided_type);
  }
  if (declared.type != provided_type) {
    throw InvalidArgument(declared_at(program, declared) + kind + " '" + declared.name + "' as " + declared.type +
                          "; " + host + " provides it as " + provided_type);
  }
}

template <typename Table>
const char* provided_type(const Table& table, const std::string& name) {
  const auto found = std::find_if(std::begin(table), std::end(table), [&](const auto& entry) { return entry.name == name; });
  return found == std::end(table) ? nullptr : found->type;
}

}  // namespace

std::span<const float> ProgramInputs::uniform(std::string_view name) const {
  for (const ProvidedUniform& u : kUniforms) {
    if (u.name == name) return u.value(*this);
  }
  throw std::logic_error("the contract has no uniform '" + std::string(name) + "'");
}

ProgramInputs view_inputs(const io::Camera& camera, int width, int height) {
  return view_inputs(io::to_mat4(io::view_matrix(camera)),
                     io::to_mat4(io::projection_matrix(camera, static_cast<float>(width) / static_cast<float>(height))),
                     width, height);
}

ProgramInputs view_inputs(const Mat4& model_view, const Mat4& projection_matrix, int width, int height) {
  const glm::dmat4 view(glm::make_mat4(model_view.data()));
  const glm::dmat4 projection(glm::make_mat4(projection_matrix.data()));
  ProgramInputs inputs;
  inputs.mvp = io::to_mat4(glm::mat4(projection * view));
  inputs.model_view = io::to_mat4(glm::mat4(view));
  // glm::dmat4 of a 3x3 matrix puts it in the upper left, the rest as the identity.
  inputs.normal_matrix = io::to_mat4(glm::mat4(glm::dmat4(glm::inverseTranspose(glm::dmat3(view)))));
  inputs.projection = io::to_mat4(glm::mat4(projection));
  inputs.viewport = {static_cast<float>(width), static_cast<float>(height)};
  return inputs;
}

ProgramSource read_program_file(const std::string& path) { return {Program::read_source(path), path}; }

void check_contract(const ProgramSource& source, const ProgramHost& host) {
  const ProgramInterface interface = Program::read_interface(source.text, source.file_name);
  const std::string& program = source.file_name;
  for (const ProgramVariable& attribute : interface.attributes) {
    check_declaration(program, host.name, "attribute", attribute, provided_type(kAttributes, attribute.name));
  }
  for (const ProgramVariable& uniform : interface.uniforms) {
    const char* type = provided_type(kUniforms, uniform.name);
    if (type != nullptr || !host.binds_users_own) check_declaration(program, host.name, "uniform", uniform, type);
  }
  for (const ProgramVariable& texture : interface.textures) {
    const bool provided = texture.name == kBaseColorTexture;
    if (provided || !host.binds_users_own) {
      check_declaration(program, host.name, "texture", texture, provided ? "texture" : nullptr);
    }
  }
  for (const ProgramVariable& buffer : interface.buffers) {
    check_declaration(program, host.name, "buffer", buffer, nullptr);
  }
  if (interface.outputs.size() != 1) {
    throw InvalidArgument("program " + program + " declares " + std::to_string(interface.outputs.size()) +
                          " outputs; " + host.name + " draws exactly one, a float4: the picture");
  }
  const ProgramVariable& output = interface.outputs.front();
  if (output.type != "float4") {
    throw InvalidArgument(declared_at(program, output) + "output '" + output.name + "' as " + output.type +
                          "; " + host.name + " draws one float4 output: the picture");
  }
}

bool provides_uniform(std::string_view name) { return provided_type(kUniforms, std::string(name)) != nullptr; }

bool declares_base_color_texture(const ProgramInterface& interface) {
  const auto& textures = interface.textures;
  return std::any_of(textures.begin(), textures.end(), [](const ProgramVariable& t) { return t.name == kBaseColorTexture; });
}

bool declares_attribute(const ProgramInterface& interface, std::string_view name) {
  const auto& attributes = interface.attributes;
  return std::any_of(attributes.begin(), attributes.end(), [&](const ProgramVariable& a) { return a.name == name; });
}

}  // namespace clraster::frontend
