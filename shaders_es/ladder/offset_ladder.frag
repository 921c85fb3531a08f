// The PowerVR "Parallax Bumpmapping" whitepaper's optimisation ladder,
// fragment stage: offset-limited parallax (uv' = uv + h_sb * V.xy) as the
// whitepaper wrote it first, then each of its steps (PX_LADDER_STEP, see
// ladder/offset_ladder.vert):
//   1, 2 the view vector normalised here, the scale applied here, every
//        read followed by the math that uses it (three waits);
//   3    the view vector arrives normalised (one normalise fewer);
//   4    and scaled (one multiply fewer);
//   5    the normal and albedo reads issued back to back, before any math
//        on them (whitepaper 3.2.1: the two waits overlap);
//   6    precisions lowered where they hold (3.2.2): texels and colour
//        lowp, the offset mediump.
// Shading is the shipped shaders' (chunks/lighting.glsl), so that the
// images differ only by what each step changes.
#define PX_LADDER_MATH PX_HIGHP
#if PX_LADDER_STEP >= 6
#undef PX_LADDER_MATH
#define PX_LADDER_MATH mediump
#define PX_LADDER_TEXEL lowp
#else
// "Initially, everything used high precision (highp)."
#define PX_LADDER_TEXEL PX_HIGHP
#endif
#include "chunks/interface.glsl"
#include "chunks/lighting.glsl"
#ifdef PX_DEBUG_OUTPUT
#include "chunks/debug_output.glsl"
#endif

uniform lowp sampler2D u_albedo_map;
#if PX_LADDER_STEP >= 6
uniform lowp sampler2D u_normal_map;
#if !defined(PX_PACKED_HEIGHT) || PX_ES < 3
uniform lowp sampler2D u_height_map;
#endif
#else
uniform PX_HIGHP sampler2D u_normal_map;
#if !defined(PX_PACKED_HEIGHT) || PX_ES < 3
uniform PX_HIGHP sampler2D u_height_map;
#endif
#endif
uniform mediump float u_height_scale;
uniform mediump float u_polygon_height;
uniform mediump float u_inv_height_scale;
uniform mediump int u_light_count;
uniform mediump vec3 u_light_color[PX_MAX_LIGHTS];
uniform mediump vec3 u_ambient;

// The height read, as the shipped shaders make it (surface_common.glsl):
// the packed normal map's alpha on GLSL ES 3.00, else the height texture.
#if defined(PX_PACKED_HEIGHT) && PX_ES >= 3
#define PX_LADDER_HEIGHT(uv) PX_TEXTURE(u_normal_map, (uv)).a
#elif defined(PX_PACKED_HEIGHT)
#define PX_LADDER_HEIGHT(uv) PX_TEXTURE(u_height_map, (uv)).a
#else
#define PX_LADDER_HEIGHT(uv) PX_TEXTURE(u_height_map, (uv)).r
#endif
#if PX_ES >= 3
#define PX_TEXTURE texture
#else
#define PX_TEXTURE texture2D
#endif

void main() {
    PX_HIGHP vec2 uv = v_uv;
#if PX_LADDER_STEP <= 2
    PX_LADDER_MATH vec3 view = normalize(v_view_ts);
    PX_LADDER_MATH vec3 view_dir = view;
#elif PX_LADDER_STEP == 3
    PX_LADDER_MATH vec3 view = v_view_ts;
    PX_LADDER_MATH vec3 view_dir = view;
#else
    // Normalised before it was scaled: unscaling it gives the direction.
    PX_LADDER_MATH vec3 view = v_view_ts;
    PX_LADDER_MATH vec3 view_dir = vec3(view.xy * u_inv_height_scale, view.z);
#endif

    // The independent read, at the interpolated uv.
    PX_LADDER_TEXEL float height = PX_LADDER_HEIGHT(uv);
#if PX_LADDER_STEP <= 3
    PX_LADDER_MATH vec2 offset = ((height - u_polygon_height) * u_height_scale) * view.xy;
#else
    PX_LADDER_MATH vec2 offset = (height - u_polygon_height) * view.xy;
#endif
    PX_HIGHP vec2 hit_uv = uv + offset;

#if PX_LADDER_STEP >= 5
    // Both dependent reads, then the math on them: one wait.
    PX_LADDER_TEXEL vec4 normal_texel = PX_TEXTURE(u_normal_map, hit_uv);
    lowp vec4 albedo = PX_TEXTURE(u_albedo_map, hit_uv);
    PX_LADDER_TEXEL vec3 normal = normalize(normal_texel.xyz * 2.0 - 1.0);
#else
    // Read, wait, math; read, wait, math.
    PX_LADDER_TEXEL vec4 normal_texel = PX_TEXTURE(u_normal_map, hit_uv);
    PX_LADDER_TEXEL vec3 normal = normalize(normal_texel.xyz * 2.0 - 1.0);
    lowp vec4 albedo = PX_TEXTURE(u_albedo_map, hit_uv);
#endif

    // Lit in linear light, as the shipped shaders light it.
    mediump vec3 base = albedo.rgb;
#ifdef PX_SRGB_DECODE
    base = px_srgb_to_linear(base);
#endif
    mediump vec3 color = u_ambient * base;
    for (int i = 0; i < PX_MAX_LIGHTS; i++) {
        if (i >= u_light_count) break;
        color += px_light_term(base, normal, normalize(view_dir), normalize(v_light_ts[i]), u_light_color[i], 1.0);
    }
#ifdef PX_DEBUG_OUTPUT
    // As surface_main.glsl reports an unshadowed hit: offset limiting reads
    // the height at the unshifted uv, and light 0's horizon.
    mediump float visibility = 1.0;
    if (u_light_count > 0) visibility = normalize(v_light_ts[0]).z > 0.0 ? 1.0 : 0.0;
    PX_FRAG_COLOR = px_debug_output(hit_uv, height, visibility);
#elif defined(PX_SRGB_OUTPUT)
    PX_FRAG_COLOR = vec4(px_linear_to_srgb(color), 1.0);
#else
    PX_FRAG_COLOR = vec4(color, 1.0);
#endif
}
