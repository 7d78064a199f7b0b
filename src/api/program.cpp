#include "api/errors.hpp"
#include "api/impl.hpp"
#include "program/generator.hpp"
#include "program/includes.hpp"
#include "runtime/files.hpp"

#include <cstring>
#include <optional>
#include <regex>
#include <sstream>

namespace clraster {
namespace {

// A compiler diagnostic as "FILE:LINE:COLUMN: severity: message": clang's own form, or PoCL's
// rewrite of it, "severity: FILE:LINE:COLUMN: message". Where the error is in a macro's expansion
// (PoCL's built-ins are macros: fract is _cl_fract), the location is followed by
// " <Spelling=HEADER:LINE:COLUMN>", which is left out: the user's line is what matters.
struct Diagnostic {
  std::string text;
  bool error = false;
  bool in_user_file = false;
};

std::optional<Diagnostic> parse_diagnostic(const std::string& line, const std::string& file_name) {
  static const std::regex clang_form(R"(^(.+?):(\d+):(\d+)(?: <Spelling=[^>]*>)?: (error|warning|note): (.*)$)");
  static const std::regex pocl_form(R"(^(error|warning|note): (.+?):(\d+):(\d+)(?: <Spelling=[^>]*>)?: (.*)$)");
  std::smatch m;
  std::string file, line_number, column, severity, message;
  if (std::regex_match(line, m, pocl_form)) {
    severity = m[1], file = m[2], line_number = m[3], column = m[4], message = m[5];
  } else if (std::regex_match(line, m, clang_form)) {
    file = m[1], line_number = m[2], column = m[3], severity = m[4], message = m[5];
  } else {
    return std::nullopt;
  }
  return Diagnostic{file + ":" + line_number + ":" + column + ": " + severity + ": " + message, severity == "error",
                    file == file_name};
}

// The compiler's errors in the usual FILE:LINE:COLUMN: form, each with the source line and caret
// clang prints under it. Errors in the user's file come first; the generated program puts the
// user's source under #line 1 "file_name", so its lines are the user's.
std::string compile_errors(const std::string& log, const std::string& file_name) {
  std::istringstream lines(log);
  std::string line, user, other;
  std::string* block = nullptr;
  while (std::getline(lines, line)) {
    if (const std::optional<Diagnostic> d = parse_diagnostic(line, file_name)) {
      block = !d->error ? nullptr : d->in_user_file ? &user : &other;
      if (block != nullptr) *block += d->text + "\n";
    } else if (block != nullptr && line.find("failed to build") == std::string::npos) {
      *block += line + "\n";
    }
  }
  std::string errors = user + other;
  if (errors.empty()) errors = log;  // not a compiler's format: show the whole log
  while (!errors.empty() && errors.back() == '\n') errors.pop_back();
  return errors;
}

std::size_t element_bytes(const ProgramVariable& u) {
  const program::VectorType vector = program::vector_type(u.type);
  // What the user passes per element: the declared components (a float3 takes 12 bytes).
  if (vector.components != 0) return 4u * static_cast<unsigned>(vector.components);
  return u.bytes / static_cast<std::size_t>(std::max(u.array_size, 1));
}

// The room one element takes in the uniform block (three components take four).
std::size_t element_stride(const ProgramVariable& u) { return u.bytes / static_cast<std::size_t>(std::max(u.array_size, 1)); }

std::string scalar_of(const std::string& type) {
  for (const char* scalar : {"float", "uint", "int"}) {
    if (type.starts_with(scalar)) return scalar;
  }
  return type;
}

template <typename Variables>
std::size_t find(const Variables& variables, const std::string& name, const char* kind, const std::string& file) {
  for (std::size_t i = 0; i < variables.size(); ++i) {
    if (variables[i].name == name) return i;
  }
  throw InvalidArgument("program " + file + " declares no " + kind + " '" + name + "'");
}

}  // namespace

std::unique_ptr<Program::Impl> compile_program(const std::shared_ptr<ContextState>& state, const std::string& source,
                                               const std::string& file_name) {
  auto impl = std::make_unique<Program::Impl>();
  impl->state = state;
  impl->file_name = file_name;
  const std::string resolved = program::resolve_includes(source, file_name);
  impl->parsed = program::parse_program(resolved, file_name);
  const DeviceInfo& device = state->device.info;
  const std::size_t uniform_bytes = impl->parsed.interface.uniform_bytes;
  if (uniform_bytes > device.constant_buffer_bytes) {
    throw InvalidArgument("program " + file_name + "'s uniforms take " + std::to_string(uniform_bytes) +
                          " bytes; device " + device.name + " has " + std::to_string(device.constant_buffer_bytes) +
                          " of constant memory for them");
  }
  const std::string text = program::generate_stage_program(impl->parsed, resolved, file_name);
  // The context's tile size, or, where the context chose it and the program's stages need more than
  // the device has at that size (local memory for the tile's attachments, work-items for its pixels),
  // the largest smaller one they fit.
  for (impl->tile_size = state->options.tile_size;; impl->tile_size /= 2) {
    try {
      impl->program = translate_cl_errors(
          [&] { return state->programs.get(file_name, text, state->stage_build_options(impl->tile_size)); });
    } catch (const BuildError& error) {
      throw BuildError("program " + file_name + " failed to compile:\n" + compile_errors(error.log(), file_name),
                       error.log());
    }
    const std::optional<runtime::KernelExcess> excess =
        translate_cl_errors([&] { return runtime::kernel_beyond_limits(impl->program, state->device); });
    if (!excess) return impl;
    if (!excess->tile_bound) {
      throw InvalidArgument("program " + file_name + " cannot run: its " + excess->description +
                            ": use fewer textures, buffers, outputs or attributes");
    }
    if (!state->tile_size_chosen || impl->tile_size == kTileSizes.front()) {
      throw InvalidArgument("program " + file_name + " cannot run with " + std::to_string(impl->tile_size) + "x" +
                            std::to_string(impl->tile_size) + " tiles: its " + excess->description +
                            (impl->tile_size > kTileSizes.front() ? ": use a smaller tile size" : "") +
                            ", or fewer outputs or varyings");
    }
  }
}

Program::Program(Context& context, std::string source, std::string file_name)
    : impl_(compile_program(context.impl().state, source, file_name)) {}
Program::Program(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Program Program::load(Context& context, const std::string& path) { return Program(context, read_source(path), path); }

std::string Program::read_source(const std::string& path) {
  runtime::FileContents file = runtime::read_regular_file(path, std::uintmax_t{CLR_MAX_PROGRAM_SOURCE_MIB} << 20);
  if (!file) throw InvalidArgument("cannot read program file " + path + ": " + file.problem);
  return std::move(file.bytes);
}

ProgramInterface Program::read_interface(const std::string& source, const std::string& file_name) {
  return program::parse_program(program::resolve_includes(source, file_name), file_name).interface;
}

Program::~Program() = default;
Program::Program(Program&&) noexcept = default;
Program& Program::operator=(Program&&) noexcept = default;
const std::string& Program::file_name() const { return impl_->file_name; }
const ProgramInterface& Program::interface() const { return impl_->parsed.interface; }

// ---- Bindings ---------------------------------------------------------------------------------

Bindings::Bindings(const Program& program) : impl_(std::make_unique<Impl>()) {
  const ProgramInterface& in = program.interface();
  impl_->program = &program.impl();
  impl_->uniforms.assign(in.uniform_bytes, std::byte{0});
  impl_->uniform_set.assign(in.uniforms.size(), false);
  impl_->textures.resize(in.textures.size());
  impl_->buffers.assign(in.buffers.size(), nullptr);
}
Bindings::~Bindings() = default;
Bindings::Bindings(const Bindings& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Bindings& Bindings::operator=(const Bindings& other) {
  *impl_ = *other.impl_;
  return *this;
}
Bindings::Bindings(Bindings&&) noexcept = default;
Bindings& Bindings::operator=(Bindings&&) noexcept = default;

Bindings& Bindings::set_bytes(const std::string& name, std::span<const std::byte> bytes, int element) {
  const Program::Impl& program = *impl_->program;
  const auto& uniforms = program.parsed.interface.uniforms;
  const std::size_t index = find(uniforms, name, "uniform", program.file_name);
  const ProgramVariable& u = uniforms[index];
  const std::size_t elements = static_cast<std::size_t>(std::max(u.array_size, 1));
  const std::size_t size = element_bytes(u);
  if (element < 0 || static_cast<std::size_t>(element) >= elements) {
    throw InvalidArgument("uniform '" + name + "' has " + std::to_string(elements) + " element(s); element " +
                          std::to_string(element) + " does not exist");
  }
  const std::size_t available = elements - static_cast<std::size_t>(element);
  if (bytes.empty() || bytes.size() % size != 0 || bytes.size() / size > available) {
    throw InvalidArgument("uniform '" + name + "' is " + u.type + (u.array_size ? "[" + std::to_string(u.array_size) + "]" : "") +
                          ": expected a multiple of " + std::to_string(size) + " bytes for at most " +
                          std::to_string(available) + " element(s), got " + std::to_string(bytes.size()) + " bytes");
  }
  for (std::size_t i = 0; i < bytes.size() / size; ++i) {
    std::memcpy(impl_->uniforms.data() + u.offset + (static_cast<std::size_t>(element) + i) * element_stride(u),
                bytes.data() + i * size, size);
  }
  impl_->uniform_set[index] = true;
  return *this;
}

namespace {

void check_scalar(const Program::Impl& program, const std::string& name, const char* scalar) {
  const auto& uniforms = program.parsed.interface.uniforms;
  const ProgramVariable& u = uniforms[find(uniforms, name, "uniform", program.file_name)];
  if (scalar_of(u.type) != scalar) {
    throw InvalidArgument("uniform '" + name + "' is " + u.type + ", not " + scalar + " data");
  }
}

}  // namespace

Bindings& Bindings::set(const std::string& name, float value) {
  check_scalar(*impl_->program, name, "float");
  return set_bytes(name, std::as_bytes(std::span<const float>(&value, 1)));
}
Bindings& Bindings::set(const std::string& name, std::int32_t value) {
  check_scalar(*impl_->program, name, "int");
  return set_bytes(name, std::as_bytes(std::span<const std::int32_t>(&value, 1)));
}
Bindings& Bindings::set(const std::string& name, std::uint32_t value) {
  check_scalar(*impl_->program, name, "uint");
  return set_bytes(name, std::as_bytes(std::span<const std::uint32_t>(&value, 1)));
}

Bindings& Bindings::set_texture(const std::string& name, const Texture& texture, const Sampler& sampler) {
  const Program::Impl& program = *impl_->program;
  const std::size_t index = find(program.parsed.interface.textures, name, "texture", program.file_name);
  if (texture.impl().state != program.state) throw InvalidArgument("texture '" + name + "' belongs to another context than the program");
  const FormatInfo& info = format_info(texture.format());
  if (info.integer && (sampler.mag_filter != Filter::Nearest || sampler.min_filter != Filter::Nearest ||
                       sampler.mip_filter == MipFilter::Linear)) {
    throw InvalidArgument("texture '" + name + "' has the integer format " + info.name +
                          ", which cannot be filtered: use a Nearest sampler and read it with clr_texel_fetch");
  }
  impl_->textures[index] = {&texture.impl(), sampler};
  return *this;
}

Bindings& Bindings::set_buffer(const std::string& name, const Buffer& buffer) {
  const Program::Impl& program = *impl_->program;
  const std::size_t index = find(program.parsed.interface.buffers, name, "buffer", program.file_name);
  if (buffer.impl().state != program.state) throw InvalidArgument("buffer '" + name + "' belongs to another context than the program");
  impl_->buffers[index] = &buffer.impl();
  return *this;
}

}  // namespace clraster
