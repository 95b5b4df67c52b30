//! A scene uploaded to the GPU: BVH arrays plus shading data, ready to bind.

use crate::bvh::{self, BuildConfig, BuilderKind};
use crate::gpu::{Buffer, Context, TexelView};
use crate::layout::flatten::{flatten_as, FlatBvh};
use crate::layout::{GpuPush, LayoutKind};
use crate::pipeline::ComputePipeline;
use crate::layout::scene_buffers::SceneBuffers;
use crate::layout::texture_atlas::{TextureAtlas, TEXEL_BUDGET_BYTES};
use crate::scene::Scene;
use anyhow::{Context as _, Result};
use ash::vk;

/// How long building and uploading took, for reports.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrepareTimes {
    pub build_seconds: f64,
    pub upload_seconds: f64,
}

/// CPU side of a prepared scene: the flat BVH and the other arrays.
pub struct PreparedScene {
    pub flat: FlatBvh,
    pub buffers: SceneBuffers,
    pub atlas: TextureAtlas,
    pub build_seconds: f64,
}

impl PreparedScene {
    /// Builds with `builder` and lays the tree out as the default (threaded) layout.
    pub fn new(scene: &Scene, builder: BuilderKind, config: &BuildConfig) -> Result<Self> {
        Self::with_layout(scene, builder, LayoutKind::default(), config)
    }

    /// Builds with `builder` and lays the tree out as `layout`.
    pub fn with_layout(scene: &Scene, builder: BuilderKind, layout: LayoutKind, config: &BuildConfig) -> Result<Self> {
        let start = std::time::Instant::now();
        let (boxes, centroids) = bvh::triangle_boxes(&scene.triangles);
        let tree = bvh::build(builder, &boxes, &centroids, config);
        let flat = flatten_as(&tree, &scene.triangles, layout).with_context(|| format!("flattening the BVH as {}", layout.name()))?;
        let build_seconds = start.elapsed().as_secs_f64();
        let atlas = TextureAtlas::pack(&scene.textures, TEXEL_BUDGET_BYTES);
        Ok(Self { flat, buffers: SceneBuffers::new(scene), atlas, build_seconds })
    }
}

/// The scene's buffers on the device.
pub struct GpuScene<'a> {
    // Views first: they are dropped before the buffers they view.
    pub node_texels: TexelView<'a>,
    pub triangle_texels: TexelView<'a>,
    pub nodes: Buffer<'a>,
    pub triangles: Buffer<'a>,
    pub shading: Buffer<'a>,
    pub materials: Buffer<'a>,
    pub lights: Buffer<'a>,
    pub emitters: Buffer<'a>,
    pub textures: Buffer<'a>,
    pub texels: Buffer<'a>,
    pub uvs: Buffer<'a>,
    pub light_count: u32,
    pub emitter_count: u32,
    pub triangle_count: u32,
    /// Nodes in `nodes` (all orders of a multi-order layout).
    pub node_count: u32,
    /// Which layout `nodes` holds: shaders must be the variant for it.
    pub layout: LayoutKind,
}

impl<'a> GpuScene<'a> {
    /// The scene's storage buffers by binding number, for every integrator shader; the BVH
    /// texel buffers are bound by [`GpuScene::bind_bvh`].
    pub fn bindings(&self) -> [(u32, &Buffer<'a>); 7] {
        use crate::layout::constants::*;
        [
            (BINDING_SHADING, &self.shading),
            (BINDING_MATERIALS, &self.materials),
            (BINDING_LIGHTS, &self.lights),
            (BINDING_EMITTERS, &self.emitters),
            (BINDING_TEXTURES, &self.textures),
            (BINDING_TEXELS, &self.texels),
            (BINDING_UVS, &self.uvs),
        ]
    }

    /// The scene's part of the push constants; each dispatch fills in the rest.
    pub fn push(&self) -> GpuPush {
        GpuPush { node_count: self.node_count, ..bytemuck::Zeroable::zeroed() }
    }

    /// Binds the BVH node and triangle texel buffers (BINDING_NODES, BINDING_TRIANGLES).
    pub fn bind_bvh(&self, pipeline: &ComputePipeline) -> Result<()> {
        use crate::layout::constants::{BINDING_NODES, BINDING_TRIANGLES};
        pipeline.bind_texels(BINDING_NODES, &self.node_texels)?;
        pipeline.bind_texels(BINDING_TRIANGLES, &self.triangle_texels)
    }

    pub fn upload(ctx: &'a Context, prepared: &PreparedScene) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Per-binding limits: storage buffers by byte range, the BVH's texel buffers by texel
        // count (16-byte RGBA32UI texels).
        let storage_limit = ctx.info.max_storage_buffer_range as usize;
        let texel_limit = ctx.info.max_texel_buffer_elements as usize * 16;
        let check = |name: &str, bytes: usize, limit: usize, kind: &str| -> Result<()> {
            if bytes > limit {
                anyhow::bail!("the scene's {name} take {} MiB, over this device's {} MiB {kind} limit", bytes >> 20, limit >> 20);
            }
            Ok(())
        };
        let b = &prepared.buffers;
        check("BVH nodes", prepared.flat.node_bytes().len(), texel_limit, "texel-buffer")?;
        check("triangles", std::mem::size_of_val(prepared.flat.triangles.as_slice()), texel_limit, "texel-buffer")?;
        check("shading data", std::mem::size_of_val(b.shading.as_slice()), storage_limit, "storage-buffer")?;
        check("texels", std::mem::size_of_val(prepared.atlas.texels.as_slice()), storage_limit, "storage-buffer")?;
        check("texture coordinates", std::mem::size_of_val(b.uvs.as_slice()), storage_limit, "storage-buffer")?;
        // Unused bindings still need a buffer: one zero element stands in for an empty array.
        fn or_one<T: bytemuck::Pod>(v: &[T]) -> std::borrow::Cow<'_, [T]> {
            if v.is_empty() { vec![T::zeroed()].into() } else { v.into() }
        }
        let texels = storage | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let nodes = Buffer::with_data(ctx, "bvh nodes", prepared.flat.node_bytes(), texels)?;
        let triangles = Buffer::with_data(ctx, "triangles", &prepared.flat.triangles, texels)?;
        Ok(Self {
            node_texels: nodes.texel_view(crate::gpu::TexelFormat::Rgba32Uint)?,
            triangle_texels: triangles.texel_view(crate::gpu::TexelFormat::Rgba32Uint)?,
            nodes,
            triangles,
            shading: Buffer::with_data(ctx, "shading", &b.shading, storage)?,
            materials: Buffer::with_data(ctx, "materials", &b.materials, storage)?,
            lights: Buffer::with_data(ctx, "lights", &b.lights, storage)?,
            emitters: Buffer::with_data(ctx, "emitters", &b.emitters, storage)?,
            textures: Buffer::with_data(ctx, "texture table", &or_one(&prepared.atlas.table), storage)?,
            texels: Buffer::with_data(ctx, "texels", &or_one(&prepared.atlas.texels), storage)?,
            uvs: Buffer::with_data(ctx, "texture coordinates", &or_one(&b.uvs), storage)?,
            light_count: b.lights.len() as u32,
            emitter_count: b.emitters.len() as u32,
            triangle_count: prepared.flat.triangles.len() as u32,
            node_count: prepared.flat.node_count() as u32,
            layout: prepared.flat.layout(),
        })
    }
}
