//! A scene uploaded to the GPU: BVH arrays plus shading data, ready to bind.

use crate::bvh::{self, BuildConfig, BuilderKind};
use crate::gpu::{Context, TexelArray, TexelFormat};
use crate::layout::compact::QuantGrid;
use crate::layout::flatten::{flatten_as, FlatBvh};
use crate::layout::{GpuPush, LayoutKind};
use crate::pipeline::ComputePipeline;
use crate::layout::scene_buffers::SceneBuffers;
use crate::layout::texture_atlas::{TextureAtlas, TEXEL_BUDGET_BYTES};
use crate::scene::Scene;
use anyhow::{Context as _, Result};

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

/// The scene's arrays on the device. All of them are read at per-lane indices (a ray's node, a
/// hit's triangle and material, a sampled light), so all are texel buffers; see
/// shaders/include/scene_bindings.glsl for why.
pub struct GpuScene<'a> {
    pub nodes: TexelArray<'a>,
    pub triangles: TexelArray<'a>,
    pub shading: TexelArray<'a>,
    pub materials: TexelArray<'a>,
    pub lights: TexelArray<'a>,
    pub emitters: TexelArray<'a>,
    pub textures: TexelArray<'a>,
    pub texels: TexelArray<'a>,
    pub uvs: TexelArray<'a>,
    pub light_count: u32,
    pub emitter_count: u32,
    pub triangle_count: u32,
    /// Nodes in `nodes` (all orders of a multi-order layout).
    pub node_count: u32,
    /// Which layout `nodes` holds: shaders must be the variant for it.
    pub layout: LayoutKind,
    /// The compact layout's grid (zero for the others); it goes to the shaders in the push
    /// constants.
    pub grid: QuantGrid,
}

impl<'a> GpuScene<'a> {
    /// The scene's shading arrays by binding number (texel buffers, like the BVH's, which
    /// [`GpuScene::bind_bvh`] binds).
    pub fn bindings(&self) -> [(u32, &TexelArray<'a>); 7] {
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
        GpuPush {
            node_count: self.node_count,
            grid_origin: self.grid.origin.to_array(),
            grid_scale: self.grid.scale.to_array(),
            ..bytemuck::Zeroable::zeroed()
        }
    }

    /// Binds the BVH node and triangle texel buffers (BINDING_NODES, BINDING_TRIANGLES).
    pub fn bind_bvh(&self, pipeline: &ComputePipeline) -> Result<()> {
        use crate::layout::constants::{BINDING_NODES, BINDING_TRIANGLES};
        pipeline.bind_texels(BINDING_NODES, &self.nodes.view)?;
        pipeline.bind_texels(BINDING_TRIANGLES, &self.triangles.view)
    }

    /// Binds everything of the scene an integrator shader reads: the BVH and [`Self::bindings`].
    pub fn bind_scene(&self, pipeline: &ComputePipeline) -> Result<()> {
        self.bind_bvh(pipeline)?;
        for (binding, array) in self.bindings() {
            pipeline.bind_texels(binding, &array.view).with_context(|| format!("binding {binding}"))?;
        }
        Ok(())
    }

    /// Uploads `prepared`; fails, naming the array, if one holds more texels than the device
    /// lets a texel buffer address.
    pub fn upload(ctx: &'a Context, prepared: &PreparedScene) -> Result<Self> {
        use TexelFormat::{R32Uint, Rgba32Uint};
        let b = &prepared.buffers;
        Ok(Self {
            nodes: TexelArray::with_data(ctx, "BVH nodes", prepared.flat.node_bytes(), Rgba32Uint)?,
            triangles: TexelArray::with_data(ctx, "triangles", &prepared.flat.triangles, Rgba32Uint)?,
            shading: TexelArray::with_data(ctx, "shading data", &b.shading, Rgba32Uint)?,
            materials: TexelArray::with_data(ctx, "materials", &b.materials, Rgba32Uint)?,
            lights: TexelArray::with_data(ctx, "lights", &b.lights, Rgba32Uint)?,
            emitters: TexelArray::with_data(ctx, "emitters", &b.emitters, Rgba32Uint)?,
            textures: TexelArray::with_data(ctx, "texture table", &prepared.atlas.table, Rgba32Uint)?,
            // One packed RGBA8 texel per R32UI texel, decoded in the shader as before.
            texels: TexelArray::with_data(ctx, "texels", &prepared.atlas.texels, R32Uint)?,
            uvs: TexelArray::with_data(ctx, "texture coordinates", &b.uvs, Rgba32Uint)?,
            light_count: b.lights.len() as u32,
            emitter_count: b.emitters.len() as u32,
            triangle_count: prepared.flat.triangles.len() as u32,
            node_count: prepared.flat.node_count() as u32,
            layout: prepared.flat.layout(),
            grid: prepared.flat.grid(),
        })
    }
}
