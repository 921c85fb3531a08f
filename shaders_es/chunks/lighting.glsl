// Lambert diffuse plus Blinn-Phong specular in texture space.
uniform mediump float u_specular;   // specular intensity
uniform mediump float u_shininess;  // Blinn-Phong exponent

// light_dir is in texture space, where the polygon's normal is +z: a light
// with light_dir.z <= 0 is on or below the polygon's plane, and lights none
// of its surface, though a normal-mapped bevel may face it (N.L > 0).
mediump vec3 px_light_term(mediump vec3 albedo, mediump vec3 normal, mediump vec3 view_dir,
                           mediump vec3 light_dir, mediump vec3 light_color, mediump float visibility) {
    if (light_dir.z <= 0.0) return vec3(0.0);
    mediump float n_dot_l = max(dot(normal, light_dir), 0.0);
    mediump vec3 half_vector = normalize(light_dir + view_dir);
    mediump float specular = n_dot_l > 0.0 ? u_specular * pow(max(dot(normal, half_vector), 0.0), u_shininess) : 0.0;
    return visibility * light_color * (albedo * n_dot_l + vec3(specular));
}

// Colour: the sRGB transfer curves, for the albedo's decoding and the
// output's encoding where the GPU does not do them.
#ifdef PX_SRGB_DECODE
// The sRGB curve (IEC 61966-2-1), where the texture unit cannot decode it
// (ES 2.0 without GL_EXT_sRGB): after filtering, which then averages
// encoded values (a texture unit decodes first).
mediump vec3 px_srgb_to_linear(mediump vec3 c) {
    mediump vec3 curve = pow((c + 0.055) * (1.0 / 1.055), vec3(2.4));
    return mix(c * (1.0 / 12.92), curve, step(vec3(0.04045), c));
}
#endif
#ifdef PX_SRGB_OUTPUT
// Linear light to what an sRGB display shows: the inverse curve, clamped
// (pow of a value at or under the toe is never used, but must not be NaN).
mediump vec3 px_linear_to_srgb(mediump vec3 c) {
    c = clamp(c, 0.0, 1.0);
    mediump vec3 curve = 1.055 * pow(max(c, vec3(0.0031308)), vec3(1.0 / 2.4)) - 0.055;
    return mix(c * 12.92, curve, step(vec3(0.0031308), c));
}
#endif
