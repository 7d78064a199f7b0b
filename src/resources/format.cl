/* format.cl: loading and storing one texel of any format (CLR_FORMAT_*), driven by the format
 * table in types.h. `index` counts texels from `data`.
 *
 * Conversions are OpenGL 4.6's:
 *  - unorm8 reads as c / 255 and is written as clamp(x, 0, 1) * 255 rounded to nearest, ties to even
 *    (llvmpipe's choice where 2.3.5.2 leaves it open), NaN as 0;
 *  - sRGB colour channels decode with c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4 (8.24) and
 *    encode with l < 0.0031308 ? 12.92 l : 1.055 l^(1/2.4) - 0.055 (17.3), then as unorm8; alpha is linear;
 *  - half floats round toward zero, as llvmpipe converts them (OpenGL leaves the rounding open), so
 *    finite values beyond half's range store its largest, 65504; 32-bit floats and integers are
 *    stored as they are;
 *  - channels a format lacks read as 0, and alpha as 1: R is (r, 0, 0, 1), RG is (r, g, 0, 1), and a
 *    depth format is (depth, 0, 0, 1).
 * What OpenGL leaves undefined, a float load or store of an integer format or an integer one of a
 * float format, reads (0, 0, 0, 1) and writes nothing here.
 */

#include "shared/types.h"

/* A format's row of the format table, as the kernels need it. */
typedef struct {
  int channels;     /* 0 for a format that does not exist: it reads (0, 0, 0, 1) and writes nothing */
  int channel_type; /* CLR_CHANNEL_* */
} clr_texel_layout;

CLR_INLINE clr_texel_layout clr_texel_layout_of(int format) {
  clr_texel_layout layout = {0, CLR_CHANNEL_UNORM8};
  switch (format) {
#define CLR_TEXEL_LAYOUT_ROW(id, name, count, type, depth, stencil) \
  case id:                                                           \
    layout.channels = count;                                         \
    layout.channel_type = type;                                      \
    break;
    CLR_FORMAT_TABLE(CLR_TEXEL_LAYOUT_ROW)
#undef CLR_TEXEL_LAYOUT_ROW
  }
  return layout;
}

CLR_INLINE bool clr_channel_is_integer(int type) { return type == CLR_CHANNEL_SINT32 || type == CLR_CHANNEL_UINT32; }

/* ---- A texel's stored bits --------------------------------------------------------------------------
 * Channel c of the texel in bits.s[c], as stored (zero-extended); channels the format lacks are 0.
 * Whole texels are read and written with vector loads and stores. */

#define CLR_READ_CHANNELS(T)                                                                    \
  if (layout.channels == 4) bits = convert_uint4(vload4(index, (__global const T*)data));         \
  else if (layout.channels == 2) bits.xy = convert_uint2(vload2(index, (__global const T*)data)); \
  else if (layout.channels == 1) bits.x = ((__global const T*)data)[index];

CLR_INLINE uint4 clr_read_texel(clr_texel_layout layout, __global const uchar* data, uint index) {
  uint4 bits = (uint4)(0u);
  switch (CLR_CHANNEL_BYTES(layout.channel_type)) {
    case 1: CLR_READ_CHANNELS(uchar) break;
    case 2: CLR_READ_CHANNELS(ushort) break;
    default: CLR_READ_CHANNELS(uint) break;
  }
  return bits;
}
#undef CLR_READ_CHANNELS

#define CLR_WRITE_CHANNELS(T, convert2, convert4)                                      \
  if (layout.channels == 4) vstore4(convert4(bits), index, (__global T*)data);         \
  else if (layout.channels == 2) vstore2(convert2(bits.xy), index, (__global T*)data); \
  else if (layout.channels == 1) ((__global T*)data)[index] = (T)bits.x;

CLR_INLINE void clr_write_texel(clr_texel_layout layout, __global uchar* data, uint index, uint4 bits) {
  switch (CLR_CHANNEL_BYTES(layout.channel_type)) {
    case 1: CLR_WRITE_CHANNELS(uchar, convert_uchar2, convert_uchar4) break;
    case 2: CLR_WRITE_CHANNELS(ushort, convert_ushort2, convert_ushort4) break;
    default: CLR_WRITE_CHANNELS(uint, , ) break;
  }
}
#undef CLR_WRITE_CHANNELS

/* ---- Bits to values and back, for the non-integer channel types --------------------------------------- */

/* sRGB-encoded byte c to linear: OpenGL's formula evaluated in double precision and rounded to float,
 * so decoding is exact (tests/test_textures.cpp checks every entry against the formula). */
__constant float clr_srgb_to_linear_table[256] = {
    0.0f, 0.000303526991f, 0.000607053982f, 0.000910580973f, 0.00121410796f, 0.00151763496f, 0.00182116195f,
    0.00212468882f, 0.00242821593f, 0.0027317428f, 0.00303526991f, 0.00334653584f, 0.00367650739f, 0.00402471703f,
    0.00439144205f, 0.00477695325f, 0.00518151652f, 0.00560539169f, 0.00604883302f, 0.00651209056f, 0.00699541019f,
    0.00749903219f, 0.00802319311f, 0.00856812578f, 0.00913405884f, 0.00972121768f, 0.010329823f, 0.0109600937f,
    0.0116122449f, 0.012286488f, 0.0129830325f, 0.0137020834f, 0.0144438436f, 0.0152085144f, 0.0159962941f,
    0.0168073755f, 0.0176419541f, 0.01850022f, 0.0193823613f, 0.0202885624f, 0.0212190095f, 0.0221738853f,
    0.0231533665f, 0.0241576321f, 0.0251868591f, 0.0262412224f, 0.0273208916f, 0.02842604f, 0.0295568351f,
    0.0307134446f, 0.0318960324f, 0.0331047662f, 0.0343398079f, 0.0356013142f, 0.0368894488f, 0.0382043719f,
    0.0395462364f, 0.0409151986f, 0.0423114114f, 0.043735031f, 0.045186203f, 0.0466650873f, 0.0481718257f,
    0.0497065671f, 0.0512694567f, 0.0528606474f, 0.054480277f, 0.0561284907f, 0.0578054301f, 0.0595112368f,
    0.0612460524f, 0.0630100146f, 0.064803265f, 0.0666259378f, 0.0684781671f, 0.0703600943f, 0.0722718537f,
    0.0742135718f, 0.0761853829f, 0.078187421f, 0.0802198201f, 0.0822827071f, 0.0843762085f, 0.0865004584f,
    0.0886555836f, 0.0908417106f, 0.0930589661f, 0.0953074694f, 0.097587347f, 0.0998987257f, 0.102241732f,
    0.104616486f, 0.107023105f, 0.10946171f, 0.111932427f, 0.114435375f, 0.116970666f, 0.119538426f,
    0.122138776f, 0.124771819f, 0.127437681f, 0.130136475f, 0.13286832f, 0.135633335f, 0.138431609f,
    0.141263291f, 0.144128472f, 0.147027269f, 0.149959788f, 0.152926147f, 0.155926466f, 0.158960834f,
    0.162029371f, 0.165132195f, 0.168269396f, 0.171441108f, 0.174647406f, 0.177888423f, 0.18116425f,
    0.18447499f, 0.187820777f, 0.191201687f, 0.194617838f, 0.198069319f, 0.20155625f, 0.205078736f,
    0.208636865f, 0.212230757f, 0.215860501f, 0.219526201f, 0.223227963f, 0.226965874f, 0.230740055f,
    0.23455058f, 0.238397568f, 0.242281124f, 0.246201321f, 0.25015828f, 0.254152089f, 0.258182853f,
    0.262250662f, 0.266355604f, 0.270497799f, 0.274677306f, 0.278894275f, 0.283148736f, 0.287440836f,
    0.291770637f, 0.296138257f, 0.300543785f, 0.304987311f, 0.309468925f, 0.313988715f, 0.318546772f,
    0.323143214f, 0.327778101f, 0.332451522f, 0.337163627f, 0.341914415f, 0.346704066f, 0.351532608f,
    0.356400132f, 0.361306787f, 0.366252601f, 0.371237695f, 0.376262128f, 0.38132602f, 0.386429429f,
    0.391572475f, 0.396755219f, 0.401977777f, 0.407240212f, 0.412542611f, 0.417885065f, 0.423267663f,
    0.428690493f, 0.434153646f, 0.439657182f, 0.445201188f, 0.450785786f, 0.456411034f, 0.462076992f,
    0.467783809f, 0.473531485f, 0.479320168f, 0.48514995f, 0.491020858f, 0.496932983f, 0.502886474f,
    0.50888133f, 0.514917672f, 0.520995557f, 0.527115107f, 0.533276379f, 0.539479494f, 0.545724452f,
    0.55201143f, 0.558340371f, 0.564711511f, 0.571124852f, 0.577580452f, 0.584078431f, 0.590618849f,
    0.597201765f, 0.603827357f, 0.610495567f, 0.617206573f, 0.623960376f, 0.630757153f, 0.637596846f,
    0.644479692f, 0.651405632f, 0.658374846f, 0.665387273f, 0.672443151f, 0.679542482f, 0.686685324f,
    0.693871737f, 0.701101899f, 0.708375752f, 0.715693474f, 0.723055124f, 0.730460763f, 0.73791039f,
    0.745404184f, 0.752942204f, 0.760524511f, 0.768151164f, 0.775822222f, 0.783537805f, 0.791297913f,
    0.799102724f, 0.806952238f, 0.814846575f, 0.822785735f, 0.830769897f, 0.838799f, 0.846873224f,
    0.854992628f, 0.863157213f, 0.871367097f, 0.8796224f, 0.887923121f, 0.896269381f, 0.904661179f,
    0.913098633f, 0.921581864f, 0.930110872f, 0.938685715f, 0.947306514f, 0.955973327f, 0.964686275f,
    0.973445296f, 0.982250571f, 0.991102099f, 1.0f,
};

/* OpenGL's float to unorm8 conversion: the nearest byte to clamp(x, 0, 1) * 255, ties to even as
 * llvmpipe rounds them (for half of the 256 values (i + 0.5f) / 255 the float product is a tie), in
 * clears and fragment stores alike. fmax turns NaN into 0. */
CLR_INLINE uint4 clr_float_to_unorm8(float4 x) { return convert_uint4_rte(fmin(fmax(x, 0.0f), 1.0f) * 255.0f); }

/* OpenGL's linear to sRGB encoding, before the unorm8 conversion (which clamps what is below 0 or
 * above 1, and NaN). */
static float4 clr_linear_to_srgb(float4 linear) {
  return select(1.055f * powr(linear, 1.0f / 2.4f) - 0.055f, 12.92f * linear, linear < 0.0031308f);
}

CLR_INLINE uint4 clr_encode_texel(int type, float4 value) {
  switch (type) {
    case CLR_CHANNEL_UNORM8: return clr_float_to_unorm8(value);
    case CLR_CHANNEL_SRGB8: return clr_float_to_unorm8((float4)(clr_linear_to_srgb(value).xyz, value.w));
    case CLR_CHANNEL_FLOAT16: {
      ushort4 bits; /* half is a storage type only (no cl_khr_fp16): convert through its bits */
      vstore_half4_rtz(value, 0, (half*)&bits); /* toward zero, as llvmpipe stores half floats */
      return convert_uint4(bits);
    }
    default: return as_uint4(value);
  }
}

/* c / 255, correctly rounded, for whole numbers c from 0 to 255, without a division: c * (1 / 255)
 * is an ulp off for 126 of the 256 bytes, and one Newton step of fused multiply-adds corrects all of
 * them (checked for each). Divisions were a fifth of a bilinear RGBA8 texture sample on PoCL. For
 * each float type a byte is decoded in (texels, tile spans). */
#define CLR_UNORM8_TO_FLOAT_FOR(type)                                                      \
  static __attribute__((overloadable)) inline type clr_unorm8_to_float(type c) {          \
    const type quotient = c * (1.0f / 255.0f);                                            \
    return fma(fma(-quotient, (type)(255.0f), c), (type)(1.0f / 255.0f), quotient);       \
  }
CLR_UNORM8_TO_FLOAT_FOR(float)
CLR_UNORM8_TO_FLOAT_FOR(float4)
CLR_UNORM8_TO_FLOAT_FOR(float8)
#undef CLR_UNORM8_TO_FLOAT_FOR

CLR_INLINE float4 clr_decode_texel(int type, uint4 bits) {
  switch (type) {
    case CLR_CHANNEL_UNORM8: return clr_unorm8_to_float(convert_float4(bits));
    case CLR_CHANNEL_SRGB8:
      return (float4)(clr_srgb_to_linear_table[bits.x & 0xffu], clr_srgb_to_linear_table[bits.y & 0xffu],
                      clr_srgb_to_linear_table[bits.z & 0xffu], clr_unorm8_to_float((float)bits.w));
    case CLR_CHANNEL_FLOAT16: {
      const ushort4 half_bits = convert_ushort4(bits);
      return vload_half4(0, (const half*)&half_bits);
    }
    default: return as_float4(bits);
  }
}

/* ---- Whole texels ---------------------------------------------------------------------------------- */

/* Channels a format lacks decode to 0 (every type decodes zero bits to 0); alpha becomes 1. */
CLR_INLINE float4 clr_complete_texel(clr_texel_layout layout, float4 value) {
  if (layout.channels < 4) value.w = 1.0f;
  return value;
}

CLR_INLINE float4 clr_load_texel_float(int format, __global const uchar* data, uint index) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (clr_channel_is_integer(layout.channel_type)) return (float4)(0.0f, 0.0f, 0.0f, 1.0f);
  return clr_complete_texel(layout, clr_decode_texel(layout.channel_type, clr_read_texel(layout, data, index)));
}

CLR_INLINE void clr_store_texel_float(int format, __global uchar* data, uint index, float4 value) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (clr_channel_is_integer(layout.channel_type)) return;
  clr_write_texel(layout, data, index, clr_encode_texel(layout.channel_type, value));
}

/* What clr_store_texel_float followed by clr_load_texel_float gives, without the memory. */
CLR_INLINE float4 clr_quantize_float(int format, float4 value) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (clr_channel_is_integer(layout.channel_type)) return (float4)(0.0f, 0.0f, 0.0f, 1.0f);
  const float4 decoded = clr_decode_texel(layout.channel_type, clr_encode_texel(layout.channel_type, value));
  /* Only the channels the format has survive a store. */
  const int4 stored = (int4)(0, 1, 2, 3) < layout.channels;
  return clr_complete_texel(layout, select((float4)(0.0f), decoded, stored));
}

/* Integer formats hold 32-bit words: a signed load or store is an unsigned one reinterpreted (and a
 * signed access of an unsigned format, which OpenGL leaves undefined, reinterprets the words too). */
static uint4 clr_load_texel_uint(int format, __global const uchar* data, uint index) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (!clr_channel_is_integer(layout.channel_type)) return (uint4)(0u, 0u, 0u, 1u);
  uint4 bits = clr_read_texel(layout, data, index);
  if (layout.channels < 4) bits.w = 1u;
  return bits;
}

static void clr_store_texel_uint(int format, __global uchar* data, uint index, uint4 value) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (clr_channel_is_integer(layout.channel_type)) clr_write_texel(layout, data, index, value);
}

static int4 clr_load_texel_int(int format, __global const uchar* data, uint index) {
  return as_int4(clr_load_texel_uint(format, data, index));
}

static void clr_store_texel_int(int format, __global uchar* data, uint index, int4 value) {
  clr_store_texel_uint(format, data, index, as_uint4(value));
}

/* What clr_store_texel_uint followed by clr_load_texel_uint gives, without the memory (and the same
 * bits for the int functions). */
CLR_INLINE uint4 clr_quantize_uint(int format, uint4 value) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
  if (!clr_channel_is_integer(layout.channel_type)) return (uint4)(0u, 0u, 0u, 1u);
  const uint4 stored = select((uint4)(0u), value, (int4)(0, 1, 2, 3) < layout.channels);
  return layout.channels < 4 ? (uint4)(stored.xyz, 1u) : stored;
}
