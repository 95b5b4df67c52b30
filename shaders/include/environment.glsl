// The environment map (`--envmap`): lookups, and importance sampling for the path tracer's
// light sampling. CPU twins: scene::envmap (EnvMap::radiance, direction_to_uv, grid_position,
// rotate_y) and prepare::envmap (EnvLight::sample, EnvLight::pdf), which say the conventions:
// Mitsuba 3's latitude-longitude mapping, texels at u = (i + 0.5) / W (wrapping) and on rows
// v = j / (H - 1), bilinear between. A cell of the W x (H - 1) bilinear cells is drawn from a
// piecewise-constant distribution (pbrt-v4's ImageInfiniteLight: marginal CDF over rows, then
// one CDF per row), and a point in it in proportion to the bilinear luminance of its four
// corners (pbrt-v4's SampleBilinear), so that a sun a texel or two wide is sampled as its
// radiance falls off instead of uniformly over its cells. The luminances are compensated
// (env_cell_luminance): the map's mean is taken off, leaving the dim sky to BSDF sampling.
#ifndef VKRT_ENVIRONMENT_GLSL
#define VKRT_ENVIRONMENT_GLSL
#include "scene_bindings.glsl"
#include "math.glsl"
#include "features.glsl"
#include "sampling.glsl"

// Whether the scene has a map. HAS_ENVMAP only says the shader may meet one: the all-features
// variant (every specialization constant left true) runs scenes without a map too, whose frame
// says width 0, and must then see the sky and the light table as they are.
bool env_present() {
    return HAS_ENVMAP && frame.env_width != 0u;
}

// The map is turned about +y by the frame's angle: world = R local.
vec3 env_to_local(vec3 d) {
    float c = frame.env_rotation_cos;
    float s = frame.env_rotation_sin;
    return vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

vec3 env_to_world(vec3 d) {
    float c = frame.env_rotation_cos;
    float s = frame.env_rotation_sin;
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

// Texel units: x from column 0's centre, wrapped into [0, W); y from the top row, in [0, H - 1].
vec2 env_grid(vec3 local) {
    float u = atan(local.x, -local.z) / (2.0 * PI);
    u -= floor(u);
    float v = acos(clamp(local.y, -1.0, 1.0)) / PI;
    float w = float(frame.env_width);
    float x = u * w - 0.5;
    x -= floor(x / w) * w;
    return vec2(min(x, w - w * 1.1920929e-7), v * float(frame.env_height - 1u));
}

vec3 env_texel(uint i, uint j) {
    return uintBitsToFloat(texelFetch(env_texels, int(j * frame.env_width + i)).xyz);
}

float env_cdf(uint k) {
    return uintBitsToFloat(texelFetch(env_cdf_texels, int(k)).x);
}

// Rec. 709 luminance, the weights the distribution was built with (prepare::envmap).
float env_luminance(vec3 c) {
    return dot(c, REC709_LUMINANCE);
}

// The texels at cell (i, j)'s corners (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1), fetched
// once for both what a lookup needs: the radiance between them and their luminances, which
// weigh the draw and the density within the cell.
struct EnvCell {
    vec3 t00;
    vec3 t10;
    vec3 t01;
    vec3 t11;
};

EnvCell env_cell(uint i, uint j) {
    uint i1 = i + 1u == frame.env_width ? 0u : i + 1u;
    return EnvCell(env_texel(i, j), env_texel(i1, j), env_texel(i, j + 1u), env_texel(i1, j + 1u));
}

// Their luminances less the map's compensation (MIS compensation, Karlik et al. 2019: what is
// no brighter than the map's mean is left to BSDF sampling; prepare::envmap::
// compensated_luminance), floored at 0: the weights of the draw in the cell and its density.
vec4 env_cell_luminance(EnvCell c) {
    vec4 lum = vec4(env_luminance(c.t00), env_luminance(c.t10), env_luminance(c.t01), env_luminance(c.t11));
    return max(lum - frame.env_compensation, vec4(0.0));
}

// The bilinear radiance at f in [0, 1]^2 of the cell.
vec3 env_cell_radiance(EnvCell c, vec2 f) {
    vec3 top = mix(c.t00, c.t10, f.x);
    vec3 bottom = mix(c.t01, c.t11, f.x);
    return mix(top, bottom, f.y);
}

// x in [0, 1) with density proportional to (1 - x) a + x b, a, b >= 0 (pbrt-v4 SampleLinear);
// u itself where both are 0. CPU twin: prepare::envmap::sample_linear.
float env_sample_linear(float u, float a, float b) {
    if (!(a + b > 0.0)) return u;
    if (u == 0.0 && a == 0.0) return 0.0;
    // The density does not change with the scale; a bright sun's squared luminance would
    // overflow without it.
    float m = max(a, b);
    a /= m;
    b /= m;
    float x = u * (a + b) / (a + sqrt(mix(a * a, b * b, u)));
    return min(x, ONE_MINUS_EPSILON);
}

// The density, over the unit square, of the bilinear function with corner weights w at f
// (pbrt-v4 BilinearPDF); 0 where all weights are 0. CPU twin: prepare::envmap::bilinear_pdf.
float env_bilinear_pdf(vec2 f, vec4 w) {
    // Scaled to at most 1 first, as in env_sample_linear: the sum must not overflow.
    float m = max(max(w.x, w.y), max(w.z, w.w));
    if (!(m > 0.0)) return 0.0;
    w /= m;
    float sum = w.x + w.y + w.z + w.w;
    return 4.0 * mix(mix(w.x, w.y, f.x), mix(w.z, w.w, f.x), f.y) / sum;
}

// The largest k < n with cdf[base + k] <= u (cdf[base] = 0 <= u): the interval u falls in.
uint env_find_interval(uint base, uint n, float u) {
    uint lo = 0u;
    uint hi = n;
    while (hi - lo > 1u) {
        // Not (lo + hi) / 2: that overflows for n near 2^32 and the search never ends.
        uint mid = lo + (hi - lo) / 2u;
        if (env_cdf(base + mid) <= u) lo = mid;
        else hi = mid;
    }
    return lo;
}

// The solid-angle density of the map's sampling at a direction with sin(theta) at point f of
// cell (i, j) (corner luminances w): the cell's probability times the bilinear density in it.
float env_density(uint i, uint j, vec2 f, vec4 w, float sin_theta) {
    uint width = frame.env_width;
    uint rows = frame.env_height - 1u;
    uint row = frame.env_height + j * (width + 1u);
    float p = (env_cdf(j + 1u) - env_cdf(j)) * (env_cdf(row + i + 1u) - env_cdf(row + i));
    return sin_theta > 0.0 ? p * env_bilinear_pdf(f, w) * float(width * rows) / (2.0 * PI * PI * sin_theta) : 0.0;
}

// Draws a world direction wi with solid-angle density pdf and the radiance li arriving along it
// (at the drawn point of the cell, from the corners the draw fetched); false if it carries
// nothing.
bool env_sample(vec2 u, out vec3 wi, out vec3 li, out float pdf) {
    uint w = frame.env_width;
    uint rows = frame.env_height - 1u;
    uint j = env_find_interval(0u, rows, u.y);
    float m0 = env_cdf(j);
    float m1 = env_cdf(j + 1u);
    float fy = clamp((u.y - m0) / (m1 - m0), 0.0, 1.0);
    uint row = frame.env_height + j * (w + 1u);
    uint i = env_find_interval(row, w, u.x);
    float c0 = env_cdf(row + i);
    float c1 = env_cdf(row + i + 1u);
    float fx = clamp((u.x - c0) / (c1 - c0), 0.0, 1.0);
    // Within the cell: y from the bilinear's marginal, then x given y.
    EnvCell cell = env_cell(i, j);
    vec4 lum = env_cell_luminance(cell);
    fy = env_sample_linear(fy, lum.x + lum.y, lum.z + lum.w);
    fx = env_sample_linear(fx, mix(lum.x, lum.z, fy), mix(lum.y, lum.w, fy));
    float x = float(i) + fx;
    float theta = PI * (float(j) + fy) / float(rows);
    float phi = 2.0 * PI * fract((x + 0.5) / float(w));
    float sin_theta = sin(theta);
    vec3 local = vec3(sin(phi) * sin_theta, cos(theta), -cos(phi) * sin_theta);
    wi = env_to_world(local);
    li = env_cell_radiance(cell, vec2(fx, fy));
    pdf = env_density(i, j, vec2(fx, fy), lum, sin_theta);
    return pdf > 0.0;
}

// The radiance arriving along world direction d (unit) and, where `with_density`, the
// solid-angle density with which env_sample draws d (else 0): one grid position and one set of
// corner fetches for both, as an escaping path ray needs both for its MIS weight.
vec3 env_lookup(vec3 d, bool with_density, out float density) {
    vec3 local = env_to_local(d);
    vec2 g = env_grid(local);
    uint i = min(uint(g.x), frame.env_width - 1u);
    uint j = min(uint(g.y), frame.env_height - 2u);
    vec2 f = g - vec2(i, j);
    EnvCell cell = env_cell(i, j);
    density = 0.0;
    if (with_density) {
        float sin_theta = sqrt(max(0.0, 1.0 - local.y * local.y));
        density = env_density(i, j, clamp(f, 0.0, 1.0), env_cell_luminance(cell), sin_theta);
    }
    return env_cell_radiance(cell, f);
}

// The radiance arriving along world direction d (unit).
vec3 env_radiance(vec3 d) {
    float unused;
    return env_lookup(d, false, unused);
}

#endif
