// Varyings shared by surface.vert and every technique's fragment stage.
// PX_VARYING is `varying` (GLSL ES 1.00) or out/in (GLSL ES 3.00), from the
// preamble the loader injects.
PX_VARYING PX_HIGHP vec2 v_uv;             // material uv; PX_HIGHP for large tiled uvs
// The view vector in texture space, xy * height scale when PX_READS_HEIGHT.
// PX_EXACT_VIEW (the default, TechniqueOptions::exact_view): highp and not
// normalised, so that interpolation is exact (the vector is affine across a
// flat triangle); the fragment stage normalises. Without it (the opt-in
// "exact_view": false): normalised per vertex and mediump (PowerVR
// whitepaper: saves a normalise per fragment), which costs POM about 1 texel
// of hit error on a two-triangle plane at 30 degrees (docs/accuracy.md).
// The optimisation ladder (ladder/) keeps it highp until its precision step.
#if defined(PX_EXACT_VIEW) || (defined(PX_LADDER_STEP) && PX_LADDER_STEP < 6)
#define PX_VIEW_PRECISION PX_HIGHP
#else
#define PX_VIEW_PRECISION mediump
#endif
PX_VARYING PX_VIEW_PRECISION vec3 v_view_ts;
PX_VARYING PX_HIGHP vec3 v_view_position;  // view space, for perspective-correct depth
PX_VARYING mediump vec3 v_light_ts[PX_MAX_LIGHTS];  // toward each light, texture space, unnormalised
#ifndef PX_LADDER_STEP
// The texture frame is the mesh's tangent frame carried by F = u_uv_frame
// times the mesh's uv stretch (surface.vert, Vertex::uv_stretch): the
// trace's view vector and the lights are F applied to their tangent-frame
// xy, and shading takes F's area out again (surface_main.glsl): times
// v_frame_scale, 1 / sqrt(det) of the stretch (one float, not the stretch's
// vec2: GLSL ES 1.00's packing puts it in the fourth column beside the vec3
// varyings, where the curved variant has no vec2 row left).
#define PX_UV_STRETCH
PX_VARYING mediump float v_frame_scale;
#endif
#if defined(PX_BOUNDED) && !defined(PX_CURVED)
// A bounded tile's side walls (renderer.cpp, make_tile_walls): how far this
// fragment lies above the polygon, in relief depths (0 on the polygon).
PX_VARYING PX_HIGHP float v_wall_height;
#endif
#ifdef PX_SHAPE
// The exact curved search (march.glsl, PX_SHAPE): the fragment's mesh-space
// position on the drawn polygon (affine across a triangle, so exact).
PX_VARYING PX_HIGHP vec3 v_object_position;
#elif defined(PX_CURVED)
// The curved relief's quadric in the texture frame (surface.vert): how far
// below the polygon's plane, in relief depths, the surface lies at a uv
// offset d: v_curvature . (d.x^2, d.x d.y, d.y^2). Linear across a triangle.
PX_VARYING PX_HIGHP vec3 v_curvature;
// The mesh's uv bend along the view's tangent direction, in texture uv per
// squared ray parameter (surface.vert): the search's uv at mu is
// uv0 - mu d + mu^2 v_uv_bend.
PX_VARYING PX_HIGHP vec2 v_uv_bend;
// How far the drawn polygon lies above the smooth surface, in relief
// depths: v_shell_lift + dot(v_view_position, vec3(v_shell_x, v_shell_y,
// v_shell_z)) (surface.vert). Four floats, not a vec4: GLSL ES 1.00's
// packing rules (Appendix A.7) fit them into the fourth column beside the
// vec3 varyings, where the ES 2.0 minimum of 8 varying vectors has no row
// left for a vec4.
PX_VARYING PX_HIGHP float v_shell_x, v_shell_y, v_shell_z, v_shell_lift;
#endif
