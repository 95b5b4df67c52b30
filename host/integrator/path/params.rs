//! The path tracer's settings as its shader reads them (`GpuPathParams`), and the bindings it
//! has besides every integrator's.

use super::adaptive::BlockGrid;
use super::PathSettings;
use crate::gpu_abi::constants::*;
use crate::gpu_abi::GpuPathParams;
use crate::pipeline::BindingKind;
use crate::prepare::GpuScene;
use anyhow::{bail, Result};

/// The path tracer's bindings besides `frame::INTEGRATOR_BINDINGS`.
pub const PATH_BINDINGS: &[(u32, BindingKind)] = &[
    (BINDING_LIGHT_PICKS, BindingKind::Texels),
    (BINDING_PATH_PARAMS, BindingKind::Uniform),
    (BINDING_SUM_EVEN_R, BindingKind::Storage),
    (BINDING_SUM_EVEN_G, BindingKind::Storage),
    (BINDING_SUM_EVEN_B, BindingKind::Storage),
    (BINDING_SUM_ODD_R, BindingKind::Storage),
    (BINDING_SUM_ODD_G, BindingKind::Storage),
    (BINDING_SUM_ODD_B, BindingKind::Storage),
    (BINDING_SAMPLE_COUNTS, BindingKind::Storage),
    (BINDING_BLOCK_SAMPLES, BindingKind::Storage),
    (BINDING_RAY_COUNTS, BindingKind::Storage),
    (BINDING_MIRROR_PROBE, BindingKind::Storage),
    (BINDING_MIRRORS, BindingKind::Texels),
    (BINDING_MIRROR_PLANES, BindingKind::Texels),
    (BINDING_CASTERS, BindingKind::Texels),
];

/// The settings as the shader reads them, with the scene's light table (already on the GPU).
pub fn path_params(scene: &GpuScene, settings: &PathSettings) -> Result<GpuPathParams> {
    let max_depth = match settings.max_depth {
        Some(0) => bail!("max depth 0 traces no rays; use 1 or more"),
        Some(d) => d,
        None => PATH_DEPTH_UNBOUNDED,
    };
    if settings.sample_rate == 0 {
        bail!("sample rate must be positive");
    }
    if settings.zsobol_log2 > ZSOBOL_MAX_LOG2 {
        bail!("Z-ordered sample sets of 2^{} spp: at most 2^{ZSOBOL_MAX_LOG2}", settings.zsobol_log2);
    }
    if settings.coherence == 0 {
        bail!("coherence must be at least 1 (pixels that share sample numbers)");
    }
    Ok(GpuPathParams {
        max_depth,
        rr_depth: PATH_RR_DEPTH,
        sampler_kind: settings.sampler.gpu_value(),
        sample_rate: settings.sample_rate,
        pick_count: scene.pick_count,
        nee: settings.nee as u32,
        inv_total_weight: scene.inv_total_weight,
        coherence: settings.coherence,
        adaptive: if settings.adaptive {
            BlockGrid::new(settings.image.width, settings.image.height, settings.coherence, settings.coherence_block).block_w
        } else {
            0
        },
        coherence_block_bits: super::coherence::block_bits(settings.coherence, settings.coherence_block),
        zsobol_log2: settings.zsobol_log2,
        // The mirror variant samples light through them (`PathSettings::mirror_sampling`).
        mirror_count: if settings.mirror_sampling { scene.mirror_plane_count } else { 0 },
        // Aiming bounces at them (`PathSettings::caster_guiding`).
        caster_count: if settings.caster_guiding { scene.caster_count } else { 0 },
        _pad0: 0,
        _pad1: 0,
        _pad2: 0,
    })
}
