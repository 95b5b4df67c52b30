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
            let push = GpuPush {
                tile_x: tx * tile,
                tile_y: ty * tile,
                sample_base,
                sample_count,
                total_spp,
                ..*scene
            };
            let w = tile.min(settings.width - push.tile_x).next_multiple_of(align);
            let h = tile.min(settings.height - push.tile_y).next_multiple_of(align);
            let groups = [w.div_ceil(wg.x), h.div_ceil(wg.y), 1];
            ctx.submit(what, |cmd| pipeline.record_dispatch(cmd, bytemuck::bytes_of(&push), groups))?;
            on_tile();
        }
    }
    Ok(())
}
