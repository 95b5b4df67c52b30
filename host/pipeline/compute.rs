//! A compute pipeline with its descriptor sets of buffers and a push-constant block. It has
//! [`IN_FLIGHT`] copies of its set, so double-buffered work binds each submission's buffers to
//! a set of its own (`bind_in`, `record_dispatch_in`); `bind` points all of them at a buffer.
//! Where the context uses shader objects (gpu::shader_objects) its shader is one, made from the
//! binary a run before kept in the shader cache when there is one (super::shader_cache), else
//! from the SPIR-V; elsewhere it is a compute pipeline. Both run the same code.

use super::shader_cache::{self, ShaderKey};
use crate::gpu::shader_objects::ShaderObjects;
use crate::gpu::{Buffer, Context, TexelView, IN_FLIGHT};
use crate::gpu_abi::constants::{SPEC_CORRECT_DIVISION, SPEC_WORKGROUP_1D, SPEC_WORKGROUP_X, SPEC_WORKGROUP_Y};
use anyhow::{anyhow, Context as _, Result};
use ash::vk;

/// What a binding holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BindingKind {
    Storage,
    Uniform,
    /// A uniform texel buffer (`utextureBuffer`), bound with [`ComputePipeline::bind_texels`].
    Texels,
}

impl BindingKind {
    fn vk(self) -> vk::DescriptorType {
        match self {
            BindingKind::Storage => vk::DescriptorType::STORAGE_BUFFER,
            BindingKind::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
            BindingKind::Texels => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
        }
    }
}

/// Where a [`ComputePipeline`]'s compiled shader came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ShaderOrigin {
    /// A compute pipeline, compiled from the SPIR-V.
    Pipeline,
    /// A shader object compiled from the SPIR-V; `kept`: its binary was written to the shader
    /// cache, or why not (None: no cache).
    SpirvShaderObject { kept: Option<Result<(), String>> },
    /// A shader object made from the binary in the shader cache.
    CachedShaderObject,
}

impl std::fmt::Display for ShaderOrigin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ShaderOrigin::Pipeline => write!(f, "compute pipeline"),
            ShaderOrigin::SpirvShaderObject { kept: None } => write!(f, "shader object from SPIR-V, no shader cache"),
            ShaderOrigin::SpirvShaderObject { kept: Some(Ok(())) } => write!(f, "shader object from SPIR-V, kept in the shader cache"),
            ShaderOrigin::SpirvShaderObject { kept: Some(Err(why)) } => write!(f, "shader object from SPIR-V, not kept: {why}"),
            ShaderOrigin::CachedShaderObject => write!(f, "shader object from the shader cache"),
        }
    }
}

/// What a shader object is made with besides its code: the pipeline layout's parts (which
/// bind its descriptor sets and push constants) and the specialization.
struct Interface<'a> {
    set_layouts: &'a [vk::DescriptorSetLayout],
    ranges: &'a [vk::PushConstantRange],
    push_size: u32,
    spec: &'a vk::SpecializationInfo<'a>,
    constants: &'a [(u32, u32)],
    bindings: &'a [(u32, BindingKind)],
}

/// Shader `name` as a shader object: from the binary the shader cache keeps for it (a binary
/// the driver refuses, VK_ERROR_INCOMPATIBLE_SHADER_BINARY_EXT for another driver version or a
/// damaged file, is passed over), else from its SPIR-V (`spv`, as words `code`), keeping its
/// binary for the next run.
///
/// # Safety
/// The set layouts must be alive; the caller destroys the shader.
unsafe fn shader_object(
    ctx: &Context,
    so: &ShaderObjects,
    name: &str,
    spv: &[u8],
    code: &[u32],
    interface: &Interface,
) -> Result<(vk::ShaderEXT, ShaderOrigin)> {
    let make = |code_type: vk::ShaderCodeTypeEXT, bytes: &[u8]| {
        let mut info = vk::ShaderCreateInfoEXT::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .code_type(code_type)
            .code(bytes)
            .name(c"main")
            .set_layouts(interface.set_layouts);
        if interface.push_size > 0 {
            info = info.push_constant_ranges(interface.ranges);
        }
        if !interface.constants.is_empty() {
            info = info.specialization_info(interface.spec);
        }
        so.fns.create_shaders(&[info], None).map(|s| s[0]).map_err(|(_, e)| e)
    };
    let info = &ctx.info;
    let device = format!("{} | {} {} {} | {}", info.name, info.driver_name, info.driver_info, info.driver_version, info.subgroup_size);
    let kinds: Vec<(u32, u32)> = interface.bindings.iter().map(|&(b, kind)| (b, kind.vk().as_raw() as u32)).collect();
    let file = ctx.shader_cache.as_ref().map(|dir| {
        let key = ShaderKey {
            binary_uuid: so.binary_uuid,
            binary_version: so.binary_version,
            device: &device,
            spirv: spv,
            constants: interface.constants,
            bindings: &kinds,
            push_size: interface.push_size,
        };
        key.file_in(dir)
    });
    if let Some(shader) = file.as_deref().and_then(shader_cache::load).and_then(|b| make(vk::ShaderCodeTypeEXT::BINARY, &b).ok()) {
        return Ok((shader, ShaderOrigin::CachedShaderObject));
    }
    let shader = make(vk::ShaderCodeTypeEXT::SPIRV, bytemuck::cast_slice(code)).map_err(|e| anyhow!("vkCreateShadersEXT '{name}': {e}"))?;
    let kept = file.map(|file| {
        let binary = so.fns.get_shader_binary_data(shader).map_err(|e| format!("vkGetShaderBinaryDataEXT: {e}"))?;
        shader_cache::store(&file, &binary)
    });
    Ok((shader, ShaderOrigin::SpirvShaderObject { kept }))
}

/// A compute pipeline (or shader object) and its descriptor sets; all freed on drop.
pub struct ComputePipeline<'a> {
    ctx: &'a Context,
    name: String,
    module: vk::ShaderModule,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    shader: vk::ShaderEXT,
    origin: ShaderOrigin,
    pool: vk::DescriptorPool,
    sets: Vec<vk::DescriptorSet>,
    bindings: Vec<(u32, BindingKind)>,
    push_size: u32,
    /// Seconds `specialized` took: on lavapipe the SPIR-V-to-NIR work it redoes every run
    /// (its disk cache keeps the compiled code, not that work) unless the shader comes from
    /// the shader cache, a fixed cost of each render.
    creation_seconds: f64,
}

impl<'a> ComputePipeline<'a> {
    /// Builds the pipeline for `spv` (entry point `main`) with the given bindings (set 0) and
    /// `push_size` bytes of push constants.
    pub fn new(ctx: &'a Context, name: &str, spv: &[u8], bindings: &[(u32, BindingKind)], push_size: u32) -> Result<Self> {
        Self::specialized(ctx, name, spv, bindings, push_size, &[])
    }

    /// As [`Self::new`], with 32-bit specialization constants `(constant_id, value)` (a GLSL
    /// `bool` constant takes 0 or 1); constants not listed keep the shader's defaults. Every
    /// pipeline also gets the device's workgroup shape (`ctx.workgroups`, SPEC_WORKGROUP_*) and
    /// whether its division needs correcting (SPEC_CORRECT_DIVISION), unless listed here.
    pub fn specialized(ctx: &'a Context, name: &str, spv: &[u8], bindings: &[(u32, BindingKind)], push_size: u32, constants: &[(u32, u32)]) -> Result<Self> {
        let start = std::time::Instant::now();
        let dev = &ctx.device;
        let code = crate::pipeline::shaders::words(spv).with_context(|| format!("shader '{name}'"))?;
        let wg = ctx.workgroups;
        let device =
            [(SPEC_WORKGROUP_X, wg.x), (SPEC_WORKGROUP_Y, wg.y), (SPEC_WORKGROUP_1D, wg.d1), (SPEC_CORRECT_DIVISION, !ctx.info.divides_exactly as u32)];
        // The caller's value wins where it names a device constant (a test forcing one).
        let given = |id: u32| constants.iter().any(|&(c, _)| c == id);
        let constants: Vec<(u32, u32)> = constants.iter().copied().chain(device.into_iter().filter(|&(id, _)| !given(id))).collect();
        let constants = constants.as_slice();
        let mut p = Self {
            ctx,
            name: name.to_string(),
            module: vk::ShaderModule::null(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            shader: vk::ShaderEXT::null(),
            origin: ShaderOrigin::Pipeline,
            pool: vk::DescriptorPool::null(),
            sets: Vec::new(),
            bindings: bindings.to_vec(),
            push_size,
            creation_seconds: 0.0,
        };
        // SAFETY: each object is stored in `p` as soon as it exists, so Drop frees whatever was
        // made if a later step fails.
        unsafe {
            let layout_bindings: Vec<vk::DescriptorSetLayoutBinding> = bindings
                .iter()
                .map(|&(b, kind)| {
                    vk::DescriptorSetLayoutBinding::default()
                        .binding(b)
                        .descriptor_type(kind.vk())
                        .descriptor_count(1)
                        .stage_flags(vk::ShaderStageFlags::COMPUTE)
                })
                .collect();
            p.set_layout = dev
                .create_descriptor_set_layout(&vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings), None)
                .with_context(|| format!("vkCreateDescriptorSetLayout '{name}'"))?;
            let ranges = [vk::PushConstantRange::default().stage_flags(vk::ShaderStageFlags::COMPUTE).offset(0).size(push_size)];
            let set_layouts = [p.set_layout];
            let mut layout_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
            if push_size > 0 {
                layout_info = layout_info.push_constant_ranges(&ranges);
            }
            p.layout = dev.create_pipeline_layout(&layout_info, None).with_context(|| format!("vkCreatePipelineLayout '{name}'"))?;
            let entries: Vec<vk::SpecializationMapEntry> =
                constants.iter().enumerate().map(|(i, &(id, _))| vk::SpecializationMapEntry { constant_id: id, offset: 4 * i as u32, size: 4 }).collect();
            let data: Vec<u8> = constants.iter().flat_map(|&(_, v)| v.to_ne_bytes()).collect();
            let spec = vk::SpecializationInfo::default().map_entries(&entries).data(&data);
            if let Some(so) = &ctx.shader_objects {
                let interface = Interface { set_layouts: &set_layouts, ranges: &ranges, push_size, spec: &spec, constants, bindings };
                (p.shader, p.origin) = shader_object(ctx, so, name, spv, &code, &interface)?;
            } else {
                p.module = dev
                    .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&code), None)
                    .with_context(|| format!("vkCreateShaderModule '{name}'"))?;
                let mut stage = vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::COMPUTE).module(p.module).name(c"main");
                if !constants.is_empty() {
                    stage = stage.specialization_info(&spec);
                }
                let info = [vk::ComputePipelineCreateInfo::default().stage(stage).layout(p.layout)];
                p.pipeline = dev
                    .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
                    .map_err(|(_, e)| anyhow!("vkCreateComputePipelines '{name}': {e}"))?[0];
            }
            let mut sizes = Vec::new();
            for kind in [BindingKind::Storage, BindingKind::Uniform, BindingKind::Texels] {
                let count = bindings.iter().filter(|b| b.1 == kind).count() as u32;
                if count > 0 {
                    sizes.push(vk::DescriptorPoolSize { ty: kind.vk(), descriptor_count: count * IN_FLIGHT as u32 });
                }
            }
            p.pool = dev
                .create_descriptor_pool(&vk::DescriptorPoolCreateInfo::default().max_sets(IN_FLIGHT as u32).pool_sizes(&sizes), None)
                .with_context(|| format!("vkCreateDescriptorPool '{name}'"))?;
            let layouts = [p.set_layout; IN_FLIGHT];
            p.sets = dev
                .allocate_descriptor_sets(&vk::DescriptorSetAllocateInfo::default().descriptor_pool(p.pool).set_layouts(&layouts))
                .with_context(|| format!("vkAllocateDescriptorSets '{name}'"))?;
        }
        p.creation_seconds = start.elapsed().as_secs_f64();
        Ok(p)
    }

    /// How long creating this pipeline took, in seconds.
    pub fn creation_seconds(&self) -> f64 {
        self.creation_seconds
    }

    /// Where its compiled shader came from.
    pub fn origin(&self) -> &ShaderOrigin {
        &self.origin
    }

    /// What binding `binding` holds.
    fn kind(&self, binding: u32) -> Result<BindingKind> {
        self.bindings.iter().find(|b| b.0 == binding).map(|b| b.1).ok_or_else(|| anyhow!("pipeline '{}' has no binding {binding}", self.name))
    }

    /// Points binding `binding` of every set at `buffer` (whole buffer), after the
    /// submissions in flight (a set must not change while one uses it).
    pub fn bind(&self, binding: u32, buffer: &Buffer) -> Result<()> {
        for set in 0..self.sets.len() {
            self.bind_in(set, binding, buffer)?;
        }
        Ok(())
    }

    /// Points binding `binding` of set `set` (below [`IN_FLIGHT`]) at `buffer`, after the
    /// submissions in flight.
    pub fn bind_in(&self, set: usize, binding: u32, buffer: &Buffer) -> Result<()> {
        let kind = self.kind(binding)?;
        if kind == BindingKind::Texels {
            return Err(anyhow!("pipeline '{}': binding {binding} is a texel buffer; bind a view with bind_texels", self.name));
        }
        let dst = *self.sets.get(set).ok_or_else(|| anyhow!("pipeline '{}' has no descriptor set {set}", self.name))?;
        self.ctx.drain()?;
        let info = [vk::DescriptorBufferInfo { buffer: buffer.buffer, offset: 0, range: vk::WHOLE_SIZE }];
        let write = [vk::WriteDescriptorSet::default().dst_set(dst).dst_binding(binding).descriptor_type(kind.vk()).buffer_info(&info)];
        // SAFETY: no submission using the set is in flight (drained above).
        unsafe { self.ctx.device.update_descriptor_sets(&write, &[]) };
        Ok(())
    }

    /// Points texel-buffer binding `binding` at `view`. Same rule as [`ComputePipeline::bind`].
    pub fn bind_texels(&self, binding: u32, view: &TexelView) -> Result<()> {
        if self.kind(binding)? != BindingKind::Texels {
            return Err(anyhow!("pipeline '{}': binding {binding} is not a texel buffer", self.name));
        }
        self.ctx.drain()?;
        let views = [view.view];
        for &set in &self.sets {
            let write = [vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(binding)
                .descriptor_type(vk::DescriptorType::UNIFORM_TEXEL_BUFFER)
                .texel_buffer_view(&views)];
            // SAFETY: no submission using the sets is in flight (drained above); the view
            // outlives its use.
            unsafe { self.ctx.device.update_descriptor_sets(&write, &[]) };
        }
        Ok(())
    }

    /// Records: bind pipeline and set 0, push `push`, dispatch `groups`.
    pub fn record_dispatch(&self, cmd: vk::CommandBuffer, push: &[u8], groups: [u32; 3]) {
        self.record_dispatch_in(cmd, 0, push, groups)
    }

    /// As [`Self::record_dispatch`] with descriptor set `set` (below [`IN_FLIGHT`]).
    pub fn record_dispatch_in(&self, cmd: vk::CommandBuffer, set: usize, push: &[u8], groups: [u32; 3]) {
        let dev = &self.ctx.device;
        // SAFETY: `cmd` is recording; push size matches the layout (checked by debug assert
        // and by the validation layers in tests).
        debug_assert_eq!(push.len() as u32, self.push_size);
        unsafe {
            match &self.ctx.shader_objects {
                Some(so) if self.shader != vk::ShaderEXT::null() => so.fns.cmd_bind_shaders(cmd, &[vk::ShaderStageFlags::COMPUTE], &[self.shader]),
                _ => dev.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline),
            }
            dev.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.layout, 0, &[self.sets[set % self.sets.len()]], &[]);
            if !push.is_empty() {
                dev.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::COMPUTE, 0, push);
            }
            dev.cmd_dispatch(cmd, groups[0], groups[1], groups[2]);
        }
    }
}

impl Drop for ComputePipeline<'_> {
    fn drop(&mut self) {
        let dev = &self.ctx.device;
        // SAFETY: no submission using these objects is pending after the drain; null handles
        // are ignored by the destroy calls.
        let _ = self.ctx.drain();
        unsafe {
            dev.destroy_descriptor_pool(self.pool, None);
            dev.destroy_pipeline(self.pipeline, None);
            if let Some(so) = &self.ctx.shader_objects {
                so.fns.destroy_shader(self.shader, None);
            }
            dev.destroy_pipeline_layout(self.layout, None);
            dev.destroy_descriptor_set_layout(self.set_layout, None);
            dev.destroy_shader_module(self.module, None);
        }
    }
}
