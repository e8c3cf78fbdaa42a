// Where a ray is inside the shapes that bound a scene: the bounding sphere, its box, and the cone
// around the sphere in which a soft shadow can still darken. The march and the shadow ray clip
// their intervals with these (render.glsl BOUNDS). Plain GLSL that also compiles as C++ (the CPU
// reference, accuracy/cpu_scene.h), as render.glsl does.
#ifndef SDF_RENDER_INTERVALS_GLSL
#define SDF_RENDER_INTERVALS_GLSL

// Where a ray is inside a sphere (centre xyz, radius w): (t_enter, t_exit), empty (x > y)
// when it misses. rd unit length.
vec2 sphereInterval(vec3 ro, vec3 rd, vec4 s) {
    vec3 oc = ro - vec3(s.x, s.y, s.z);
    float b = dot(oc, rd);
    float disc = b * b - (dot(oc, oc) - s.w * s.w);
    if (disc < 0.0f) return vec2(1e30f, -1e30f);
    float q = sqrt(disc);
    return vec2(-b - q, -b + q);
}

// Where a ray is inside the box lo..hi: (t_enter, t_exit), empty (x > y) when it misses.
vec2 boxInterval(vec3 ro, vec3 rd, vec3 lo, vec3 hi) {
    vec3 inv = vec3(1.0f / (abs(rd.x) > 1e-20f ? rd.x : 1e-20f), 1.0f / (abs(rd.y) > 1e-20f ? rd.y : 1e-20f),
                    1.0f / (abs(rd.z) > 1e-20f ? rd.z : 1e-20f));
    vec3 t0 = (lo - ro) * inv;
    vec3 t1 = (hi - ro) * inv;
    vec3 tn = min(t0, t1);
    vec3 tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

// Where a soft-shadow ray can still be darkened by whatever lies in the sphere s: outside the
// cone |ro + t rd - centre| < radius + t / k every sample is at least t / k from the objects,
// so its penumbra term k * h / t is >= 1 and changes nothing. Empty (x > y) when the ray
// stays out of that cone; (-1e30, 1e30) when k <= 1 (the cone then holds everything).
vec2 penumbraInterval(vec3 ro, vec3 rd, vec4 s, float k) {
    if (k <= 1.0f) return vec2(-1e30f, 1e30f);
    vec3 oc = ro - vec3(s.x, s.y, s.z);
    float a = 1.0f - 1.0f / (k * k);
    float b = dot(oc, rd) - s.w / k;
    float c = dot(oc, oc) - s.w * s.w;
    float disc = b * b - a * c;
    if (disc < 0.0f) return vec2(1e30f, -1e30f);
    float q = sqrt(disc);
    return vec2((-b - q) / a, (-b + q) / a);
}

#endif
