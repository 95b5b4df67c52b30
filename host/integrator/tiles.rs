//! The dispatch loop every image integrator shares: the image cut into square tiles, one
//! submission per tile and sample batch, so that no single submission runs long (lavapipe and
//! some drivers have no watchdog; others have one that kills long dispatches). Submissions
//! stay in flight (`Context::submit`): the host records the next tile while the device runs
//! the last; reading a result buffer waits for them.

use super::RenderSettings;
use crate::gpu::{Buffer, Context};
use crate::gpu_abi::GpuPush;
use crate::pipeline::ComputePipeline;
use anyhow::{Context as _, Result};

/// Binds each (binding, buffer) pair of `bindings` to `pipeline`.
pub fn bind_all(pipeline: &ComputePipeline, bindings: &[(u32, &Buffer)]) -> Result<()> {
    for (binding, buffer) in bindings {
        pipeline.bind(*binding, buffer).with_context(|| format!("binding {binding}"))?;
    }
    Ok(())
}

/// The tile side on `ctx`'s device: the settings' if given, else the device's; a multiple of
/// `align`, the pixels a dispatch must cover together (see [`dispatch_samples`]).
pub fn tile_side(ctx: &Context, settings: &RenderSettings, align: u32) -> u32 {
    let tile = if settings.tile_size > 0 { settings.tile_size } else { ctx.workgroups.tile };
    tile.next_multiple_of(align.max(1))
}

/// How many tiles one sample batch takes.
pub fn tile_count(ctx: &Context, settings: &RenderSettings, align: u32) -> u64 {
    let tile = tile_side(ctx, settings, align);
    (settings.width.div_ceil(tile) * settings.height.div_ceil(tile)) as u64
}

/// The stride at which an image kernel deals a dispatch's `groups` workgroups to the tile's
/// regions (`tile_slot` in shaders/include/tile_region.glsl): workgroup i renders region
/// (i * stride) mod groups, in row order. Why: lavapipe hands each of its threads one
/// contiguous run of a dispatch's workgroups (Mesa's `lp_cs_tpool_queue_task`: groups /
/// threads each, in order), so with regions in order the thread whose run holds the costlier
/// part of a tile (a lit floor, against an empty sky) finishes last while the others wait:
/// both cores of the 2-core development machine were 12 % idle in a path-traced Cornell box
/// (docs/experiments/dispatch-split.md). A stride near groups / phi (a golden-ratio Weyl
/// sequence, the most even of such spreads) gives every run regions from all over the tile.
/// Coprime with `groups`, so every region is rendered once. The shader multiplies in 32 bits,
/// so dispatches of more than [`MAX_DEALT_GROUPS`] keep the plain order (1).
pub fn group_stride(groups: u32) -> u32 {
    if groups <= 2 || groups > MAX_DEALT_GROUPS {
        return 1;
    }
    const INV_PHI: f64 = 0.618_033_988_749_895;
    let mut stride = ((groups as f64 * INV_PHI).round() as u32).clamp(1, groups - 1);
    // Ends by groups - 1 at the latest, which is coprime with groups.
    while gcd(stride, groups) != 1 {
        stride += 1;
    }
    stride
}

/// The most workgroups a dispatch deals at a stride: index * stride < groups^2 fits in 32 bits.
/// vkrt's tiles are far below it (a 512² tile in workgroups of 64 is 4096).
pub const MAX_DEALT_GROUPS: u32 = 1 << 16;

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The CPU twin of the region `tile_slot` (shaders/include/tile_region.glsl) picks: the region (in workgroups, row order) that
/// workgroup `index` of a dispatch of `groups` workgroups renders.
pub fn tile_region(index: u32, groups: u32, stride: u32) -> u32 {
    ((index as u64 * stride.max(1) as u64) % groups as u64) as u32
}

/// Renders samples `sample_base .. sample_base + sample_count` of every pixel, one submission
/// per tile; `on_tile()` runs after each. `total_spp` goes to the shader (for stratification).
/// `scene` is the scene's part of the push constants (`GpuBvh::push`). Each dispatch covers
/// whole `align` x `align` squares, past the image's edge if need be: the path tracer's
/// scattered coherence deals each square's pixels to its invocations in a random order
/// (`path::coherence`), so an invocation outside the image may hold a pixel inside it.
#[allow(clippy::too_many_arguments)]
pub fn dispatch_samples(
    ctx: &Context,
    scene: &GpuPush,
    pipeline: &ComputePipeline,
    what: &str,
    settings: &RenderSettings,
    align: u32,
    sample_base: u32,
    sample_count: u32,
    total_spp: u32,
    on_tile: &mut dyn FnMut(),
) -> Result<()> {
    let tile = tile_side(ctx, settings, align);
    let align = align.max(1);
    let wg = ctx.workgroups;
    for ty in 0..settings.height.div_ceil(tile) {
        for tx in 0..settings.width.div_ceil(tile) {
            let push = GpuPush { tile_x: tx * tile, tile_y: ty * tile, sample_base, sample_count, total_spp, ..*scene };
            let w = tile.min(settings.width - push.tile_x).next_multiple_of(align);
            let h = tile.min(settings.height - push.tile_y).next_multiple_of(align);
            let groups = [w.div_ceil(wg.x), h.div_ceil(wg.y), 1];
            let push = GpuPush { group_stride: group_stride(groups[0] * groups[1]), group_width: wg.x, group_height: wg.y, ..push };
            ctx.submit(what, |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups))?;
            on_tile();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_region_is_rendered_once() {
        for groups in 1..=4096u32 {
            let stride = group_stride(groups);
            let mut seen = vec![false; groups as usize];
            for i in 0..groups {
                let r = tile_region(i, groups, stride) as usize;
                assert!(!seen[r], "{groups} groups, stride {stride}: region {r} twice");
                seen[r] = true;
            }
        }
        // The shader's 32-bit product: (groups - 1) * stride must fit wherever a stride is used.
        for groups in [MAX_DEALT_GROUPS - 1, MAX_DEALT_GROUPS] {
            assert!((groups as u64 - 1) * group_stride(groups) as u64 <= u32::MAX as u64);
        }
        assert_eq!(group_stride(MAX_DEALT_GROUPS + 1), 1);
    }

    /// What the stride is for: each thread's contiguous run of workgroups (lavapipe splits a
    /// dispatch in order) covers every horizontal band of the tile about equally.
    #[test]
    fn every_threads_run_covers_the_whole_tile() {
        let (gx, gy) = (16u32, 16u32); // a 128-pixel tile in 8 x 8 workgroups
        let groups = gx * gy;
        let stride = group_stride(groups);
        for threads in [2u32, 3, 4, 8, 16] {
            let run = groups / threads;
            for t in 0..threads {
                // Regions of this run in the top and in the bottom half of the tile.
                let top = (t * run..(t + 1) * run).filter(|&i| tile_region(i, groups, stride) / gx < gy / 2).count() as f64;
                let share = top / run as f64;
                assert!((share - 0.5).abs() <= 0.1, "{threads} threads: run {t} has {share:.2} of its regions in the top half");
                // In order, run 0 of 2 would hold only the top half.
                assert!(threads > 2 || (0..run).any(|i| tile_region(i, groups, stride) / gx >= gy / 2));
            }
        }
    }
}
