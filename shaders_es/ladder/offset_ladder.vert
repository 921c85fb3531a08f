// The PowerVR "Parallax Bumpmapping" whitepaper's optimisation ladder,
// vertex stage (`parallax profile --ladder`, docs/profiling.md). PX_LADDER_STEP:
//   1 baseline: the eye-to-tangent matrix built per vertex from the
//     world-view product (u_view * u_model), the view vector passed on
//     unnormalised and unscaled;
//   2 the frame from the inverse-transpose matrix the CPU computes
//     (u_normal_matrix), in world space (whitepaper 3.1);
//   3 the view vector normalised here, not per fragment (3.1);
//   4 the parallax scale folded into it here (3.2);
//   5, 6 as 4 (the fragment stage changes: reads back to back, precisions).
// It draws with the renderer's uniforms and varyings, so each step is
// timed and compared with the exact reference on the bench's own scenes.
// Unlike surface.vert it keeps the whitepaper's frame as written: no
// fallback for degenerate authored frames (the ladder runs on the bench
// plane, whose frame is exact).
#include "chunks/interface.glsl"

PX_ATTRIBUTE highp vec3 a_position;
PX_ATTRIBUTE highp vec3 a_normal;
PX_ATTRIBUTE highp vec4 a_tangent;
PX_ATTRIBUTE highp vec2 a_uv;

uniform highp mat4 u_model;
uniform highp mat4 u_view;
uniform highp mat4 u_projection;
uniform highp mat3 u_normal_matrix;
uniform mediump float u_model_handedness;
uniform highp vec3 u_camera_position;
uniform highp mat2 u_uv_matrix;
uniform highp vec2 u_uv_offset;
uniform mediump mat2 u_uv_frame;
uniform highp float u_parallax_scale;
uniform highp vec4 u_light_vector[PX_MAX_LIGHTS];

void main() {
    highp vec4 world_position = u_model * vec4(a_position, 1.0);
    highp vec4 view_position = u_view * world_position;
    gl_Position = u_projection * view_position;
    v_uv = u_uv_matrix * a_uv + u_uv_offset;
    v_view_position = view_position.xyz;

#if PX_LADDER_STEP == 1
    // Eye space, with the frame through the world-view product per vertex.
    highp mat4 world_view = u_view * u_model;
    highp mat3 world_view3 = mat3(world_view[0].xyz, world_view[1].xyz, world_view[2].xyz);
    highp vec3 n = normalize(world_view3 * a_normal);
    highp vec3 t = normalize(world_view3 * a_tangent.xyz);
    highp vec3 to_eye = -view_position.xyz;
    highp mat3 view3 = mat3(u_view[0].xyz, u_view[1].xyz, u_view[2].xyz);
#else
    // World space, the frame through the CPU's inverse transpose.
    highp vec3 n = normalize(u_normal_matrix * a_normal);
    highp vec3 t = normalize(u_normal_matrix * a_tangent.xyz);
    highp vec3 to_eye = u_camera_position - world_position.xyz;
#endif
    highp vec3 b = (a_tangent.w * u_model_handedness) * cross(n, t);
    highp mat3 eye_to_tangent = mat3(t.x, b.x, n.x, t.y, b.y, n.y, t.z, b.z, n.z);

    highp vec3 view_ts = eye_to_tangent * to_eye;
#if PX_LADDER_STEP >= 3
    view_ts = normalize(view_ts);
#endif
    view_ts.xy = u_uv_frame * view_ts.xy;
#if PX_LADDER_STEP >= 4
    view_ts.xy *= u_parallax_scale;
#endif
    v_view_ts = view_ts;

    for (int i = 0; i < PX_MAX_LIGHTS; i++) {
#if PX_LADDER_STEP == 1
        highp vec3 light_world = u_light_vector[i].w > 0.5 ? u_light_vector[i].xyz - world_position.xyz
                                                           : u_light_vector[i].xyz;
        highp vec3 to_light = view3 * light_world;
#else
        highp vec3 to_light = u_light_vector[i].w > 0.5 ? u_light_vector[i].xyz - world_position.xyz
                                                        : u_light_vector[i].xyz;
#endif
        mediump vec3 light_ts = eye_to_tangent * to_light;
        light_ts.xy = u_uv_frame * light_ts.xy;
        v_light_ts[i] = light_ts;
    }
}
