// Lambert diffuse plus Blinn-Phong specular in texture space.
uniform mediump float u_specular;   // specular intensity
uniform mediump float u_shininess;  // Blinn-Phong exponent

// light_dir is in texture space, where the polygon's normal is +z: a light
// with light_dir.z <= 0 is on or below the polygon's plane, and lights none
// of its surface, though a normal-mapped bevel may face it (N.L > 0).
mediump vec3 px_light_term(lowp vec3 albedo, mediump vec3 normal, mediump vec3 view_dir,
                           mediump vec3 light_dir, mediump vec3 light_color, mediump float visibility) {
    if (light_dir.z <= 0.0) return vec3(0.0);
    mediump float n_dot_l = max(dot(normal, light_dir), 0.0);
    mediump vec3 half_vector = normalize(light_dir + view_dir);
    mediump float specular = n_dot_l > 0.0 ? u_specular * pow(max(dot(normal, half_vector), 0.0), u_shininess) : 0.0;
    return visibility * light_color * (albedo * n_dot_l + vec3(specular));
}
