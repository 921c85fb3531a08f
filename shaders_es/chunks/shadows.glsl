// Self-shadowing (Tatarchuk 2005; McGuire & McGuire 2005): from the hit, cast
// a ray toward the light through the relief and look for blockers.
// PX_SHADOW is 1 (hard) or 2 (soft).
#define PX_SHADOW_HARD 1  // else 2: soft

// The light's angular radius (radians): the soft penumbra's size. Declared
// here, with the only code that reads it.
uniform mediump float u_light_angular_radius[PX_MAX_LIGHTS];

// light_dir: unit vector toward the light in texture space (not height-scaled).
mediump float px_light_visibility(PX_HIGHP vec2 uv_hit, mediump float hit_height, mediump vec3 light_dir,
                                  mediump float angular_radius PX_TRACE_GRADIENTS) {
    mediump float horizontal = length(light_dir.xy);
#if PX_SHADOW == PX_SHADOW_HARD
    if (light_dir.z <= 0.0) return 0.0;  // below the geometric horizon
#else
    // A disc: the polygon's plane (the geometric horizon) blocks what of it
    // is below elevation 0, as any relief blocker does. With its centre on
    // or under the horizon, only a hit on the relief's top sees the part
    // above (every lower hit has relief in the way at grazing light).
    if (light_dir.z <= 0.0) {
        if (hit_height < 1.0) return 0.0;
        return clamp(0.5 + atan(light_dir.z, horizontal) / (2.0 * max(angular_radius, 1.0 / 1024.0)), 0.0, 1.0);
    }
#endif
    // Straight overhead, or already at the top: nothing in the relief can
    // block (a soft light low enough still loses what of it is under the horizon).
#if PX_SHADOW == PX_SHADOW_HARD
    if (horizontal < 1.0 / 1024.0 || hit_height >= 1.0) return 1.0;
#else
    if (horizontal < 1.0 / 1024.0) return 1.0;
    if (hit_height >= 1.0)
        return clamp(0.5 + atan(light_dir.z, horizontal) / (2.0 * max(angular_radius, 1.0 / 1024.0)), 0.0, 1.0);
#endif
    // uv shift per unit of normalised height along the light ray.
    PX_HIGHP vec2 shift = (u_height_scale / light_dir.z) * light_dir.xy;
    mediump float step = (1.0 - hit_height) / float(PX_SHADOW_SAMPLES);
#if PX_SHADOW == PX_SHADOW_HARD
    for (int j = 1; j <= PX_SHADOW_SAMPLES; j++) {
        mediump float ray = hit_height + float(j) * step;
        mediump float h = px_trace_height(uv_hit + (ray - hit_height) * shift);
        PX_WORK(0.0, 1.0);  // the shadow ray's fetches; its steps are not the search's
        // Half an 8-bit quantum above the ray counts as a blocker.
        if (h > ray + 1.0 / 512.0) return 0.0;
    }
    return 1.0;
#else
    // Soft: the steepest blocker seen from the receiver. Its elevation above
    // the light's centre, against the light's angular radius, gives the share
    // of the light's disc it hides: the blocker-to-receiver penumbra estimate
    // of Tatarchuk 2005 (w_p = w_s (d_r - d_b) / d_b) in angular form.
    mediump float steepest = 0.0;  // tangent of blocker elevation x horizontal / light_dir.z; 0: the horizon
    for (int j = 1; j <= PX_SHADOW_SAMPLES; j++) {
        // The ray's rise above the hit, formed directly: in fp16,
        // (hit + rise) - hit cancels to 0 when the hit is just under the top
        // and the step is under half an ulp of it, and 0 / 0 is NaN. step > 0
        // here: hit_height < 1, so 1 - hit_height >= 2^-11 in fp16.
        mediump float rise = float(j) * step;
        mediump float h = px_trace_height(uv_hit + rise * shift);
        PX_WORK(0.0, 1.0);  // the shadow ray's fetches; its steps are not the search's
        steepest = max(steepest, (h - hit_height) / rise);
    }
    // (h - h0) / (ray - h0) is the blocker's rise over the light ray's rise;
    // times tan(light elevation) it is the tangent of the blocker's elevation.
    mediump float light_elevation = atan(light_dir.z, horizontal);
    mediump float blocker_elevation = atan(steepest * light_dir.z, horizontal);
    return clamp(0.5 - (blocker_elevation - light_elevation) / (2.0 * max(angular_radius, 1.0 / 1024.0)), 0.0, 1.0);
#endif
}
