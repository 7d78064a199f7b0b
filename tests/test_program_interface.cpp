// The program interface: what parse_program reads from a program's declarations (types, layouts,
// interpolation, entry points), the errors it gives for malformed ones, and compile errors reported
// at the user's file and line.
#include "api/impl.hpp"
#include "program/interface.hpp"
#include "support/test_support.hpp"

#include <regex>

namespace clraster::test {
namespace {

using program::Interpolation;
using program::parse_program;

const char* const kMinimal = R"(
void vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }
void fragment(clr_fragment* f) {}
)";

std::string with_entry_points(const std::string& declarations) { return declarations + kMinimal; }

// The InvalidArgument message parse_program throws for `source`.
std::string parse_error(const std::string& source) {
  try {
    parse_program(source, "user.cl");
  } catch (const InvalidArgument& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(ProgramInterface, ReadsEveryKindOfDeclarationInOrder) {
  const program::ParsedProgram p = parse_program(with_entry_points(R"(
clr_attribute(float3, position)
clr_attribute(uint2, ids)
clr_varying(float2, uv)
clr_varying_flat(int, material)
clr_varying_noperspective(float, screen_x)
clr_uniform(float16, mvp)
clr_texture(albedo)
clr_buffer(const float4, palette)
clr_buffer(uint, counters)
clr_output(float4, color)
clr_output(uint4, id)
)"), "user.cl");
  const ProgramInterface& in = p.interface;
  ASSERT_EQ(in.attributes.size(), 2u);
  EXPECT_EQ(in.attributes[1].name, "ids");
  EXPECT_EQ(in.attributes[1].type, "uint2");
  EXPECT_EQ(in.attributes[1].line, 3);
  ASSERT_EQ(in.varyings.size(), 3u);
  EXPECT_EQ(in.varyings[1].interpolation, "flat");
  EXPECT_EQ(in.varyings[2].interpolation, "noperspective");
  EXPECT_EQ(in.varyings[2].offset, 3u);  // after uv's two floats and material's one
  EXPECT_EQ(p.varying_floats, (std::vector<Interpolation>{Interpolation::Smooth, Interpolation::Smooth,
                                                           Interpolation::Flat, Interpolation::NoPerspective}));
  ASSERT_EQ(in.textures.size(), 1u);
  EXPECT_EQ(in.textures[0].name, "albedo");
  ASSERT_EQ(in.buffers.size(), 2u);
  EXPECT_FALSE(in.buffers[0].writable);
  EXPECT_TRUE(in.buffers[1].writable);
  ASSERT_EQ(in.outputs.size(), 2u);
  EXPECT_EQ(in.outputs[1].type, "uint4");
  EXPECT_FALSE(in.uses_derivatives);
  EXPECT_FALSE(in.has_depth_test);
  EXPECT_FALSE(in.has_blend);
}

TEST(ProgramInterface, LaysUniformsOutAsOpenClCDoes) {
  const program::ParsedProgram p = parse_program(with_entry_points(R"(
clr_uniform(float, scale)
clr_uniform(float3, light)
clr_uniform(int2, size)
clr_uniform(float16, mvp)
clr_uniform(float3, colors[3])
clr_uniform(uint, flags)
)"), "user.cl");
  const auto& u = p.interface.uniforms;
  ASSERT_EQ(u.size(), 6u);
  EXPECT_EQ(u[0].offset, 0u);
  EXPECT_EQ(u[1].offset, 16u);  // float3 is aligned like float4
  EXPECT_EQ(u[1].bytes, 16u);
  EXPECT_EQ(u[2].offset, 32u);
  EXPECT_EQ(u[3].offset, 64u);  // float16 aligns to 64 bytes
  EXPECT_EQ(u[4].offset, 128u);
  EXPECT_EQ(u[4].array_size, 3);
  EXPECT_EQ(u[4].bytes, 48u);
  EXPECT_EQ(u[5].offset, 176u);
  EXPECT_EQ(p.interface.uniform_bytes, 192u);  // padded to the struct's 64-byte alignment
}

TEST(ProgramInterface, IgnoresDeclarationsInCommentsAndStrings) {
  const program::ParsedProgram p = parse_program(with_entry_points(R"(
// clr_uniform(float, commented)
/* clr_texture(also_commented) */
clr_uniform(float, real)
)"), "user.cl");
  ASSERT_EQ(p.interface.uniforms.size(), 1u);
  EXPECT_EQ(p.interface.uniforms[0].name, "real");
  EXPECT_TRUE(p.interface.textures.empty());
}

TEST(ProgramInterface, FindsOptionalEntryPointsAndWhatTheFragmentProgramUses) {
  const program::ParsedProgram p = parse_program(R"(
clr_texture(t)
void vertex(clr_vertex* v) {}
bool depth_test(clr_fragment* f, float a, float b) { return a > b; }
float4 blend(clr_fragment* f, uint target, float4 s, float4 d) { return s * d; }
void fragment(clr_fragment* f) {
  if (clr_sample(f, f->textures.t, (float2)(0.0f)).x < 0.5f) clr_discard(f);
  f->frag_depth = 0.25f;
}
)", "user.cl");
  EXPECT_TRUE(p.interface.has_depth_test);
  EXPECT_TRUE(p.interface.has_blend);
  EXPECT_TRUE(p.interface.uses_derivatives);
  EXPECT_TRUE(p.may_discard);
  EXPECT_TRUE(p.writes_depth);
}

TEST(ProgramInterface, FindsASpanProgramAndRejectsWhatNeedsOneFragment) {
  const std::string vertex = "void vertex(clr_vertex* v) {}\n";
  const std::string per_span = "void fragment_span(clr_span_fragment* f) {}\n";
  EXPECT_TRUE(parse_program(vertex + per_span, "user.cl").interface.has_fragment_span);
  EXPECT_FALSE(parse_program(with_entry_points(""), "user.cl").interface.has_fragment_span);
  EXPECT_EQ(parse_error(vertex + "void fragment(clr_fragment* f) {}\n" + per_span),
            "user.cl:1: the program defines both void fragment(...) and void fragment_span(...): one fragment program, "
            "per fragment or per span");
  const std::string span_program = vertex + "void fragment_span(clr_span_fragment* f) {\n";
  const std::string advice = " needs a per-fragment program: a program with fragment_span cannot use it (write void "
                             "fragment(clr_fragment* f) instead)";
  EXPECT_EQ(parse_error(span_program + "  clr_discard(f);\n}\n"), "user.cl:3: clr_discard" + advice);
  EXPECT_EQ(parse_error(span_program + "\n  f->frag_depth = 0.5f;\n}\n"), "user.cl:4: frag_depth" + advice);
  // Derivatives and samples are span vectors too: such a program is shaded in quads.
  const auto quads = parse_program(span_program + "  f->out.c = clr_dfdx(f, f->in.x);\n}\n", "user.cl");
  EXPECT_TRUE(quads.interface.has_fragment_span);
  EXPECT_TRUE(quads.interface.uses_derivatives);
  // The first use is the one named.
  EXPECT_EQ(parse_error(span_program + "  f->out.c = clr_framebuffer_fetch(f, 0);\n  clr_discard(f);\n}\n"),
            "user.cl:3: clr_framebuffer_fetch" + advice);
  EXPECT_EQ(parse_error(span_program + "}\nfloat4  blend(clr_fragment* f, uint t, float4 s, float4 d) { return s; }\n"),
            "user.cl:4: float4 blend" + advice);
  EXPECT_EQ(parse_error(span_program + "}\nbool depth_test(clr_fragment* f, float a, float b) { return a < b; }\n"),
            "user.cl:4: bool depth_test" + advice);
}

TEST(ProgramInterface, MalformedDeclarationsNameFileLineAndProblem) {
  EXPECT_EQ(parse_error(with_entry_points("\n\nclr_uniform(vec3, light)\n")),
            "user.cl:3: uniform type 'vec3' is not a float, int or uint vector (1, 2, 3, 4, 8 or 16 components)");
  EXPECT_EQ(parse_error(with_entry_points("clr_varying(int, id)\n")),
            "user.cl:1: integer varying 'id' must be declared with clr_varying_flat (integers are not interpolated)");
  EXPECT_EQ(parse_error(with_entry_points("clr_attribute(float3, p)\nclr_attribute(float2, p)\n")),
            "user.cl:2: attribute 'p' is already declared on line 1");
  EXPECT_EQ(parse_error(with_entry_points("clr_output(float3, color)\n")),
            "user.cl:1: output type 'float3' is not float4, int4 or uint4");
  EXPECT_EQ(parse_error(with_entry_points("clr_texture(a, b)\n")), "user.cl:1: clr_texture takes one argument: (name)");
  EXPECT_EQ(parse_error(with_entry_points("clr_uniform(float, 2x)\n")), "user.cl:1: uniform name '2x' is not an identifier");
  EXPECT_EQ(parse_error(with_entry_points("clr_uniform(float, big[100000])\n")),
            "user.cl:1: uniform array 'big' needs 1 to 65536 elements");
  // More digits than an unsigned long holds: the same error, not an exception of another kind.
  EXPECT_EQ(parse_error(with_entry_points("clr_uniform(float, huge[99999999999999999999999])\n")),
            "user.cl:1: uniform array 'huge' needs 1 to 65536 elements");
  EXPECT_EQ(parse_error("void fragment(clr_fragment* f) {}\n"),
            "user.cl:1: the program defines no vertex program: void vertex(clr_vertex* v) { ... }");
  EXPECT_EQ(parse_error("void vertex(clr_vertex* v) {}\n"),
            "user.cl:1: the program defines no fragment program: void fragment(clr_fragment* f) { ... } (or void "
            "fragment_span(clr_span_fragment* f) { ... })");
  EXPECT_EQ(parse_error("void vertex(clr_vertex* v) { clr_uniform(float, x) }\nvoid fragment(clr_fragment* f) {}"),
            "user.cl:1: clr_uniform must be declared at file scope, outside any function");
  std::string nine_outputs;
  for (int i = 0; i < 9; ++i) nine_outputs += "clr_output(float4, out" + std::to_string(i) + ")\n";
  EXPECT_EQ(parse_error(with_entry_points(nine_outputs)), "user.cl:9: more than 8 outputs (one per colour attachment)");
}

TEST(ProgramInterface, ReadInterfaceReadsTheDeclarationsWithoutCompiling) {
  // The functions would not compile: only the declarations are read.
  const ProgramInterface in = Program::read_interface(
      "clr_attribute(float3, position)\nclr_uniform(float4, tint)\nclr_output(float4, color)\n"
      "void vertex(clr_vertex* v) { v->position = undefined_thing; }\nvoid fragment(clr_fragment* f) {}\n",
      "tool.cl");
  ASSERT_EQ(in.attributes.size(), 1u);
  EXPECT_EQ(in.attributes[0].name, "position");
  ASSERT_EQ(in.uniforms.size(), 1u);
  EXPECT_EQ(in.uniforms[0].type, "float4");
  EXPECT_EQ(in.uniforms[0].line, 2);
  ASSERT_EQ(in.outputs.size(), 1u);
  EXPECT_THROW(Program::read_interface(with_entry_points("clr_uniform(float5, x)\n"), "tool.cl"), InvalidArgument);
}

TEST(ProgramCompile, ErrorsPointAtTheUsersFileAndLine) {
  try {
    Program(shared_context(), "clr_output(float4, color)\nvoid vertex(clr_vertex* v) {\n  v->position = undefined_thing;\n}\n"
                              "void fragment(clr_fragment* f) { f->out.color = (float4)(1.0f); }\n",
            "shaders/broken.cl");
    FAIL() << "the program compiled";
  } catch (const BuildError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("program shaders/broken.cl failed to compile:"), std::string::npos) << message;
    EXPECT_NE(message.find("shaders/broken.cl:3:17: error: use of undeclared identifier 'undefined_thing'"),
              std::string::npos)
        << message;
  }
}

// The BuildError message of compiling `source` as "shaders/user.cl".
std::string build_error(const std::string& source) {
  try {
    Program(shared_context(), source, "shaders/user.cl");
  } catch (const BuildError& error) {
    return error.what();
  }
  return "(compiled)";
}

TEST(ProgramCompile, ErrorsInTheFragmentProgramPointAtTheirLine) {
  const std::string message = build_error(
      "clr_output(float4, color)\n"
      "void vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }\n"
      "void fragment(clr_fragment* f) {\n"
      "  const float4 c = (float4)(1.0f);\n"
      "  f->out.colour = c;\n"
      "}\n");
  EXPECT_NE(message.find("shaders/user.cl:5:10: error: no member named 'colour'"), std::string::npos) << message;
}

// A declared type that does not exist is reported on the declaration's line (the column is where the
// type stands in the generated member, not in the declaration).
TEST(ProgramCompile, AnUnknownTypeInADeclarationPointsAtTheDeclaration) {
  const std::string message = build_error(
      "clr_output(float4, color)\n"
      "\n"
      "clr_buffer(no_such_type, b)\n"
      "void vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }\n"
      "void fragment(clr_fragment* f) { f->out.color = (float4)(1.0f); }\n");
  EXPECT_TRUE(std::regex_search(message, std::regex(R"(shaders/user\.cl:3:[0-9]+: error: unknown type name 'no_such_type')")))
      << message;
}

// Warnings alone do not fail a build.
TEST(ProgramCompile, AProgramWithOnlyWarningsCompiles) {
  EXPECT_EQ(build_error("clr_output(float4, color)\n"
                        "void vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }\n"
                        "void fragment(clr_fragment* f) {\n"
                        "  int unused = 3;\n"
                        "  if (unused = 4) f->out.color = (float4)(1.0f);\n"  // assignment as a condition
                        "}\n"),
            "(compiled)");
}

TEST(ProgramCompile, ErrorsInsideBuiltInsPointAtTheUsersLineToo) {
  // PoCL's fract is a macro: clang places the error in the user's line and in PoCL's header.
  try {
    Program(shared_context(), "clr_output(float4, color)\nvoid vertex(clr_vertex* v) {}\n"
                              "void fragment(clr_fragment* f) { f->out.color = fract(f->frag_coord); }\n",
            "shaders/one_argument.cl");
    FAIL() << "the program compiled";
  } catch (const BuildError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("\nshaders/one_argument.cl:3:49: error: no matching function for call to "), std::string::npos)
        << message;
    EXPECT_EQ(message.find("Spelling"), std::string::npos) << message;
  }
}

TEST(ProgramCompile, AMissingFileIsAnError) {
  EXPECT_THROW(
      {
        try {
          Program::load(shared_context(), "/nonexistent/program.cl");
        } catch (const InvalidArgument& error) {
          EXPECT_STREQ(error.what(), "cannot read program file /nonexistent/program.cl: No such file or directory");
          throw;
        }
      },
      InvalidArgument);
}

}  // namespace
}  // namespace clraster::test
