// Vertex stage shared by every technique. Builds the tangent frame and moves
// the view and light vectors into texture space, as the PowerVR whitepaper
// does, and folds the parallax scale into the view vector. The view vector
// is normalised here only without PX_EXACT_VIEW (the whitepaper's saving, an
// opt-in); by default the fragment stage normalises it (exact).
#include "chunks/interface.glsl"

PX_ATTRIBUTE highp vec3 a_position;
// highp: an authored frame's components reach 1e5 (past fp16's 65504) and
// may be tiny; the frame below is built from them in highp.
PX_ATTRIBUTE highp vec3 a_normal;
PX_ATTRIBUTE highp vec4 a_tangent;  // xyz tangent along +u, w handedness (+1/-1)
PX_ATTRIBUTE highp vec2 a_uv;

uniform highp mat4 u_model;
uniform highp mat4 u_view;
uniform highp mat4 u_projection;
uniform highp mat3 u_normal_matrix;      // inverse transpose of the model's 3x3
uniform mediump float u_model_handedness;// -1 when the model matrix mirrors, else +1
uniform highp vec3 u_camera_position;    // world space
// Material uv transform: uv' = u_uv_matrix * uv + u_uv_offset (highp: tiled
// uvs grow large and need all their bits for sub-texel offsets).
uniform highp mat2 u_uv_matrix;
uniform highp vec2 u_uv_offset;
// u_uv_matrix divided by sqrt(|det|): carries mesh-tangent directions into the
// material's texture frame (rotation and mirroring; the relief depth is
// already in tile units, so the uniform scale cancels).
uniform mediump mat2 u_uv_frame;
// The relief depth in tile units, folded into the view vector. highp, and
// the vertex stage's own (GLSL ES 1.00 wants a uniform in both stages to have
// one precision, and a fragment stage may have no highp): as mediump (strict
// fp16, 2^-11 relative) it scaled every parallax vector by up to 2e-4, which
// moved maxmip's exact hits 100 times past their fp32 error (0.026 texel on
// the text relief at 85 degrees; docs/stability.md).
uniform highp float u_parallax_scale;
// xyz: world direction toward the light (w = 0) or world position (w = 1).
uniform highp vec4 u_light_vector[PX_MAX_LIGHTS];
#ifdef PX_UV_STRETCH
// Mesh uv crossed per unit step along tangent and bitangent, over the
// mesh's mean (Vertex::uv_stretch).
PX_ATTRIBUTE highp vec2 a_uv_stretch;
#endif
#if defined(PX_CURVED) && !defined(PX_SHAPE)
// The mesh's bend below its tangent plane (Vertex::curvature, mesh units):
// c.x x^2 + c.y x y + c.z y^2 at offset (x, y) along tangent and bitangent.
PX_ATTRIBUTE highp vec3 a_curvature;
// Into relief depths per squared tile: units_per_tile / (height_scale *
// the model's scale) (renderer.cpp set_object_uniforms).
uniform highp float u_curvature_scale;
// The mesh's uv bend (Vertex::uv_bend_u/v: mesh uv per squared mesh unit
// along the tangent plane) and its scale into squared ray parameters
// (renderer.cpp set_object_uniforms).
PX_ATTRIBUTE highp vec3 a_uv_bend_u;
PX_ATTRIBUTE highp vec3 a_uv_bend_v;
uniform highp float u_uv_bend_scale;
#endif
#ifdef PX_CURVED
// The shell (renderer.cpp set_object_uniforms): x how far out along its
// normals the mesh is drawn (mesh units), y the same in relief depths, z
// relief depths per view-space unit.
uniform highp vec3 u_shell;
#endif
#if defined(PX_BOUNDED) && !defined(PX_CURVED)
uniform highp float u_wall_scale;  // relief depths per mesh unit along z (a plane's normal)
#endif

void main() {
    highp vec3 position = a_position;
#ifdef PX_CURVED
    // Drawn out past its chords, so that the polygon covers the smooth
    // surface's outline (the relief's top); the fragment stage knows how far
    // above the smooth surface each of its points lies (v_shell_*).
    if (dot(a_normal, a_normal) > 1e-12) position += normalize(a_normal) * u_shell.x;
#endif
    highp vec4 world_position = u_model * vec4(position, 1.0);
    highp vec4 view_position = u_view * world_position;
    gl_Position = u_projection * view_position;
    v_uv = u_uv_matrix * a_uv + u_uv_offset;
    v_view_position = view_position.xyz;
#if defined(PX_BOUNDED) && !defined(PX_CURVED)
    // A side wall's height above the tile's polygon (which lies in z = 0).
    v_wall_height = a_position.z * u_wall_scale;
#endif

    // The frame in highp: the vertex stage always has it (GLSL ES 1.00 and
    // 3.00, section 4.5.3/4.5.4), and an authored frame may be any vector
    // (docs/scene-format.md, mesh.tangent and mesh.normal), zero and
    // parallel ones included. The same rule, in double, builds the exact
    // reference's frame (src/reference/reference_image.cpp, plane_frame):
    //  - n: the normal by the normal matrix; a normal shorter than 1e-6
    //    (model space, so independent of the object's scale) is replaced
    //    by the model's +z. Either has a world length of at least 1e-10
    //    (the normal matrix shrinks by at most 1e-4, limits.h), whose square
    //    fp32 keeps.
    //  - t: Gram-Schmidt against n. Where what remains is under 1e-3 of the
    //    tangent (within 0.06 degrees of n, or a tangent shorter than 1e-6),
    //    the model's +x made orthogonal to n; where that degenerates too (n
    //    along the model's x), the model's +y, orthogonal to the model's x
    //    (a TransformDesc has no shear), so orthogonal to n.
    highp mat3 model3 = mat3(u_model[0].xyz, u_model[1].xyz, u_model[2].xyz);
    highp vec3 authored_n = a_normal;
    highp vec3 authored_t = a_tangent.xyz;
    highp vec3 n = normalize(u_normal_matrix * (dot(authored_n, authored_n) < 1e-12 ? vec3(0.0, 0.0, 1.0) : authored_n));
    highp vec3 t = model3 * authored_t;
    highp vec3 t_perp = t - n * dot(n, t);
    if (dot(authored_t, authored_t) < 1e-12 || dot(t_perp, t_perp) <= 1e-6 * dot(t, t)) {
        t = model3[0];
        t_perp = t - n * dot(n, t);
        if (dot(t_perp, t_perp) <= 1e-6 * dot(t, t)) {
            t = model3[1];
            t_perp = t - n * dot(n, t);
        }
    }
    t = normalize(t_perp);
    highp vec3 b = (a_tangent.w * u_model_handedness) * cross(n, t);

    highp vec3 to_eye = u_camera_position - world_position.xyz;
#ifdef PX_EXACT_VIEW
    highp vec3 view_ts = vec3(dot(to_eye, t), dot(to_eye, b), dot(to_eye, n));
#else
    mediump vec3 view_ts = normalize(vec3(dot(to_eye, t), dot(to_eye, b), dot(to_eye, n)));
#endif
#ifdef PX_UV_STRETCH
    // The searches step in uv: a step along the tangent crosses a_uv_stretch
    // times the mean mesh uv per unit here (a uv sphere's u crowds at the
    // poles), so the view's uv step is stretched by it (the lights too: they
    // share the frame). The fragment stage takes the frame's area out for
    // shading (px_shading_vector, surface_main.glsl).
    view_ts.xy *= a_uv_stretch;
    v_frame_scale = inversesqrt(a_uv_stretch.x * a_uv_stretch.y);
#endif
    view_ts.xy = u_uv_frame * view_ts.xy;
#ifdef PX_READS_HEIGHT
    view_ts.xy *= u_parallax_scale;  // folded here: one multiply per vertex, not per fragment
#endif
    v_view_ts = view_ts;
#ifdef PX_SHAPE
    v_object_position = position;  // the exact search's ray starts here (march.glsl)
#elif defined(PX_CURVED)
    // The quadric carried into the texture frame: x_tex = F x_mesh (F =
    // u_uv_frame, det +-1), so with A = F^-1 its matrix G becomes A^T G A,
    // and q = view_ts.xy . (A^T G A) view_ts.xy is the quadric of the mesh-
    // frame direction the trace's uv step stands for (the same model of
    // offsets the searches use). A mirroring model needs nothing: the
    // bitangent above mirrors with it.
    // (With the uv stretch, F is u_uv_frame times the stretch.)
    highp vec2 f0 = u_uv_frame[0] * a_uv_stretch.x;
    highp vec2 f1 = u_uv_frame[1] * a_uv_stretch.y;
    highp float det = f0.x * f1.y - f1.x * f0.y;
    highp vec2 a0 = vec2(f1.y, -f0.y) / det;  // the columns of F^-1
    highp vec2 a1 = vec2(-f1.x, f0.x) / det;
    highp float mxx = a_curvature.x;
    highp float mxy = 0.5 * a_curvature.y;
    highp float myy = a_curvature.z;
    highp float gxx = mxx * a0.x * a0.x + 2.0 * mxy * a0.x * a0.y + myy * a0.y * a0.y;
    highp float gyy = mxx * a1.x * a1.x + 2.0 * mxy * a1.x * a1.y + myy * a1.y * a1.y;
    highp float gxy = mxx * a0.x * a1.x + mxy * (a0.x * a1.y + a0.y * a1.x) + myy * a0.y * a1.y;
    v_curvature = vec3(gxx, 2.0 * gxy, gyy) * u_curvature_scale;
    {
        // Where the search's ray runs in the tangent plane the mesh's uv is
        // not linear: at parameter mu it is uv0 - mu d + mu^2 v_uv_bend, the
        // bend of the view's own tangent direction (unit view vector).
        highp vec3 e = normalize(to_eye);
        highp vec2 w = vec2(dot(e, t), dot(e, b));
        highp vec3 ww = vec3(w.x * w.x, w.x * w.y, w.y * w.y);
        v_uv_bend = (u_uv_matrix * vec2(dot(a_uv_bend_u, ww), dot(a_uv_bend_v, ww))) * u_uv_bend_scale;
    }
    // How far the polygon lies above the smooth surface, in relief depths:
    // the shell minus the chord sag, sag(p) = 1/2 (<p_i . n_i> - p . <n_i>)
    // (< > interpolated across the triangle; Phong tessellation with shape
    // factor 1/2, exact to second order on a sphere), so that
    // lift = v_shell_lift + dot(v_view_position, v_shell_xyz), each part linear.
    highp vec3 n_view = normalize(mat3(u_view[0].xyz, u_view[1].xyz, u_view[2].xyz) * n);
    highp vec3 half_normal = 0.5 * u_shell.z * n_view;
    v_shell_x = half_normal.x;
    v_shell_y = half_normal.y;
    v_shell_z = half_normal.z;
    v_shell_lift = u_shell.y - dot(view_position.xyz, half_normal);
#endif

    for (int i = 0; i < PX_MAX_LIGHTS; i++) {
        highp vec3 to_light = u_light_vector[i].w > 0.5 ? u_light_vector[i].xyz - world_position.xyz
                                                        : u_light_vector[i].xyz;
        // Left unnormalised: normalising per vertex visibly damaged lighting
        // (PowerVR whitepaper, section 3.1); the fragment stage normalises.
        mediump vec3 light_ts = vec3(dot(to_light, t), dot(to_light, b), dot(to_light, n));
#ifdef PX_UV_STRETCH
        light_ts.xy *= a_uv_stretch;
#endif
        light_ts.xy = u_uv_frame * light_ts.xy;
        v_light_ts[i] = light_ts;
    }
}
