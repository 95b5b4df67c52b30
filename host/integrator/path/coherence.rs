//! Coherent sampling: which pixel each invocation of a path-tracing dispatch renders, and which
//! sample numbers it draws (`PathSettings::coherence`, `PathSettings::coherence_block`).
//!
//! Coherent path tracing (Sadeghi, Chen & Jensen 2009, "Coherent path tracing", JGT 14(2)):
//! when the lanes of a SIMD subgroup draw the same sample numbers they take the same light,
//! lobe, direction and roulette choices, so their rays stay alike and their paths end
//! together; on lavapipe that halves the time per sample. Each pixel's estimator is unchanged
//! (its own Owen-scrambled sequence), so the expected error per pixel is too; what changes is
//! that the errors of the pixels sharing numbers are correlated. In a row (block 0, the earlier
//! form) they show as horizontal streaks. Scattered over a block (the default) the group's
//! pixels are spread over a 16 x 16 square (in Z order with the default sampler, at random with
//! the others), so correlated errors are apart and the noise looks like independent noise:
//! with the Z-ordered sampler relMSE +2-3 % and HDR-FLIP +3-4 % against no shared numbers at
//! equal spp, at 0.55-0.56x the time (docs/experiments/zsobol-blue-noise.md; with `sobol`
//! over 32 x 32 squares: docs/experiments/scattered-coherence.md).
//!
//! [`coherent_pixel`] is the CPU twin of shaders/include/sampler.glsl's `coherent_pixel`: the
//! tests use it to find the pixels whose errors must be correlated.

use crate::geom::morton::{compact2, spread2};
use crate::gpu_abi::constants::ZSOBOL_CELL_BITS;
use anyhow::{bail, Result};

/// Pixels that draw the same sample numbers by default: one row of the 8-wide image workgroup,
/// all of lavapipe's 8 lanes (`gpu::workgroups`); on wider subgroups several groups share one.
pub const DEFAULT_COHERENCE: u32 = 8;
/// The side of the square over which a group's pixels are spread by default. With the
/// Z-ordered sampler 16 wins on both metrics at equal time on three Cornell boxes: against 32,
/// 0.81-0.89x the time for +0-2 % FLIP at equal spp (8: 0.73-0.75x the time but FLIP +10 %,
/// blotchy; docs/experiments/zsobol-blue-noise.md). (With `sobol`'s random dealing 16 cost
/// FLIP +7 % against 32: docs/experiments/scattered-coherence.md.)
pub const DEFAULT_COHERENCE_BLOCK: u32 = 16;
/// The largest block side (the dispatch covers whole blocks: tiles are cut to multiples of it).
pub const MAX_COHERENCE_BLOCK: u32 = 256;

/// Fails, naming the flag, unless `coherence` and `block` are a valid pair: `block` 0 (rows)
/// or a power of two from 8 to [`MAX_COHERENCE_BLOCK`]; with a block, `coherence` a power of
/// two that fits in one (so that groups are whole runs of slots). Adaptive sampling takes
/// either: its blocks are whole coherence blocks (`super::adaptive::BlockGrid`), so a block's
/// neighbours never share its numbers.
pub fn check(coherence: u32, block: u32) -> Result<()> {
    if coherence == 0 {
        bail!("--coherence must be at least 1");
    }
    if block == 0 {
        return Ok(());
    }
    if !block.is_power_of_two() || !(8..=MAX_COHERENCE_BLOCK).contains(&block) {
        bail!("--coherence-block {block}: must be 0 (groups in a row) or a power of two from 8 to {MAX_COHERENCE_BLOCK}");
    }
    if coherence > 1 && (!coherence.is_power_of_two() || coherence > block * block) {
        bail!("--coherence {coherence} with --coherence-block {block}: the group must be a power of two of at most {} pixels", block * block);
    }
    Ok(())
}

/// log2 of the block side for the shader (0: rows, or no coherence).
pub fn block_bits(coherence: u32, block: u32) -> u32 {
    if coherence <= 1 || block == 0 {
        0
    } else {
        block.trailing_zeros()
    }
}

/// The pixels a dispatch must cover together: whole blocks when groups are scattered.
pub fn dispatch_alignment(coherence: u32, block: u32) -> u32 {
    if block_bits(coherence, block) == 0 {
        1
    } else {
        block
    }
}

/// rng.glsl's `hash_pcg` (Jarzynski & Olano 2020, "Hash functions for GPU rendering").
fn hash_pcg(v: u32) -> u32 {
    let state = v.wrapping_mul(747796405).wrapping_add(2891336453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
    (word >> 22) ^ word
}

/// sampler.glsl's `sample_key`: a row of `coherence` pixels shares a key.
fn row_key(slot: (u32, u32), width: u32, coherence: u32) -> u32 {
    let c = coherence.max(1);
    slot.1 * width.div_ceil(c) + slot.0 / c
}

/// The pixel invocation `slot` (tile origin plus global invocation id) renders, and the key of
/// the sample numbers it draws; `seed` is the render's seed, `zordered` true for the Z-ordered
/// sampler (whose groups are dealt in Z order, sampler.glsl's `coherent_pixel` says how). The
/// pixel may lie outside the image (the invocation then does nothing) only where `slot` does
/// too, for a dispatch that covers whole blocks.
pub fn coherent_pixel(slot: (u32, u32), width: u32, coherence: u32, block: u32, seed: u32, zordered: bool) -> ((u32, u32), u32) {
    let bits = block_bits(coherence, block);
    if bits == 0 {
        if !zordered {
            return (slot, row_key(slot, width, coherence));
        }
        let c = coherence.max(1);
        let g = (slot.0 / c, slot.1);
        let tiles_per_row = (width.div_ceil(c) + 255) >> 8;
        let tile = (g.1 >> 8) * tiles_per_row + (g.0 >> 8);
        return (slot, (tile << ZSOBOL_CELL_BITS) | spread2(g.0 & 255) | (spread2(g.1 & 255) << 1));
    }
    let side = 1u32 << bits;
    let mask = side - 1;
    let blocks_per_row = (width + mask) >> bits;
    let (bx, by) = (slot.0 >> bits, slot.1 >> bits);
    let block_index = by * blocks_per_row + bx;
    let q = ((slot.1 & mask) << bits) | (slot.0 & mask);
    let block_seed = hash_pcg(block_index ^ hash_pcg(seed ^ 0x5bd1e995));
    if zordered {
        let k = coherence.trailing_zeros();
        let (group, member) = (q >> k, q & (coherence - 1));
        let (kx, ky) = (k / 2, k - k / 2);
        let (w, h) = (side >> kx, side >> ky);
        let roll = hash_pcg(block_seed ^ member.wrapping_mul(0x9e3779b9));
        let x = compact2(group).wrapping_add(roll) & (w - 1);
        let y = compact2(group >> 1).wrapping_add(roll >> 16) & (h - 1);
        let key = (block_index << ZSOBOL_CELL_BITS) | group;
        return (((bx << bits) + (member & ((1 << kx) - 1)) * w + x, (by << bits) + (member >> kx) * h + y), key);
    }
    // A 4-round Feistel network on the slot's two halves: a bijection of the block's slots.
    let (mut l, mut r) = (q >> bits, q & mask);
    for round in 0..4u32 {
        let f = hash_pcg(r ^ block_seed.wrapping_add(round.wrapping_mul(0x9e3779b9))) & mask;
        (l, r) = (r, l ^ f);
    }
    let key = block_index * (side * side / coherence) + q / coherence;
    (((bx << bits) + r, (by << bits) + l), key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_block_is_dealt_out_once_and_groups_hold_coherence_pixels() {
        for zordered in [false, true] {
            for (c, b) in [(8, 32), (2, 8), (16, 32)] {
                dealt_once(96, 64, c, b, zordered);
            }
        }
    }

    fn dealt_once(w: u32, h: u32, c: u32, b: u32, zordered: bool) {
        let mut seen = vec![0u32; (w * h) as usize];
        let mut groups = std::collections::HashMap::<u32, Vec<(u32, u32)>>::new();
        for y in 0..h {
            for x in 0..w {
                let (p, key) = coherent_pixel((x, y), w, c, b, 7, zordered);
                assert_eq!((p.0 / b, p.1 / b), (x / b, y / b), "a pixel left its block");
                seen[(p.1 * w + p.0) as usize] += 1;
                groups.entry(key).or_default().push(p);
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "not a permutation");
        assert_eq!(groups.len() as u32, w * h / c);
        assert!(groups.values().all(|g| g.len() == c as usize));
        // Scattered: a group's pixels are rarely neighbours in a row.
        let adjacent = groups.values().flat_map(|g| g.iter().map(move |p| g.contains(&(p.0 + 1, p.1)) as u32)).sum::<u32>();
        assert!(adjacent * 20 < w * h, "{c}/{b} z {zordered}: {adjacent} of {} pixels have a group-mate to their right", w * h);
    }

    /// Z order: a pixel's right and lower neighbours belong to groups next to its own in Z
    /// order (same cell quad, or a neighbouring one) except where a sub-tile's roll wraps, so
    /// that their Z-ordered sets are complementary strata of one sequence.
    #[test]
    fn zordered_neighbours_take_neighbouring_cells() {
        let (w, h, c, b) = (64u32, 64u32, 8u32, 32u32);
        let mut cell = vec![0u32; (w * h) as usize];
        for y in 0..h {
            for x in 0..w {
                let (p, key) = coherent_pixel((x, y), w, c, b, 3, true);
                cell[(p.1 * w + p.0) as usize] = key;
            }
        }
        let (mut same_quad, mut pairs) = (0, 0);
        for y in 0..h {
            for x in 0..w - 1 {
                let (a, n) = (cell[(y * w + x) as usize], cell[(y * w + x + 1) as usize]);
                pairs += 1;
                same_quad += (a >> 2 == n >> 2) as u32;
            }
        }
        // Half of all horizontal pairs share a quad of cells when the tiles are 2-aligned;
        // random rolls misalign some sub-tiles, so at least a quarter must.
        assert!(same_quad * 4 >= pairs, "{same_quad} of {pairs} horizontal neighbours share a quad of cells");
        // And the rows-and-no-coherence form is the pixel's own Z-order position.
        assert_eq!(coherent_pixel((5, 3), 100, 1, 32, 0, true).1, 0b11011);
        assert_eq!(coherent_pixel((300, 2), 600, 1, 32, 0, true).1, (1 << ZSOBOL_CELL_BITS) | 0b100_0101_1000);
    }

    #[test]
    fn rows_and_no_coherence_keep_the_earlier_keys() {
        assert_eq!(coherent_pixel((13, 2), 20, 1, 32, 0, false), ((13, 2), 2 * 20 + 13));
        assert_eq!(coherent_pixel((13, 2), 20, 8, 0, 0, false), ((13, 2), 2 * 3 + 1));
    }

    #[test]
    fn bad_pairs_are_refused() {
        assert!(check(8, 32).is_ok() && check(1, 0).is_ok() && check(6, 0).is_ok() && check(1, 32).is_ok());
        assert!(check(0, 0).is_err());
        assert!(check(8, 24).is_err() && check(8, 4).is_err() && check(8, 512).is_err());
        assert!(check(6, 32).is_err());
    }
}
