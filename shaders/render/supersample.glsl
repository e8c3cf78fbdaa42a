// supersample.glsl - the pixel entry of both paths (GLSL only, after render.glsl): renderPixel.
//
// SUPERSAMPLE 1 (the `ssaa` effect): four samples a pixel on a rotated grid, each marched on
// its own. When the four hit one surface (the same albedo at nearly the same depth) that is flat
// across the pixel, the shading (normal, shadows, AO, the mirror bounce) is done once and every
// sample takes its colour, as multisampling shares a fragment's shading between the samples it
// covers; samples that see the sky share one colour too. A silhouette, an edge of a box or a
// fractal's folds are shaded per sample. The samples are resolved in display space (tone
// mapped, then averaged), as a supersampled frame downsampled would be.
// SUPERSAMPLE 2 (`ssaa_exact`): the same samples, each shaded on its own (what the shared shading
// is measured against). SUPERSAMPLE 0 (default): one ray through the pixel's centre (renderFrom).
#ifndef SDF_RENDER_SUPERSAMPLE_GLSL
#define SDF_RENDER_SUPERSAMPLE_GLSL

#ifndef SUPERSAMPLE
#define SUPERSAMPLE 0
#endif
#define USE_SUPERSAMPLE (SUPERSAMPLE && DEBUG_VIEW == 0)

#if USE_SUPERSAMPLE
// The rotated grid: each sample alone on its row and on its column, within the pixel.
#ifndef SUPERSAMPLE_FLAT
#define SUPERSAMPLE_FLAT 0.05   // sine of the largest angle between the samples' plane and the fourth hit
#endif
const vec2 SAMPLE_OFFSETS[4] = vec2[4](vec2(-0.125, -0.375), vec2(0.375, -0.125), vec2(0.125, 0.375), vec2(-0.375, 0.125));

// Whether two samples see one surface: both the sky, or the same albedo at nearly the same depth.
bool sameSurface(Hit a, Hit b) {
    if (a.hit != b.hit) return false;
    if (!a.hit) return true;   // both see the sky: its colour varies slowly with the direction
    return abs(a.t - b.t) <= 0.02 * max(a.t, b.t) && all(equal(a.albedo, b.albedo));
}

vec4 renderSupersampled(vec2 fragCoord, float tStart) {
    callSceneSetup();
    vec3 rds[4];
    Hit hits[4];
    vec3 points[4];   // where each sample hit (its far end on a miss)
    for (int s = SDF_LOOP_ZERO; s < 4; s++) {   // one march call site: a loop, not four copies
        rds[s] = cameraRay(fragCoord + SAMPLE_OFFSETS[s]);
        hits[s] = march(u_camPos, rds[s], tStart);
        points[s] = u_camPos + rds[s] * hits[s].t;
    }
    vec3 sum = vec3(0.0);
    int shaded = 0;   // bit s: sample s has its colour
    // The four hits on one surface, flat across the pixel, share one shading; a surface that bends
    // within the pixel (an edge of a box, a fractal's folds) or a silhouette is shaded per sample.
    bool oneFlat = false;
    if (SUPERSAMPLE == 1 && hits[0].hit && sameSurface(hits[0], hits[1]) && sameSurface(hits[0], hits[2]) &&
        sameSurface(hits[0], hits[3])) {
        vec3 n = cross(points[1] - points[0], points[2] - points[0]);
        vec3 c = points[3] - points[0];
        oneFlat = abs(dot(c, n)) <= SUPERSAMPLE_FLAT * length(n) * max(length(c), 1e-20);
    }
    for (int lead = SDF_LOOP_ZERO; lead < 4; lead++) {
        if ((shaded & (1 << lead)) != 0) continue;
        vec4 c = traceRay(u_camPos, rds[lead], 0.0, hits[lead], true);
        vec3 display = displayColor(c.rgb);
        for (int s = lead; s < 4; s++)
            if ((shaded & (1 << s)) == 0 && (s == lead || oneFlat || (SUPERSAMPLE == 1 && !hits[lead].hit && !hits[s].hit))) {
                sum += display;
                shaded |= 1 << s;
            }
    }
    return pixelColor(sum * 0.25, fragCoord);
}
#endif

// The display colour of the pixel whose centre is fragCoord; tStart as renderFrom's.
vec4 renderPixel(vec2 fragCoord, float tStart) {
#if USE_SUPERSAMPLE
    return renderSupersampled(fragCoord, tStart);
#else
    return renderFrom(fragCoord, tStart);
#endif
}

#endif
