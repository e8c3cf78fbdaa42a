// work.glsl - the counting views (render.glsl DEBUG_VIEW 6, 7 and 8; `sdfvj bench work`, effect
// `work`). Included by render.glsl after the scene and uniforms.glsl, before any map() call site.
#ifndef SDF_RENDER_WORK_GLSL
#define SDF_RENDER_WORK_GLSL
// DEBUG_VIEW 6 and 7 (`sdfvj bench work`): each call of the scene's map() (or of mapObjects(), the
// same field less the floor's plane) adds one to the phase the pixel is in. Probes that read the
// floor's plane alone (mapNear, the object steps) call neither and are not counted; nor is the
// compute path's cone pre-pass (one ray per 8x8 tile). Other views: WORK_PHASE is nothing.
#define WORK_VIEW (DEBUG_VIEW >= 6 && DEBUG_VIEW <= 8)
#if WORK_VIEW
float g_work[8];   // 0-3: the primary ray's march, normal, shadow, AO; 4-7: its reflection's
int g_workPhase = 0;
vec4 workMap(vec3 p) {
    g_work[g_workPhase] += 1.0f;
    return map(p);
}
#define map(p) workMap(p)
#if defined(SCENE_OBJECTS) && SCENE_OBJECTS
vec4 workMapObjects(vec3 p) {
    g_work[g_workPhase] += 1.0f;
    return mapObjects(p);
}
#define mapObjects(p) workMapObjects(p)
#endif
// The view's value: 6 the primary ray's phases, 7 its reflection's, 8 all calls (in x).
vec4 workView() {
    if (DEBUG_VIEW == 6) return vec4(g_work[0], g_work[1], g_work[2], g_work[3]);
    if (DEBUG_VIEW == 7) return vec4(g_work[4], g_work[5], g_work[6], g_work[7]);
    float calls = 0.0f;
    for (int k = 0; k < 8; k++) calls += g_work[k];
    return vec4(calls);
}
#define WORK_PHASE(k) g_workPhase = (k)
#define WORK_RESET() for (int k_ = 0; k_ < 8; k_++) g_work[k_] = 0.0f
#else
#define WORK_PHASE(k)
#define WORK_RESET()
#endif
#endif
