// Varyings shared by surface.vert and every technique's fragment stage.
// PX_VARYING is `varying` (GLSL ES 1.00) or out/in (GLSL ES 3.00), from the
// preamble the loader injects.
PX_VARYING PX_HIGHP vec2 v_uv;             // material uv; PX_HIGHP for large tiled uvs
PX_VARYING mediump vec3 v_view_ts;      // unit view vector in texture space; xy * height scale when PX_READS_HEIGHT
PX_VARYING PX_HIGHP vec3 v_view_position;  // view space, for perspective-correct depth
PX_VARYING mediump vec3 v_light_ts[PX_MAX_LIGHTS];  // toward each light, texture space, unnormalised
