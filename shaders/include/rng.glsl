// Random numbers as a pure function of (pixel, sample index, seed, dimension): the same
// command renders the same image, whatever the tiling or batching.
#ifndef VKRT_RNG_GLSL
#define VKRT_RNG_GLSL

// PCG-style integer hash (Jarzynski & Olano 2020, "Hash functions for GPU rendering", pcg).
uint hash_pcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng { uint state; };

Rng rng_init(uint pixel, uint sample_index, uint seed) {
    Rng r;
    r.state = hash_pcg(pixel ^ hash_pcg(sample_index ^ hash_pcg(seed)));
    return r;
}

// Uniform in [0, 1): the top 24 bits, so the result is exactly representable and never 1.
float rng_next(inout Rng r) {
    r.state = hash_pcg(r.state);
    return float(r.state >> 8u) * (1.0 / 16777216.0);
}

#endif
