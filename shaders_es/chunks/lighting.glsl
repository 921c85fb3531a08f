// Lambert diffuse plus Blinn-Phong specular in texture space.
uniform mediump float u_specular;   // specular intensity
uniform mediump float u_shininess;  // Blinn-Phong exponent

mediump vec3 px_light_term(lowp vec3 albedo, mediump vec3 normal, mediump vec3 view_dir,
                           mediump vec3 light_dir, mediump vec3 light_color, mediump float visibility) {
    mediump float n_dot_l = max(dot(normal, light_dir), 0.0);
    mediump vec3 half_vector = normalize(light_dir + view_dir);
    mediump float specular = n_dot_l > 0.0 ? u_specular * pow(max(dot(normal, half_vector), 0.0), u_shininess) : 0.0;
    return visibility * light_color * (albedo * n_dot_l + vec3(specular));
}
