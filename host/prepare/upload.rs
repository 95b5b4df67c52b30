//! A prepared scene on the device: the BVH arrays ([`GpuBvh`], all a batch query needs) and the
//! shading arrays, texture atlas and light table beside them ([`GpuScene`], what the
//! integrators bind). Every array is read at per-lane indices (a ray's node, a hit's triangle
//! and material, a sampled light), so all are texel buffers; shaders/include/scene_bindings.glsl
//! says why.

use super::{PreparedScene, SceneArrays, SceneInfo};
use crate::accel::{FlatBvh, LayoutKind};
use crate::gpu::{Buffer, Context, TexelArray, TexelFormat};
use crate::gpu_abi::constants::*;
use crate::gpu_abi::{GpuInstance, GpuPush, GpuTriangle};
use crate::pipeline::shaders::Tracing;
use crate::pipeline::{BindingKind, ComputePipeline};
use anyhow::{Context as _, Result};
use ash::vk;
use bytemuck::Zeroable;

/// A BVH on the device: nodes of one layout and the triangles in leaf order.
pub struct GpuBvh<'a> {
    pub nodes: TexelArray<'a>,
    pub triangles: TexelArray<'a>,
    pub triangle_count: u32,
    /// The triangle list's uniform block (BINDING_TRIANGLE_LIST, `accel::triangle_list`) and
    /// how many triangles it holds: every pipeline that traces sets SPEC_LIST_TRIANGLES to it.
    pub list: Buffer<'a>,
    pub list_count: u32,
    /// Which layout `nodes` holds: shaders must be the variant for it.
    pub layout: LayoutKind,
    /// The BVH's part of the push constants (node count, layout data); each dispatch fills in
    /// the rest.
    pub push: GpuPush,
    /// A two-level BVH's instances (BINDING_INSTANCES, `accel::two_level`): `nodes` then holds
    /// both levels, walked by the shaders' `_two_level_<id>` builds. None for a one-level BVH.
    pub instances: Option<TexelArray<'a>>,
    /// How many instances `instances` holds (0 for a one-level BVH).
    pub instance_count: u32,
}

impl<'a> GpuBvh<'a> {
    /// Uploads `flat`; fails, naming the array, if one holds more texels than the device lets a
    /// texel buffer address.
    pub fn upload(ctx: &'a Context, flat: &FlatBvh) -> Result<Self> {
        Self::upload_arrays(ctx, flat.layout(), flat.nodes.bytes(), &flat.triangles, flat.push())?.with_instances(ctx, flat.nodes.instances())
    }

    /// With a two-level BVH's instances uploaded beside it (none: as it is).
    pub fn with_instances(mut self, ctx: &'a Context, instances: &[GpuInstance]) -> Result<Self> {
        if !instances.is_empty() {
            self.instances = Some(TexelArray::with_data(ctx, "instances", instances, TexelFormat::Rgba32Uint)?);
            self.instance_count = u32::try_from(instances.len()).context("more than 2^32 instances")?;
        }
        Ok(self)
    }

    /// The same from the arrays themselves (`layout`'s node bytes, the triangles in leaf order
    /// and the BVH's push constants), wherever they are: a `FlatBvh`, or a mapped cache file.
    pub fn upload_arrays(ctx: &'a Context, layout: LayoutKind, nodes: &[u8], triangles: &[GpuTriangle], push: GpuPush) -> Result<Self> {
        // The triangle list as its uniform block holds it: MAX_LIST_TRIANGLES entries, the
        // unused ones zero (the shader's loop reads only push.list_count of them).
        let listed = listed(triangles, &push);
        let mut block = vec![GpuTriangle::zeroed(); MAX_LIST_TRIANGLES as usize];
        block[..listed.len()].copy_from_slice(listed);
        Ok(Self {
            list: Buffer::with_data(ctx, "triangle list", &block, vk::BufferUsageFlags::UNIFORM_BUFFER)?,
            list_count: listed.len() as u32,
            nodes: TexelArray::with_data(ctx, "BVH nodes", nodes, TexelFormat::Rgba32Uint)?,
            triangles: TexelArray::with_data(ctx, "triangles", triangles, TexelFormat::Rgba32Uint)?,
            triangle_count: triangles.len() as u32,
            layout,
            push,
            instances: None,
            instance_count: 0,
        })
    }

    /// Binds the node and triangle texel buffers and the triangle list (BINDING_NODES,
    /// BINDING_TRIANGLES, BINDING_TRIANGLE_LIST), and a two-level BVH's instances
    /// (BINDING_INSTANCES).
    pub fn bind(&self, pipeline: &ComputePipeline) -> Result<()> {
        pipeline.bind_texels(BINDING_NODES, &self.nodes.view)?;
        if let Some(instances) = &self.instances {
            pipeline.bind_texels(BINDING_INSTANCES, &instances.view)?;
        }
        pipeline.bind_texels(BINDING_TRIANGLES, &self.triangles.view)?;
        pipeline.bind(BINDING_TRIANGLE_LIST, &self.list)
    }

    /// The SPIR-V of `shader` that walks this BVH: the build for its layout, or the two-level
    /// one for its levels' layout.
    pub fn spirv(&self, shader: Tracing) -> Result<&'static [u8]> {
        if self.instances.is_some() {
            shader.spirv_two_level(self.layout).with_context(|| format!("no shader walks a two-level BVH laid out as {}", self.layout.name()))
        } else {
            Ok(shader.spirv(self.layout))
        }
    }

    /// The bindings a pipeline walking this BVH needs besides the node and triangle arrays and
    /// the triangle list: a two-level BVH's instances.
    pub fn instance_bindings(&self) -> &'static [(u32, BindingKind)] {
        if self.instances.is_some() {
            &[(BINDING_INSTANCES, BindingKind::Texels)]
        } else {
            &[]
        }
    }

    /// The specialization constant every tracing pipeline for this BVH needs: the triangle
    /// list's size, for which the shaders unroll its loop.
    pub fn spec_constants(&self) -> [(u32, u32); 1] {
        [(SPEC_LIST_TRIANGLES, self.list_count)]
    }
}

/// The triangle list within the leaf-order triangles, as `push` places it (clamped to them).
fn listed<'t>(triangles: &'t [GpuTriangle], push: &GpuPush) -> &'t [GpuTriangle] {
    let first = (push.list_first as usize).min(triangles.len());
    &triangles[first..(first + push.list_count as usize).min(triangles.len())]
}

/// Which of the triangle list's triangles are walls (`accel::walls`, bit i for the list's i-th)
/// in the scene of `a`: shadow rays end at surface points and at point lights' positions, so a
/// wall must have those on its side too.
pub fn list_walls(a: &SceneArrays, info: &SceneInfo) -> u32 {
    let positions: Vec<glam::Vec3> = a.lights.iter().filter(|l| l.kind != LIGHT_DIRECTIONAL).map(|l| glam::Vec3::from(l.position)).collect();
    crate::accel::walls::walls(listed(a.triangles, &a.push), a.triangles, &positions, &info.bounds, info.scale)
}

/// A whole prepared scene on the device.
pub struct GpuScene<'a> {
    pub bvh: GpuBvh<'a>,
    /// Which of the triangle list's triangles are walls (`accel::walls`): the integrators'
    /// shadow rays skip them (SPEC_LIST_WALLS). Decided at every upload, like the mirrors.
    pub list_walls: u32,
    pub shading: TexelArray<'a>,
    pub materials: TexelArray<'a>,
    pub lights: TexelArray<'a>,
    pub emitters: TexelArray<'a>,
    pub textures: TexelArray<'a>,
    pub texels: TexelArray<'a>,
    pub uvs: TexelArray<'a>,
    pub tangents: TexelArray<'a>,
    /// The path tracer's light-selection alias table (`GpuLightPick[]`).
    pub light_picks: TexelArray<'a>,
    /// The planar mirrors the path tracer samples light through (`GpuMirror[]` grouped by
    /// plane, and the planes, `GpuMirrorPlane[]`; `super::mirrors`; one zero entry without any).
    pub mirrors: TexelArray<'a>,
    pub mirror_planes: TexelArray<'a>,
    pub mirror_plane_count: u32,
    /// The caustic casters diffuse bounces are partly aimed at (`GpuCaster[]`, `super::casters`;
    /// one zero entry without any).
    pub casters: TexelArray<'a>,
    pub caster_count: u32,
    pub light_count: u32,
    pub emitter_count: u32,
    /// Entries in `light_picks`.
    pub pick_count: u32,
    /// 1 / the light table's total weight (0 when nothing emits).
    pub inv_total_weight: f32,
    /// The environment map's radiance and sampling distribution (BINDING_ENV_TEXELS,
    /// BINDING_ENV_CDF; one zero texel each without a map).
    pub env_texels: TexelArray<'a>,
    pub env_cdf: TexelArray<'a>,
    /// What the frame uniform says of the map (`EnvFrame::NONE` without one).
    pub env: super::envmap::EnvFrame,
    /// The probability that light sampling picks the map (its light-table entry, the last).
    pub env_pick_pmf: f32,
    /// The ambient light the Whitted integrator adds (Kd times it, unshadowed): the scene's
    /// (`SceneInfo::ambient`), plus an environment map's mean radiance; a map that replaces the
    /// default light replaces the ambient that came with it too.
    pub ambient: glam::Vec3,
    pub info: SceneInfo,
}

impl<'a> GpuScene<'a> {
    /// Uploads `prepared`; fails, naming the array, if one holds more texels than the device
    /// lets a texel buffer address.
    pub fn upload(ctx: &'a Context, prepared: &PreparedScene) -> Result<Self> {
        Self::upload_arrays(ctx, &prepared.arrays(), &prepared.info)
    }

    /// The same from the arrays, wherever they are (a `PreparedScene`, or a mapped cache file),
    /// seen as `info` says.
    pub fn upload_arrays(ctx: &'a Context, a: &SceneArrays, info: &SceneInfo) -> Result<Self> {
        use TexelFormat::{R32Uint, Rgba32Uint};
        // Decided at every upload (cheap: one pass over the triangles), so prepared scenes and
        // their cache files do not hold it.
        let (materials, mirrors) = super::mirrors::planar_mirrors(a.world_triangles, a.world_shading, a.materials);
        let (mirrors, planes) = super::mirrors::by_plane(&mirrors);
        let casters = super::casters::caustic_casters(a.world_triangles, a.world_shading, &materials, a.emitters, !a.lights.is_empty(), info.radius);
        Ok(Self {
            bvh: GpuBvh::upload_arrays(ctx, a.layout, a.nodes, a.triangles, a.push)?.with_instances(ctx, a.instances)?,
            list_walls: list_walls(a, info),
            shading: TexelArray::with_data(ctx, "shading data", a.shading, Rgba32Uint)?,
            materials: TexelArray::with_data(ctx, "materials", &materials, Rgba32Uint)?,
            lights: TexelArray::with_data(ctx, "lights", a.lights, Rgba32Uint)?,
            emitters: TexelArray::with_data(ctx, "emitters", a.emitters, Rgba32Uint)?,
            textures: TexelArray::with_data(ctx, "texture table", a.textures, Rgba32Uint)?,
            // One packed RGBA8 texel per R32UI texel, decoded in the shader.
            texels: TexelArray::with_data(ctx, "texels", a.texels, R32Uint)?,
            uvs: TexelArray::with_data(ctx, "texture coordinates", a.uvs, Rgba32Uint)?,
            tangents: TexelArray::with_data(ctx, "tangents", a.tangents, Rgba32Uint)?,
            light_picks: TexelArray::with_data(ctx, "light picks", a.picks, Rgba32Uint)?,
            mirrors: TexelArray::with_data(ctx, "planar mirrors", &mirrors, Rgba32Uint)?,
            mirror_planes: TexelArray::with_data(ctx, "mirror planes", &planes, Rgba32Uint)?,
            mirror_plane_count: planes.len() as u32,
            casters: TexelArray::with_data(ctx, "caustic casters", &casters, Rgba32Uint)?,
            caster_count: casters.len() as u32,
            light_count: a.lights.len() as u32,
            emitter_count: a.emitters.len() as u32,
            pick_count: a.picks.len() as u32,
            inv_total_weight: if a.total_weight > 0.0 { (1.0 / a.total_weight) as f32 } else { 0.0 },
            env_texels: TexelArray::with_data::<[u32; 4]>(ctx, "environment map", &[], Rgba32Uint)?,
            env_cdf: TexelArray::with_data::<u32>(ctx, "environment map distribution", &[], R32Uint)?,
            env: super::envmap::EnvFrame::NONE,
            env_pick_pmf: 0.0,
            ambient: info.ambient,
            info: info.clone(),
        })
    }

    /// Lights the scene with an environment map: uploads its texels and distribution, and adds
    /// it to the light table by its power. If the scene file's only light is the default one
    /// the loader added (`LoadStats::default_light`), the map replaces it: `drop_default_light`
    /// takes it out of light sampling and out of the lights the Whitted integrator loops over.
    pub fn set_environment(
        &mut self,
        ctx: &'a Context,
        env: &super::EnvLight,
        picks: &[crate::gpu_abi::GpuLightPick],
        total_weight: f64,
        drop_default_light: bool,
    ) -> Result<()> {
        use TexelFormat::{R32Uint, Rgba32Uint};
        let mut dropped = Vec::new();
        if drop_default_light && self.light_count > 0 {
            // The default light is the last light, after the emitters in the table.
            dropped.push((self.emitter_count + self.light_count - 1) as usize);
            self.light_count -= 1;
        }
        let table = super::light_table::LightTable::with_extra(picks, total_weight, env.weight(self.info.radius), &dropped);
        self.env_texels = TexelArray::with_data(ctx, "environment map", &env.texels, Rgba32Uint)?;
        self.env_cdf = TexelArray::with_data(ctx, "environment map distribution", &env.cdf, R32Uint)?;
        self.light_picks = TexelArray::with_data(ctx, "light picks", &table.picks, Rgba32Uint)?;
        self.pick_count = table.picks.len() as u32;
        self.inv_total_weight = if table.total_weight > 0.0 { (1.0 / table.total_weight) as f32 } else { 0.0 };
        self.env_pick_pmf = table.picks.last().map_or(0.0, |p| p.pmf);
        self.env = env.frame_fields();
        // The loader's ambient came with the default light: it goes with it.
        let kept = if dropped.is_empty() { self.info.ambient } else { glam::Vec3::ZERO };
        self.ambient = kept + env.mean_radiance;
        Ok(())
    }

    /// The specialization constants every integrator's pipeline needs for this scene's BVH:
    /// the triangle list's size and its walls.
    pub fn trace_spec_constants(&self) -> Vec<(u32, u32)> {
        [&self.bvh.spec_constants()[..], &[(SPEC_LIST_WALLS, self.list_walls)]].concat()
    }

    /// The scene's shading arrays by binding number (texel buffers, like the BVH's).
    pub fn shading_bindings(&self) -> [(u32, &TexelArray<'a>); 10] {
        [
            (BINDING_SHADING, &self.shading),
            (BINDING_MATERIALS, &self.materials),
            (BINDING_LIGHTS, &self.lights),
            (BINDING_EMITTERS, &self.emitters),
            (BINDING_TEXTURES, &self.textures),
            (BINDING_TEXELS, &self.texels),
            (BINDING_UVS, &self.uvs),
            (BINDING_ENV_TEXELS, &self.env_texels),
            (BINDING_ENV_CDF, &self.env_cdf),
            (BINDING_TANGENTS, &self.tangents),
        ]
    }

    /// Binds everything of the scene an integrator shader reads: the BVH and the shading
    /// arrays (not the light picks: only the path tracer reads them, [`Self::bind_path_arrays`]).
    pub fn bind(&self, pipeline: &ComputePipeline) -> Result<()> {
        self.bvh.bind(pipeline)?;
        for (binding, array) in self.shading_bindings() {
            pipeline.bind_texels(binding, &array.view).with_context(|| format!("binding {binding}"))?;
        }
        Ok(())
    }

    /// Binds what only the path tracer reads: the light-selection table (BINDING_LIGHT_PICKS)
    /// the planar mirrors (BINDING_MIRRORS, BINDING_MIRROR_PLANES) and the caustic casters
    /// (BINDING_CASTERS).
    pub fn bind_path_arrays(&self, pipeline: &ComputePipeline) -> Result<()> {
        pipeline.bind_texels(BINDING_LIGHT_PICKS, &self.light_picks.view)?;
        pipeline.bind_texels(BINDING_MIRRORS, &self.mirrors.view)?;
        pipeline.bind_texels(BINDING_MIRROR_PLANES, &self.mirror_planes.view)?;
        pipeline.bind_texels(BINDING_CASTERS, &self.casters.view)
    }
}
