#include "program/generator.hpp"

#include "runtime/kernel_sources.hpp"
#include "shared/types.h"

#include <algorithm>
#include <sstream>

namespace clraster::program {
namespace {

// Varyings travel as at least one float: OpenCL C has no empty arrays.
std::size_t varying_float_count(const ParsedProgram& p) { return std::max<std::size_t>(p.varying_floats.size(), 1); }

const char* const kComponent[] = {".s0", ".s1", ".s2", ".s3"};

// Component c of `access`, a value of `components` components (scalars have none: `access` itself).
std::string component(const std::string& access, int components, int c) {
  return components == 1 ? access : access + kComponent[c];
}

constexpr const char* kInterfaceName = "<clraster generated interface>";

// The span program's type of a value of `type` (float3 -> clr_span_float3, fragment_ops.cl).
std::string span_type(const std::string& type) { return "clr_span_" + type; }

// Float j of the varyings, flat: the provoking vertex's value, which all three vertices hold, as a
// `scalar` (integers travel as their bits).
std::string flat_varying(const std::string& scalar, std::size_t j) {
  const std::string value = "t->varyings[0][" + std::to_string(j) + "]";
  return scalar == "float" ? value : "as_" + scalar + "(" + value + ")";
}

// A member of a generated struct that the user declared, and the declaration's line.
struct Member {
  std::string text;  // "type name"
  int line;
};

// The generated interface, written under #line 1 "<clraster generated interface>" from offset
// `start` of `out`. Each member the user declared goes under a #line directive naming its
// declaration in the user's file, so that the compiler reports an error in it (an unknown type, say)
// there; the directive after it returns to the interface's own numbering.
struct InterfaceWriter {
  std::ostringstream& out;
  std::string user_file;  // escaped for #line
  std::size_t start;

  void member(const Member& m) {
    out << "#line " << m.line << " \"" << user_file << "\"\n  " << m.text << ";\n";
    const std::string text = out.str().substr(start);
    const auto lines_so_far = std::count(text.begin(), text.end(), '\n');
    out << "#line " << lines_so_far + 2 << " \"" << kInterfaceName << "\"\n";
  }
};

// A struct of the given members, or of one placeholder (C has no empty structs).
void emit_struct(InterfaceWriter& w, const char* type_name, const std::vector<Member>& members) {
  w.out << "typedef struct {\n";
  if (members.empty()) w.out << "  int clr_none;\n";
  for (const Member& member : members) w.member(member);
  w.out << "} " << type_name << ";\n\n";
}

std::string buffer_pointer_type(const ProgramVariable& b) { return "__global " + b.type + "*"; }

void emit_constants(std::ostringstream& out, const ParsedProgram& p) {
  const ProgramInterface& in = p.interface;
  out << "/* Generated for this program by clraster (program/generator.cpp). */\n"
      << "#define CLR_NUM_VARYINGS " << varying_float_count(p) << "\n"
      << "#define CLR_SHADED_VERTEX_FLOAT4S " << shaded_vertex_bytes(p) / 16 << "\n"
      << "#define CLR_NUM_OUTPUTS " << in.outputs.size() << "\n"
      << "#define CLR_QUAD_SHADING " << (in.uses_derivatives ? 1 : 0) << "\n"
      << "#define CLR_EARLY_TESTS " << (early_fragment_tests(p) ? 1 : 0) << "\n"
      << "#define CLR_READS_FRAMEBUFFER " << (p.reads_framebuffer ? 1 : 0) << "\n"
      << "#define CLR_PROGRAM_DEPTH_TEST " << (in.has_depth_test ? 1 : 0) << "\n"
      << "#define CLR_PROGRAM_BLEND " << (in.has_blend ? 1 : 0) << "\n"
      << "#define CLR_SPAN_PROGRAM " << (in.has_fragment_span ? 1 : 0) << "\n";
  bool flat = false;
  for (const Interpolation mode : p.varying_floats) flat = flat || mode == Interpolation::Flat;
  out << "#define CLR_HAS_FLAT_VARYINGS " << (flat ? 1 : 0) << "\n";
}

void emit_interface(InterfaceWriter& w, const ParsedProgram& p) {
  const ProgramInterface& in = p.interface;
  std::vector<Member> members;
  for (const ProgramVariable& a : in.attributes) members.push_back({a.type + " " + a.name, a.line});
  emit_struct(w, "clr_attributes", members);
  members.clear();
  for (const ProgramVariable& v : in.varyings) members.push_back({v.type + " " + v.name, v.line});
  emit_struct(w, "clr_varyings", members);
  members.clear();
  for (const ProgramVariable& u : in.uniforms) {
    std::string member = u.type + " " + u.name;
    if (u.array_size) member += '[' + std::to_string(u.array_size) + ']';
    members.push_back({member, u.line});
  }
  emit_struct(w, "clr_uniforms", members);
  members.clear();
  for (const ProgramVariable& t : in.textures) members.push_back({"clr_texture " + t.name, t.line});
  emit_struct(w, "clr_textures", members);
  members.clear();
  for (const ProgramVariable& b : in.buffers) members.push_back({buffer_pointer_type(b) + " " + b.name, b.line});
  emit_struct(w, "clr_buffers", members);
  members.clear();
  for (const ProgramVariable& o : in.outputs) members.push_back({o.type + " " + o.name, o.line});
  emit_struct(w, "clr_outputs", members);
  // A span program's inputs and outputs: a span vector per component (fragment_ops.cl).
  members.clear();
  for (const ProgramVariable& v : in.varyings) members.push_back({span_type(v.type) + " " + v.name, v.line});
  emit_struct(w, "clr_span_varyings", members);
  members.clear();
  for (const ProgramVariable& o : in.outputs) members.push_back({span_type(o.type) + " " + o.name, o.line});
  emit_struct(w, "clr_span_program_outputs", members);

  std::ostringstream& out = w.out;
  out << "/* The outputs of a span of fragments (raster/shade.cl): floats as colours, integers as their bits. */\n"
      << "typedef struct {\n";
  if (in.outputs.empty()) out << "  int clr_none;\n";
  for (const ProgramVariable& o : in.outputs) {
    out << "  " << (o.type == "float4" ? "clr_span_color " : "clr_span_bits ") << o.name << ";\n";
  }
  out << "} clr_span_outputs;\n\n";
  out << R"(/* What the vertex program reads and writes. */
typedef struct {
  uint vertex_id;        /* the index (indexed draws) or first + position (non-indexed) */
  uint instance_id;
  uint view_id;          /* the view drawn: its layer of a layered framebuffer (DrawCall::views) */
  clr_attributes in;
  float4 position;       /* out: clip-space position */
  clr_varyings out;      /* out: interpolated for the fragment program */
  __constant const clr_uniforms* uniforms;
  clr_textures textures;
  clr_buffers buffers;
} clr_vertex;

/* What the fragment program reads and writes. */
typedef struct {
  clr_varyings in;
  float4 frag_coord;     /* window x, y of the pixel centre (in its layer), depth z, and 1 / clip w */
  float3 barycentric;    /* perspective-correct weights of the triangle's three vertices */
  float frag_depth;      /* out: the depth tested and written; starts as frag_coord.z */
  uint primitive_id;     /* the primitive's index in the draw (per instance) */
  uint view_id;          /* as the vertex program's */
  bool front_facing;
  bool helper;           /* a helper invocation of quad shading: its results are thrown away */
  bool discarded;        /* set by clr_discard */
  clr_outputs out;       /* out: one value per colour attachment */
  __constant const clr_uniforms* uniforms;
  clr_textures textures;
  clr_buffers buffers;
  /* The pipeline's: */
  __local float4* clr_quad;        /* derivative exchange, one slot per work-item of the tile */
  __local const uint* clr_tile;    /* the tile's colour attachments (CLR_TILE_WORD), for framebuffer fetch */
  __constant const DrawUniforms* clr_draw;
  __constant const clr_uniforms* clr_uniform_table; /* every draw's of the pass: uniforms is one of them */
  uint clr_lane;                   /* this pixel's work-item in the tile */
} clr_fragment;

/* What a span program reads and writes: the fragments of a span of pixels, one vector lane per
 * pixel (docs/programs.md). */
typedef struct {
  clr_span_varyings in;
  clr_span_float4 frag_coord;  /* as clr_fragment's, lane by lane */
  clr_span_float3 barycentric;
  clr_span_int written;        /* the lanes whose fragments passed the tests; the others are thrown away */
  uint primitive_id;
  uint view_id;
  bool front_facing;
  clr_span_program_outputs out; /* out: one value per colour attachment */
  __constant const clr_uniforms* uniforms;
  clr_textures textures;
  clr_buffers buffers;
  /* The pipeline's, for derivatives in spans of one pixel (prelude.cl): */
  __local float4* clr_quad;
  uint clr_lane;
} clr_span_fragment;

/* Defined by the generated glue at the end of the program. */
void clr_store_varyings(const clr_varyings* v, __global float* out);
CLR_INLINE void clr_lane_varyings(const __local SetupTriangle* t, const clr_span_float* values, int lane, clr_varyings* v);
#if CLR_PROGRAM_DEPTH_TEST
bool clr_program_depth_test(clr_fragment* f, float fragment_depth, float stored_depth);
#endif
#if CLR_PROGRAM_BLEND
float4 clr_program_blend(clr_fragment* f, uint target, float4 source, float4 destination);
#endif
CLR_INLINE void clr_gather_outputs(const clr_fragment* f, int lane, clr_span_outputs* outputs);
CLR_INLINE void clr_span_program_inputs(const __local SetupTriangle* t, const clr_span_float* values, clr_span_varyings* v);
CLR_INLINE void clr_span_program_results(const clr_span_program_outputs* out, clr_span_outputs* outputs);
CLR_INLINE void clr_merge_outputs(clr_fragment* f, const clr_span_outputs* outputs, clr_span_int written,
                                  __local uint* tile, const clr_span_place* place, __constant const DrawUniforms* u);

)";

  // Resources travel as kernel parameters after each stage kernel's own.
  out << "#define CLR_RESOURCE_PARAMS , __constant const clr_uniforms* clr_uniform_block, "
         "__constant const TextureDesc* clr_texture_descs";
  for (std::size_t i = 0; i < in.textures.size(); ++i) out << ", __global const uchar* clr_texture_" << i;
  for (std::size_t i = 0; i < in.buffers.size(); ++i) out << ", " << buffer_pointer_type(in.buffers[i]) << " clr_buffer_" << i;
  // The uniform block holds the uniforms of every draw of a pass, one clr_uniforms each.
  out << "\n#define CLR_BIND_RESOURCES(target, draw) do { (target).uniforms = clr_uniform_block + (draw);";
  for (std::size_t i = 0; i < in.textures.size(); ++i) {
    out << " (target).textures." << in.textures[i].name << ".data = clr_texture_" << i << "; (target).textures."
        << in.textures[i].name << ".desc = clr_texture_descs + " << i << ";";
  }
  for (std::size_t i = 0; i < in.buffers.size(); ++i) out << " (target).buffers." << in.buffers[i].name << " = clr_buffer_" << i << ";";
  out << " } while (0)\n";
  out << "#define CLR_ATTRIBUTE_PARAMS , __constant const AttributeDesc* clr_attribute_descs";
  for (std::size_t i = 0; i < in.attributes.size(); ++i) out << ", __global const uchar* clr_attribute_" << i;
  // The attribute descriptions of every draw of a pass, draw after draw.
  out << "\n#define CLR_FETCH_ATTRIBUTES(attributes, vertex, instance, draw) do {";
  for (std::size_t i = 0; i < in.attributes.size(); ++i) {
    const ProgramVariable& a = in.attributes[i];
    const VectorType vector = vector_type(a.type);
    const char* swizzle[] = {"", ".x", ".xy", ".xyz", ""};
    out << " (attributes)." << a.name << " = clr_fetch_" << vector.scalar << "(clr_attribute_descs + (draw) * "
        << in.attributes.size() << " + " << i << ", clr_attribute_" << i << ", vertex, instance)" << swizzle[vector.components] << ";";
  }
  out << " } while (0)\n";
  out << "#define CLR_TARGET_PARAMS ";
  for (std::size_t i = 0; i < in.outputs.size(); ++i) out << ", __global uchar* clr_color_" << i;
  out << "\n#define CLR_TARGETS {";
  for (std::size_t i = 0; i < in.outputs.size(); ++i) out << (i ? ", " : " ") << "clr_color_" << i;
  out << " }\n\n";

  out << "/* How each varying float is interpolated (CLR_INTERPOLATE_*). */\n"
      << "__constant uchar clr_varying_interpolation[CLR_NUM_VARYINGS] = {";
  if (p.varying_floats.empty()) out << "0";
  for (std::size_t i = 0; i < p.varying_floats.size(); ++i) out << (i ? ", " : "") << static_cast<int>(p.varying_floats[i]);
  out << "};\n\n";
}

// Functions the stages call that depend on the interface: packing varyings into floats and back,
// calling the optional depth_test and blend functions, and merging the outputs into the tile.
void emit_glue(std::ostringstream& out, const ParsedProgram& p) {
  const ProgramInterface& in = p.interface;
  out << "/* ---- Generated glue ---- */\n"
      << "void clr_store_varyings(const clr_varyings* v, __global float* out) {\n";
  for (const ProgramVariable& v : in.varyings) {
    const VectorType vector = vector_type(v.type);
    for (int c = 0; c < vector.components; ++c) {
      const std::string value = component("v->" + v.name, vector.components, c);
      out << "  out[" << v.offset + static_cast<std::size_t>(c) << "] = "
          << (vector.scalar == "float" ? value : "as_float(" + value + ")") << ";\n";
    }
  }
  out << "}\n\n"
      << "/* The varyings of lane `lane` of a span, whose interpolated floats are `values`\n"
      << " * (raster/interpolation.cl). Flat varyings hold the provoking vertex's value in all three vertices. */\n"
      << "CLR_INLINE void clr_lane_varyings(const __local SetupTriangle* t, const clr_span_float* values, int lane, "
         "clr_varyings* v) {\n";
  // Each varying in one assignment, a vector literal for vectors: the program reads it whole, and a
  // vector written by one store is forwarded to that load, where one written a component at a time
  // makes the load wait for the stores to reach the cache.
  for (const ProgramVariable& v : in.varyings) {
    const VectorType vector = vector_type(v.type);
    out << "  v->" << v.name << " = ";
    if (vector.components > 1) out << "(" << v.type << ")(";
    for (int c = 0; c < vector.components; ++c) {
      const std::size_t j = v.offset + static_cast<std::size_t>(c);
      if (c > 0) out << ", ";
      if (v.interpolation == "flat") {
        out << flat_varying(vector.scalar, j);
      } else {
        out << "CLR_SPAN_LANE(float, values[" << j << "], lane)";
      }
    }
    out << (vector.components > 1 ? ");\n" : ";\n");
  }
  out << "}\n\n";

  out << "/* A span program's varyings from the span's interpolated floats `values` (raster/interpolation.cl). */\n"
      << "CLR_INLINE void clr_span_program_inputs(const __local SetupTriangle* t, const clr_span_float* values, "
         "clr_span_varyings* v) {\n";
  for (const ProgramVariable& v : in.varyings) {
    const VectorType vector = vector_type(v.type);
    for (int c = 0; c < vector.components; ++c) {
      const std::size_t j = v.offset + static_cast<std::size_t>(c);
      const std::string member = "v->" + v.name + (vector.components == 1 ? "" : std::string(".") + "xyzw"[c]);
      if (v.interpolation == "flat") {
        out << "  " << member << " = (" << span_type(vector.scalar) << ")(" << flat_varying(vector.scalar, j) << ");\n";
      } else {
        out << "  " << member << " = values[" << j << "];\n";
      }
    }
  }
  out << "}\n\n"
      << "/* A span program's outputs as the merge takes them: colours, and integers as their bits. */\n"
      << "CLR_INLINE void clr_span_program_results(const clr_span_program_outputs* out, clr_span_outputs* outputs) {\n";
  for (const ProgramVariable& o : in.outputs) {
    for (int c = 0; c < 4; ++c) {
      const std::string value = "out->" + o.name + "." + "xyzw"[c];
      out << "  outputs->" << o.name << ".c[" << c << "] = "
          << (o.type == "float4" ? value : "CLR_SPAN_AS(uint, " + value + ")") << ";\n";
    }
  }
  out << "}\n\n";

  if (in.has_depth_test) {
    out << "bool clr_program_depth_test(clr_fragment* f, float fragment_depth, float stored_depth) {\n"
        << "  return depth_test(f, fragment_depth, stored_depth);\n}\n\n";
  }
  if (in.has_blend) {
    out << "float4 clr_program_blend(clr_fragment* f, uint target, float4 source, float4 destination) {\n"
        << "  return blend(f, target, source, destination);\n}\n\n";
  }
  out << "CLR_INLINE void clr_gather_outputs(const clr_fragment* f, int lane, clr_span_outputs* outputs) {\n";
  for (const ProgramVariable& o : in.outputs) {
    if (o.type == "float4") {
      out << "  clr_span_set_color_lane(&outputs->" << o.name << ", lane, f->out." << o.name << ");\n";
    } else {
      out << "  clr_span_set_bits_lane(&outputs->" << o.name << ", lane, as_uint4(f->out." << o.name << "));\n";
    }
  }
  out << "}\n\n"
      << "CLR_INLINE void clr_merge_outputs(clr_fragment* f, const clr_span_outputs* outputs, clr_span_int written,\n"
      << "                                  __local uint* tile, const clr_span_place* place, __constant const DrawUniforms* u) {\n";
  for (std::size_t k = 0; k < in.outputs.size(); ++k) {
    const ProgramVariable& o = in.outputs[k];
    // Only float outputs take the fragment: the program's blend function may read it.
    out << "  " << (o.type == "float4" ? "clr_merge_float_output(f, " : "clr_merge_integer_output(") << k
        << ", outputs->" << o.name << ", written, tile, place, u);\n";
  }
  out << "}\n";
}

}  // namespace

bool early_fragment_tests(const ParsedProgram& p) {
  // A per-fragment program that takes derivatives runs for every pixel of its quads, those that fail
  // the tests too, so it gains nothing from testing first; a span program runs for whole spans
  // anyway (raster/shade.cl).
  return !p.may_discard && !p.writes_depth && (!p.interface.uses_derivatives || p.interface.has_fragment_span);
}

std::size_t shaded_vertex_bytes(const ParsedProgram& p) {
  return 16 * (CLR_SHADED_VARYINGS + (varying_float_count(p) + 3) / 4);  // layout in shared/types.h
}

std::size_t setup_triangle_bytes(const ParsedProgram& p) {
  // SetupTriangle (types.h): 128 bytes of fixed fields and 3 vertices' varyings, padded to its
  // 8-byte alignment. Checked against the compiler by a kernel test.
  return (128 + 12 * varying_float_count(p) + 7) / 8 * 8;
}

std::string generate_stage_program(const ParsedProgram& p, const std::string& user_source, const std::string& file_name) {
  std::ostringstream out;
  runtime::sources::Composer sources;
  emit_constants(out, p);
  // What the generated interface names: span types and textures.
  out << sources.include("raster/span.cl") << sources.include("resources/texture.cl");
  std::string quoted;
  for (const char c : file_name) {
    if (c == '"' || c == '\\') quoted += '\\';
    if (c != '\n') quoted += c;
  }
  out << "#line 1 \"" << kInterfaceName << "\"\n";
  InterfaceWriter interface{out, quoted, static_cast<std::size_t>(out.tellp())};
  emit_interface(interface, p);
  out << sources.include("program/prelude.cl");
  out << "#line 1 \"" << quoted << "\"\n" << user_source << "\n";
  // The stages' kernels, which call the user's functions.
  for (const char* stage : {"geometry/vertex.cl", "geometry/setup.cl", "geometry/bin.cl", "raster/tile.cl"}) {
    out << sources.include(stage);
  }
  out << "#line 1 \"<clraster generated glue>\"\n";
  emit_glue(out, p);
  return out.str();
}

}  // namespace clraster::program
