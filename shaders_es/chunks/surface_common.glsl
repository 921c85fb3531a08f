// Fragment-stage declarations shared by every technique, and the height fetch.
#include "chunks/interface.glsl"

// Albedo is colour, decoded from sRGB to linear light (by the texture unit,
// or by px_srgb_to_linear below): mediump, because linear light needs about
// 12 bits where sRGB's 8 are dark (its first step is 1/3295), more than lowp
// promises.
uniform mediump sampler2D u_albedo_map;

// Normals (and height in alpha when packed): mediump, because Mesa's default
// sampler precision (lowp) returns fp16 texels and heights are compared with
// the ray at 1/256 steps; mediump holds 8-bit texels exactly on every GPU.
uniform mediump sampler2D u_normal_map;
// The traced height. GLSL ES 1.00 always reads it from its own texture, bound
// at base level only (see below); when packed, that texture is the packed
// normal map again, without mips, and height is its alpha.
// An 11-bit height map (EAC R11) is read at highp where the exact walk
// needs every one of its 2048 levels apart (fp16 keeps 11 bits, not 2048
// values of v / 2047).
#if defined(PX_READS_HEIGHT) && (!defined(PX_PACKED_HEIGHT) || PX_ES < 3)
#ifdef PX_HEIGHT_11BIT
uniform highp sampler2D u_height_map;
#else
uniform mediump sampler2D u_height_map;
#endif
#endif

uniform mediump float u_height_scale;     // relief depth, tile units
// Height of the polygon within the relief, in units of the relief depth:
// -bias / scale (1 = the polygon touches the relief's top; Welsh's bias).
uniform mediump float u_polygon_height;
uniform mediump float u_inv_height_scale; // 1 / u_height_scale (0 when flat)
uniform mediump int u_light_count;
uniform mediump vec3 u_light_color[PX_MAX_LIGHTS];
uniform mediump vec3 u_ambient;
uniform PX_HIGHP vec2 u_texture_size;        // height map size in texels (LOD)

// PX_COUNT_WORK (VariantKey::count_work, debug outputs only; read by
// include/parallaxes/profiling/measurement/work.h for `parallax bench`'s work columns): the
// debug outputs show the search's loop iterations and texture fetches per
// pixel in place of the hit uv. Each search counts its own steps and
// fetches with PX_WORK; relief's refinements and the shadow rays' marches
// (shadows.glsl) count their fetches only, so that the iterations are the
// search's steps (what `bench --gpu` compiles a search truncated to).
#ifdef PX_BOUNDED
// A bounded relief's fragment outside its tile (the polygon is drawn wider,
// by the relief's reach): its ray comes into the relief through the tile's
// side at this t (0 at the relief's top, 1 at its bottom, as the searches
// count). surface_main.glsl sets it before px_trace; a trace that defines
// PX_TRACE_STARTS starts there, and the others are not asked to.
PX_HIGHP float px_start_t = 0.0;
#endif

#ifdef PX_COUNT_WORK
PX_HIGHP vec2 px_work = vec2(0.0);
#define PX_WORK(iterations, fetches) px_work += vec2(iterations, fetches)
#else
#define PX_WORK(iterations, fetches)
#endif

// Height reads inside tracing loops never use implicit derivatives (their
// value is undefined in non-uniform control flow), and they read the base
// level: the traced surface is the texture's own, not a blurred mip of it, so
// a hit is exact up to the search (the reference traces the same surface).
// GLSL ES 3.00: textureLod at level 0. GLSL ES 1.00 has no lod sampling in
// the fragment stage without GL_EXT_shader_texture_lod, so the renderer binds
// a base-level-only copy of the traced texture instead, and the shading reads
// keep their mip chain. The gradients of the unshifted uv still travel with
// the trace for the shading reads (textureGrad after the offset).
#if PX_ES >= 3
#define PX_TRACE_GRADIENTS , PX_HIGHP vec2 uv_dx, PX_HIGHP vec2 uv_dy
#define PX_TRACE_GRADIENT_ARGS , uv_dx, uv_dy
#else
#define PX_TRACE_GRADIENTS
#define PX_TRACE_GRADIENT_ARGS
#endif
// A texture file stored top row first (KTXorientation T=d, PVR y down, the
// tools' default) goes up as it is: its first row lands at t = 0, so it is
// read at (u, 1 - v), which is the file's own image the right way up. Each
// texture has its own flag (a PNG albedo with a KTX height map).
#define px_flip_v(uv) vec2((uv).x, 1.0 - (uv).y)
#define px_flip_dv(d) vec2((d).x, -(d).y)
#ifdef PX_FLIP_ALBEDO_V
#define PX_ALBEDO_UV(uv) px_flip_v(uv)
#define PX_ALBEDO_D(d) px_flip_dv(d)
#else
#define PX_ALBEDO_UV(uv) (uv)
#define PX_ALBEDO_D(d) (d)
#endif
#ifdef PX_FLIP_NORMAL_V
#define PX_NORMAL_UV(uv) px_flip_v(uv)
#define PX_NORMAL_D(d) px_flip_dv(d)
#else
#define PX_NORMAL_UV(uv) (uv)
#define PX_NORMAL_D(d) (d)
#endif
#ifdef PX_FLIP_HEIGHT_V
#define PX_HEIGHT_UV(uv) px_flip_v(uv)
#else
#define PX_HEIGHT_UV(uv) (uv)
#endif

// The height fetch, only where a technique reads height: an untraced
// variant's source then names no height sampler at all.
#ifdef PX_READS_HEIGHT
#if defined(PX_PACKED_HEIGHT) && PX_ES >= 3
#define PX_HEIGHT_SAMPLER u_normal_map
#else
#define PX_HEIGHT_SAMPLER u_height_map
#endif
#ifdef PX_PACKED_HEIGHT
#define PX_HEIGHT_CHANNEL a
#else
#define PX_HEIGHT_CHANNEL r
#endif
#if PX_ES >= 3
#define px_trace_height(uv) textureLod(PX_HEIGHT_SAMPLER, PX_HEIGHT_UV(uv), 0.0).PX_HEIGHT_CHANNEL
#else
#define px_trace_height(uv) texture2D(PX_HEIGHT_SAMPLER, PX_HEIGHT_UV(uv)).PX_HEIGHT_CHANNEL
#endif
#endif

// Where the view ray meets the relief: the uv to shade with, and the ray's
// height there (normalised: 0 bottom, 1 top of the relief).
struct PxHit {
    PX_HIGHP vec2 uv;
    mediump float height;
};
