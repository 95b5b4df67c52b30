//! The discrete-GPU submission shapes, run on any device: device buffers reached through the
//! reused staging buffers (`VKRT_MEMORY=staged`, how a GPU without resizable BAR works), or
//! written in place and read through staging (`VKRT_MEMORY=mapped-writes`, how one with it
//! works: its mapping is uncached) give the same bytes as mapped memory, for Whitted, the
//! adaptive path tracer (a host write between batches) and double-buffered ray queries; and
//! images do not depend on the tile size (which only bounds a submission's work).

mod common;

use vkrt::gpu::{Context, ContextOptions, HostAccess, Validation};
use vkrt::gpu_abi::GpuRay;
use vkrt::integrator::RenderSettings;
use vkrt::query::RayOrder;
use vkrt::query::RayQuery;

fn context(memory: Option<&str>) -> Context {
    let mut options = ContextOptions::from_env();
    options.validation.get_or_insert(Validation::IfAvailable);
    options.memory = memory.map(str::to_string);
    Context::new(&options).expect("a Vulkan device (run tools/ensure-deps.sh)")
}

/// Rays from inside the measured Cornell box in every direction: more than two ray batches.
fn rays() -> Vec<GpuRay> {
    let mut rng = common::Pcg::new(7);
    (0..150_000)
        .map(|_| {
            let d = rng.unit_vector();
            GpuRay { origin: [278.0, 273.0, 280.0], tmin: 0.0, direction: d.to_array(), tmax: f32::INFINITY }
        })
        .collect()
}

/// Whitted, adaptive path and ray-query results on `ctx`, as bytes; the Whitted render with
/// the given tile size.
fn results(ctx: &Context, tile_size: u32) -> (Vec<u8>, Vec<u8>, Vec<u8>, Vec<u8>) {
    let lab = vkrt::scene::load::load_scene(&common::repo_path("scenes/lab/cornell_box/cornell_box.yaml")).unwrap();
    let measured = vkrt::scene::load::load_scene(&common::repo_path("scenes/cornell-measured/cornell.yaml")).unwrap();
    let gpu = common::upload(ctx, &lab);
    let settings = RenderSettings { width: 72, height: 40, spp: 2, tile_size, ..RenderSettings::default() };
    let (image, _) = vkrt::integrator::whitted::render(ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    let whitted = bytemuck::cast_slice(&image.pixels).to_vec();
    let gpu = common::upload(ctx, &measured);
    let mut path = common::path_settings(48, 32, 16);
    path.adaptive = true;
    // Adaptive sampling takes no scattered coherence: every pixel its own numbers.
    path.coherence = 1;
    path.image.tile_size = tile_size;
    let (acc, stats) = vkrt::integrator::path::render(ctx, &gpu, &path, None, &mut Default::default()).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    let path_bytes = [bytemuck::cast_slice::<_, u8>(&acc.even), bytemuck::cast_slice(&acc.odd), bytemuck::cast_slice(&acc.counts)].concat();
    let rays = rays();
    let mut query = RayQuery::new(ctx, &gpu.bvh).unwrap();
    let given = {
        query.order = RayOrder::Given;
        bytemuck::cast_slice(&query.trace(&rays, false).unwrap()).to_vec()
    };
    query.order = RayOrder::Sorted;
    let sorted = bytemuck::cast_slice(&query.trace(&rays, true).unwrap()).to_vec();
    common::assert_no_validation_messages(ctx);
    (whitted, path_bytes, given, sorted)
}

#[test]
fn staged_memory_gives_the_same_bytes_as_mapped_memory() {
    let staged = context(Some("staged"));
    assert_eq!(staged.host_access, HostAccess::Staged);
    let before = staged.staged_bytes();
    let from_staged = results(&staged, 16);
    // The scenes, the per-batch block writes, the read-backs and both traces' rays and hits
    // went through staging.
    let (ray, hit) = (std::mem::size_of::<GpuRay>(), std::mem::size_of::<vkrt::gpu_abi::GpuHit>());
    let least = 2 * rays().len() * (ray + hit);
    assert!(staged.staged_bytes() - before > least as u64, "staged only {} bytes", staged.staged_bytes() - before);
    drop(staged);
    let default = context(None);
    let from_default = results(&default, 16);
    if default.host_access == HostAccess::Mapped {
        assert_eq!(default.staged_bytes(), 0, "a mapped device staged bytes");
    }
    assert!(from_staged.0 == from_default.0, "Whitted images differ");
    assert!(from_staged.1 == from_default.1, "adaptive path sums differ");
    assert!(from_staged.2 == from_default.2, "closest hits differ");
    assert!(from_staged.3 == from_default.3, "any hits (sorted order) differ");
    // Tiles of 16 and 64 pixels: the same images (the rays are the same on both).
    let big_tiles = results(&default, 64);
    assert!(big_tiles.0 == from_default.0, "Whitted image depends on the tile size");
    assert!(big_tiles.1 == from_default.1, "path sums depend on the tile size");
}

/// A resizable-BAR GPU's way (mapped, uncached device memory): writes in place, reads through
/// staging; the same bytes, and only the reads were staged.
#[test]
fn mapped_writes_with_staged_reads_give_the_same_bytes() {
    let default = context(None);
    let from_default = results(&default, 16);
    drop(default);
    let ctx = context(Some("mapped-writes"));
    if ctx.host_access == HostAccess::Staged {
        // A device whose memory is not host-visible cannot map it; nothing to compare.
        assert_eq!(ctx.info.host_access, HostAccess::Staged);
        return;
    }
    assert_eq!(ctx.host_access, HostAccess::MappedWrites);
    let before = ctx.staged_bytes();
    let got = results(&ctx, 16);
    let staged = ctx.staged_bytes() - before;
    let (ray, hit) = (std::mem::size_of::<GpuRay>(), std::mem::size_of::<vkrt::gpu_abi::GpuHit>());
    // Both traces' hits came back through staging, their rays did not go through it.
    assert!(staged >= (2 * rays().len() * hit) as u64, "staged only {staged} bytes");
    assert!(staged < (2 * rays().len() * (ray + hit)) as u64, "rays were staged too: {staged} bytes");
    assert!(got.0 == from_default.0, "Whitted images differ");
    assert!(got.1 == from_default.1, "adaptive path sums differ");
    assert!(got.2 == from_default.2, "closest hits differ");
    assert!(got.3 == from_default.3, "any hits (sorted order) differ");
}

#[test]
fn an_unknown_memory_mode_is_an_error_naming_it() {
    let mut options = ContextOptions::from_env();
    options.memory = Some("fast".into());
    let err = Context::new(&options).err().expect("VKRT_MEMORY=fast must be refused");
    assert!(format!("{err:#}").contains("VKRT_MEMORY='fast'"), "{err:#}");
}
