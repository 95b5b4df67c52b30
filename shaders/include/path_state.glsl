// What a path carries from one vertex to the next (path.comp's radiance()): its throughput and
// its sum, and what the multiple importance sampling weights at the next vertex need to know
// of the bounce that made the current ray (path_mis.glsl). Host twin: none; the path tracer's
// CPU side sees only the sums.
#ifndef VKRT_PATH_STATE_GLSL
#define VKRT_PATH_STATE_GLSL

struct PathState {
    vec3 throughput;
    vec3 result;
    // Density of the BSDF sample that made the current ray, and whether its lobe was a delta
    // (the camera ray counts as delta: no other strategy could have made it).
    float prev_pdf;
    bool prev_delta;
    // Light-vertex connections (light_connection.glsl): the area density with which the
    // current ray's vertex was reached, where the vertex before it made a connection (else 0),
    // and the geometric cosine of the current ray there.
    float bounce_arrive;
    float bounce_cos;
    // Light through planar mirrors (mirror_light.glsl): when the current ray leaves a planar
    // mirror that a non-delta bounce led to, that bounce's density times the mirror lobe's
    // probability, and the bounce's distance to the mirror; else 0.
    float mirror_pdf;
    float mirror_dist;
};

PathState path_start() {
    PathState ps;
    ps.throughput = vec3(1.0);
    ps.result = vec3(0.0);
    ps.prev_pdf = 0.0;
    ps.prev_delta = true;
    ps.bounce_arrive = 0.0;
    ps.bounce_cos = 0.0;
    ps.mirror_pdf = 0.0;
    ps.mirror_dist = 0.0;
    return ps;
}

#endif
