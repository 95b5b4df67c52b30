// The path tracer's sample generators. Every value is a pure function of (pixel, sample index,
// seed, dimension), so any tiling, batching or resumed run draws the same numbers.
#ifndef VKRT_SAMPLER_GLSL
#define VKRT_SAMPLER_GLSL
#include "constants.glsl"
#include "rng.glsl"

// Laine-Karras style hash that permutes the bits of x so that each bit depends only on the
// bits below it: applied to a bit-reversed value, that is a nested uniform (Owen) scramble.
// (Burley 2020, "Practical hash-based Owen scrambling", JCGT 9(4), with its constants.)
uint lk_permutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

uint owen_scramble(uint x, uint seed) {
    return bitfieldReverse(lk_permutation(bitfieldReverse(x), seed));
}

// The second Sobol dimension as a 32-bit fraction: primitive polynomial x + 1, direction
// numbers v_{k+1} = v_k ^ (v_k >> 1) (Joe & Kuo 2008). With the first dimension, the bit
// reversal of the index (van der Corput), it forms a (0,2)-sequence.
//
// Closed form instead of a loop over the index's bits (which ran up to 32 times per call on a
// scrambled index and took ~7 % of the path tracer's time, docs/experiments/
// per-step-cost.md): v_k is (1 + s)^k applied to the top bit, s a right shift, so the sum over the set
// bits b_k of the index is the polynomial B(t) = sum b_k t^k evaluated at t = 1 + s: a Taylor
// shift by 1 over GF(2). Since (1 + s)^(2^m) = 1 + s^(2^m) there, it splits into halves,
// B = L + t^(2^m) H -> L(1+s) + H(1+s) + s^(2^m) H(1+s), one shift-and-xor per level, five levels
// for 32 bits; coefficient j then sits at bit j and belongs at bit 31 - j, hence the reversal.
uint sobol_dim1(uint index) {
    uint x = index;
    x ^= (x >> 1) & 0x55555555u;
    x ^= (x >> 2) & 0x33333333u;
    x ^= (x >> 4) & 0x0f0f0f0fu;
    x ^= (x >> 8) & 0x00ff00ffu;
    x ^= (x >> 16) & 0x0000ffffu;
    return bitfieldReverse(x);
}

struct Sampler {
    uint kind;
    uint pixel_seed;
    uint index;
    uint dim;
    uint sample_rate;
    Rng rng;
};

// Which sample numbers a pixel draws: its own (coherence 1, the pixel index), or those of its
// block of `coherence` pixels in a row, so that neighbouring lanes trace alike (coherent path
// tracing, Sadeghi et al. 2009; PathSettings::coherence says why and what it costs).
uint sample_key(uvec2 pixel, uint width, uint coherence) {
    uint c = max(coherence, 1u);
    return pixel.y * ((width + c - 1u) / c) + pixel.x / c;
}

// The even-numbered bits of x, packed: the x coordinate of a Morton (Z-order) code.
uint morton_compact(uint x) {
    x &= 0x55555555u;
    x = (x | (x >> 1)) & 0x33333333u;
    x = (x | (x >> 2)) & 0x0f0f0f0fu;
    x = (x | (x >> 4)) & 0x00ff00ffu;
    x = (x | (x >> 8)) & 0x0000ffffu;
    return x;
}

// x's low 16 bits spread to the even-numbered bits.
uint morton_spread(uint x) {
    x &= 0x0000ffffu;
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    x = (x | (x << 1)) & 0x55555555u;
    return x;
}

// The row-major index of the 2^block_bits square that pixel (or slot) p lies in, in an image
// `width` pixels wide: scattered coherence's sampler tile and the adaptive sampler's block.
uint coherence_block_index(uvec2 p, uint width, uint block_bits) {
    uint per_row = (width + (1u << block_bits) - 1u) >> block_bits;
    return (p.y >> block_bits) * per_row + (p.x >> block_bits);
}

// Scattered coherence (PathSettings::coherence_block = 2^block_bits > 0, coherence > 1): each
// run of `coherence` slots (one row of lanes of the 8-wide workgroup) draws the same sample
// numbers, and its pixels lie scattered over the block, so the lanes trace alike (same light,
// lobe, direction and roulette choices at nearby points) while the pixels whose errors are
// correlated are far apart and the noise shows no streaks (docs/experiments/
// scattered-coherence.md). The dispatch covers whole blocks (integrator::tiles). Returns the
// pixel slot `slot` renders; `key` its numbers.
// - Independent orders (`zordered` false: sobol and the other samplers): the block's pixels are
//   dealt to its slots in a random order (a 4-round Feistel network on the two halves of the
//   slot's bits, keyed by the block and the seed).
// - Z order (`zordered`, SAMPLER_ZSOBOL): the block is cut into `coherence` sub-tiles (a grid
//   of 2^floor(k/2) x 2^ceil(k/2) for coherence 2^k), and group g takes the pixel at Z-order
//   position g of each sub-tile, each sub-tile's positions rolled by its own random offset
//   (so that the group's pixels are not a regular lattice). Neighbouring pixels then belong
//   to neighbouring groups, whose Z-ordered sets make the error blue noise; the key is
//   (block << ZSOBOL_CELL_BITS) | g. Without scattering the key is (tile << ZSOBOL_CELL_BITS)
//   | Z-order position of the group in its 256 x 256 tile of groups.
// CPU twin: integrator::path::coherence::coherent_pixel.
uvec2 coherent_pixel(uvec2 slot, uint width, uint coherence, uint block_bits, uint seed, bool zordered, out uint key) {
    if (block_bits == 0u || coherence <= 1u) {
        if (!zordered) {
            key = sample_key(slot, width, coherence);
        } else {
            uint c = max(coherence, 1u);
            uvec2 g = uvec2(slot.x / c, slot.y);
            uint tiles_per_row = ((width + c - 1u) / c + 255u) >> 8u;
            uint tile = (g.y >> 8u) * tiles_per_row + (g.x >> 8u);
            key = (tile << ZSOBOL_CELL_BITS) | morton_spread(g.x & 255u) | (morton_spread(g.y & 255u) << 1u);
        }
        return slot;
    }
    uint side = 1u << block_bits;
    uint mask = side - 1u;
    uvec2 block = slot >> block_bits;
    uint block_index = coherence_block_index(slot, width, block_bits);
    uint q = ((slot.y & mask) << block_bits) | (slot.x & mask);
    uint block_seed = hash_pcg(block_index ^ hash_pcg(seed ^ 0x5bd1e995u));
    if (zordered) {
        uint k = uint(findMSB(coherence));
        uint group = q >> k;
        uint member = q & (coherence - 1u);
        // Sub-tiles: 2^kx across, 2^ky down; each w x h, w = h or 2h (the Z order's extra bit is x's).
        uint kx = k / 2u;
        uint ky = k - kx;
        uint w = side >> kx;
        uint h = side >> ky;
        uint roll = hash_pcg(block_seed ^ (member * 0x9e3779b9u));
        uint x = (morton_compact(group) + roll) & (w - 1u);
        uint y = (morton_compact(group >> 1u) + (roll >> 16u)) & (h - 1u);
        key = (block_index << ZSOBOL_CELL_BITS) | group;
        return (block << block_bits) + uvec2((member & ((1u << kx) - 1u)) * w + x, (member >> kx) * h + y);
    }
    uint l = q >> block_bits;
    uint r = q & mask;
    for (uint round = 0u; round < 4u; round++) {
        uint f = hash_pcg(r ^ (block_seed + round * 0x9e3779b9u)) & mask;
        uint next_r = l ^ f;
        l = r;
        r = next_r;
    }
    key = block_index * ((side * side) / coherence) + q / coherence;
    return (block << block_bits) + uvec2(r, l);
}

// `key` names the sample numbers (coherent_pixel); `zsobol_log2` is SAMPLER_ZSOBOL's set size.
// Z-ordered Sobol (Ahmed & Wonka 2020, "Screen-space blue-noise diffusion of Monte Carlo
// sampling error via hierarchical ordering of pixels"; pbrt-v4's ZSobolSampler): sample j of
// the cell at Z-order position z of its tile is point (z << zsobol_log2) | j of one Sobol
// sequence per tile, set and dimension pair, its index Owen-scrambled as a whole. The
// scramble maps every aligned power-of-two range of indices onto another, so each pixel still
// draws a whole (0,m,2)-net per power-of-two prefix, and every aligned 2^a x 2^a square of cells
// together draws a finer one: neighbours take complementary strata and their errors cancel
// locally (blue noise). The structure holds within a set of 2^zsobol_log2 samples per pixel
// (the run's spp rounded up); sample j belongs to set j >> zsobol_log2, each set with its own
// scramble.
Sampler sampler_init(uint kind, uint key, uint sample_index, uint seed, uint sample_rate, uint zsobol_log2) {
    Sampler s;
    s.kind = kind;
    s.index = sample_index;
    s.dim = 0u;
    s.sample_rate = max(sample_rate, 1u);
    s.rng = rng_init(key, sample_index, seed);
    if (kind == SAMPLER_ZSOBOL) {
        uint set = sample_index >> zsobol_log2;
        uint j = sample_index & ((1u << zsobol_log2) - 1u);
        s.index = ((key & ((1u << ZSOBOL_CELL_BITS) - 1u)) << zsobol_log2) | j;
        s.pixel_seed = hash_pcg((key >> ZSOBOL_CELL_BITS) ^ hash_pcg(set ^ hash_pcg(seed ^ 0x2c1b3c6du)));
    } else {
        s.pixel_seed = hash_pcg(key ^ hash_pcg(seed ^ 0x9e3779b9u));
    }
    return s;
}

// 24-bit fraction in [0, 1), exactly representable and never 1.
float u32_to_unit(uint x) {
    return float(x >> 8u) * (1.0 / 16777216.0);
}

// Sobol: each pair of dimensions is its own Owen-scrambled 2D Sobol sequence, its sample order
// shuffled by a scramble of the index (Burley 2020, section 4: "padding" by shuffling), so that
// pairs are decorrelated from each other and from neighbouring pixels. This is the seed of
// pair d of this pixel's sequence (Z-ordered Sobol: of this tile's and set's sequence).
uint sobol_pair_seed(Sampler s, uint d) {
    return hash_pcg(s.pixel_seed ^ hash_pcg(d + 0x68bc21ebu));
}

// The pair's first dimension: the Owen-scrambled radical inverse of the index, written as
// owen_scramble(bitfieldReverse(i)) = bitfieldReverse(lk_permutation(i)).
float sobol_first(uint index, uint h) {
    return u32_to_unit(bitfieldReverse(lk_permutation(index, hash_pcg(h ^ 0xa511e9b3u))));
}

// The next two dimensions.
vec2 sampler_2d(inout Sampler s) {
    uint d = s.dim++;
    if (s.kind == SAMPLER_SOBOL || s.kind == SAMPLER_ZSOBOL) {
        uint h = sobol_pair_seed(s, d);
        uint index = owen_scramble(s.index, h);
        return vec2(sobol_first(index, h), u32_to_unit(owen_scramble(sobol_dim1(index), hash_pcg(h ^ 0x63d83595u))));
    }
    return vec2(rng_next(s.rng), rng_next(s.rng));
}

// The first of the next two dimensions, as sampler_2d(s).x but without computing the second
// (three of the path tracer's five draws per bounce are 1D).
float sampler_1d(inout Sampler s) {
    uint d = s.dim++;
    if (s.kind == SAMPLER_SOBOL || s.kind == SAMPLER_ZSOBOL) {
        uint h = sobol_pair_seed(s, d);
        return sobol_first(owen_scramble(s.index, h), h);
    }
    float x = rng_next(s.rng);
    // The independent stream still advances by two, as sampler_2d does.
    rng_next(s.rng);
    return x;
}

// Where in its pixel the sample lands (box filter: uniform over the pixel). Stratified: sample k
// takes stratum k mod n^2 of an n x n grid (the lab report's SampleRate^2 pattern), jittered inside it.
vec2 sampler_pixel(inout Sampler s) {
    vec2 u = sampler_2d(s);
    if (s.kind == SAMPLER_STRATIFIED) {
        uint n = s.sample_rate;
        uint cell = s.index % (n * n);
        return (vec2(float(cell % n), float(cell / n)) + u) / float(n);
    }
    return u;
}

#endif
