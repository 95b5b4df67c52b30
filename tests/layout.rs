//! The GLSL mirror of every GPU struct (shaders/include/layout.glsl) checked against Rust:
//! member names, offsets, struct sizes and array strides as the compiled SPIR-V says them,
//! and every binding number. Also runs `spirv-val` on every shader variant.

use std::collections::HashMap;
use std::mem::{offset_of, size_of};
use vkrt::layout::constants::*;
use vkrt::layout::*;

/// (member name, offset) of each field, in declaration order, from the Rust definition.
macro_rules! rust_fields {
    ($ty:ty { $($field:ident),* $(,)? }) => {
        (stringify!($ty), size_of::<$ty>(), vec![$((stringify!($field), offset_of!($ty, $field))),*])
    };
}

struct SpirvStruct {
    members: Vec<(String, u32)>,
    span: u32,
}

fn probe_module() -> naga::Module {
    parse(vkrt::pipeline::shaders::LAYOUT_PROBE)
}

fn parse(spv: &[u8]) -> naga::Module {
    naga::front::spv::parse_u8_slice(spv, &naga::front::spv::Options::default()).expect("naga reads the layout probe")
}

/// A layout's node struct, from the probe compiled for that layout (the node binding holds it
/// there), with the node binding's number and the struct's stride.
fn check_node_mirror(spv: &[u8], name: &str, size: usize, fields: &[(&str, usize)]) {
    let module = parse(spv);
    let structs = spirv_structs(&module);
    let s = structs.get(name).unwrap_or_else(|| panic!("struct {name} is missing from the SPIR-V"));
    let rust: Vec<(String, u32)> = fields.iter().map(|(n, o)| (n.to_string(), *o as u32)).collect();
    assert_eq!(s.members, rust, "members and offsets of {name}: SPIR-V (left) vs Rust (right)");
    assert_eq!(s.span as usize, size, "size of {name}");
    let nodes = module
        .global_variables
        .iter()
        .find(|(_, v)| module.types[v.ty].name.as_deref() == Some("Nodes"))
        .map(|(_, v)| v)
        .expect("the Nodes block");
    assert_eq!(nodes.binding.as_ref().map(|b| b.binding), Some(BINDING_NODES));
    let naga::TypeInner::Struct { members, .. } = &module.types[nodes.ty].inner else { panic!("Nodes is not a block") };
    let naga::TypeInner::Array { base, stride, .. } = &module.types[members[0].ty].inner else { panic!("Nodes holds no array") };
    assert_eq!(module.types[*base].name.as_deref(), Some(name));
    assert_eq!(*stride as usize, size);
}

#[test]
fn parent_link_node_matches_its_glsl_mirror() {
    let (name, size, fields) = rust_fields!(GpuParentNode { bmin, parent, bmax, leaf });
    check_node_mirror(vkrt::pipeline::shaders::LAYOUT_PROBE_PARENT_LINK, name, size, &fields);
}

#[test]
fn compact_node_matches_its_glsl_mirror() {
    let (name, size, fields) = rust_fields!(GpuCompactNode { min_xy, min_z_max_x, max_yz, link });
    check_node_mirror(vkrt::pipeline::shaders::LAYOUT_PROBE_COMPACT, name, size, &fields);
}

#[test]
fn wide_node_matches_its_glsl_mirror() {
    let (name, size, fields) =
        rust_fields!(GpuWideNode { min_x, min_y, min_z, max_x, max_y, max_z, children, parent, info, _pad0, _pad1 });
    check_node_mirror(vkrt::pipeline::shaders::LAYOUT_PROBE_WIDE, name, size, &fields);
}

fn spirv_structs(module: &naga::Module) -> HashMap<String, SpirvStruct> {
    let mut out = HashMap::new();
    for (_, ty) in module.types.iter() {
        if let (Some(name), naga::TypeInner::Struct { members, span }) = (&ty.name, &ty.inner) {
            let members = members.iter().map(|m| (m.name.clone().unwrap_or_default(), m.offset)).collect();
            out.insert(name.clone(), SpirvStruct { members, span: *span });
        }
    }
    out
}

#[test]
fn every_gpu_struct_matches_its_glsl_mirror() {
    let module = probe_module();
    let structs = spirv_structs(&module);
    let expected = vec![
        rust_fields!(GpuNode { bmin, escape, bmax, leaf }),
        rust_fields!(GpuTriangle { v0, prim, v1, _pad0, v2, _pad1 }),
        rust_fields!(GpuShading { n0, material, n1, _pad0, n2, _pad1 }),
        rust_fields!(GpuMaterial {
            diffuse, flags, specular, shininess, emission, ior, diffuse_texture, alpha_texture, _pad0, _pad1
        }),
        rust_fields!(GpuTexture { offset, width, height, _pad0 }),
        rust_fields!(GpuUv { uv0, uv1, uv2, _pad0, _pad1 }),
        rust_fields!(GpuLight { position, kind, direction, radius, intensity, _pad0 }),
        rust_fields!(GpuEmitter { v0, prim, v1, area, v2, _pad0, radiance, _pad1 }),
        rust_fields!(GpuFrame {
            cam_origin, tan_half_fov_y, cam_forward, aspect, cam_right, width, cam_up, height,
            ambient, max_depth, light_count, emitter_count, seed, scene_scale, sky_color, sky_texture
        }),
        rust_fields!(GpuPush {
            tile_x, tile_y, sample_base, sample_count, total_spp, ray_count, any_hit, node_count,
            grid_origin, _pad0, grid_scale, _pad1
        }),
        rust_fields!(GpuRay { origin, tmin, direction, tmax }),
        rust_fields!(GpuHit { t, prim, u, v, nodes_visited, tris_tested, _pad0, _pad1 }),
        rust_fields!(GpuLightPick { pmf, alias, threshold, _pad0 }),
        rust_fields!(GpuPathParams { max_depth, rr_depth, sampler_kind, sample_rate, pick_count, nee, inv_total_weight, coherence, adaptive, _pad0, _pad1, _pad2 }),
    ];
    for (name, size, fields) in expected {
        let s = structs.get(name).unwrap_or_else(|| panic!("struct {name} is missing from the SPIR-V"));
        let spirv: Vec<(String, u32)> = s.members.clone();
        let rust: Vec<(String, u32)> = fields.iter().map(|(n, o)| (n.to_string(), *o as u32)).collect();
        assert_eq!(spirv, rust, "members and offsets of {name}: SPIR-V (left) vs Rust (right)");
        assert_eq!(s.span as usize, size, "size of {name}: SPIR-V {} vs Rust {size}", s.span);
    }
}

/// Binding number -> (block name in GLSL, element struct for arrays, Rust element size).
#[test]
fn bindings_and_array_strides_match() {
    let module = probe_module();
    let expected: Vec<(u32, &str, usize)> = vec![
        (BINDING_NODES, "Nodes", size_of::<GpuNode>()),
        (BINDING_TRIANGLES, "Triangles", size_of::<GpuTriangle>()),
        (BINDING_SHADING, "Shading", size_of::<GpuShading>()),
        (BINDING_MATERIALS, "Materials", size_of::<GpuMaterial>()),
        (BINDING_LIGHTS, "Lights", size_of::<GpuLight>()),
        (BINDING_EMITTERS, "Emitters", size_of::<GpuEmitter>()),
        (BINDING_FRAME, "Frame", size_of::<GpuFrame>()),
        (BINDING_ACCUM, "Accum", 16),
        (BINDING_RAYS, "Rays", size_of::<GpuRay>()),
        (BINDING_HITS, "Hits", size_of::<GpuHit>()),
        (BINDING_LIGHT_PICKS, "LightPicks", size_of::<GpuLightPick>()),
        (BINDING_PATH_PARAMS, "PathParams", size_of::<GpuPathParams>()),
        (BINDING_ACCUM_EVEN, "AccumEven", 16),
        (BINDING_BLOCK_SAMPLES, "BlockSamples", 8),
        (BINDING_TEXTURES, "Textures", size_of::<GpuTexture>()),
        (BINDING_TEXELS, "Texels", 4),
        (BINDING_UVS, "Uvs", size_of::<GpuUv>()),
    ];
    let mut found = HashMap::new();
    for (_, var) in module.global_variables.iter() {
        let (Some(binding), Some(name)) = (&var.binding, &module.types[var.ty].name) else { continue };
        assert_eq!(binding.group, 0, "{name} is not in descriptor set 0");
        // The block's only member is the array (or, for Frame, the struct).
        let naga::TypeInner::Struct { members, .. } = &module.types[var.ty].inner else { panic!("{name} is not a block") };
        let element_size = match &module.types[members[0].ty].inner {
            naga::TypeInner::Array { stride, .. } => *stride as usize,
            naga::TypeInner::Struct { span, .. } => *span as usize,
            other => panic!("{name}: unexpected member type {other:?}"),
        };
        found.insert(name.clone(), (binding.binding, element_size));
    }
    for (binding, block, size) in expected {
        let (b, s) = found.get(block).copied().unwrap_or_else(|| panic!("block {block} missing from the probe"));
        assert_eq!(b, binding, "binding of {block}");
        assert_eq!(s, size, "array stride / size of {block}");
    }
    // Every binding number is distinct.
    let mut numbers: Vec<u32> = found.values().map(|v| v.0).collect();
    numbers.sort();
    numbers.dedup();
    assert_eq!(numbers.len(), found.len(), "two blocks share a binding number");
}

#[test]
fn push_constants_fit_the_guaranteed_minimum() {
    // Vulkan guarantees 128 bytes of push constants on every device.
    assert!(size_of::<GpuPush>() <= 128);
}

#[test]
fn every_shader_variant_passes_spirv_val() {
    let dir = std::env::temp_dir().join(format!("vkrt-spirv-val-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    assert!(!vkrt::pipeline::shaders::ALL.is_empty());
    for (name, spv) in vkrt::pipeline::shaders::ALL {
        let path = dir.join(format!("{name}.spv"));
        std::fs::write(&path, spv).unwrap();
        let out = std::process::Command::new("spirv-val")
            .args(["--target-env", "vulkan1.2"])
            .arg(&path)
            .output()
            .expect("spirv-val runs (install spirv-tools: tools/ensure-deps.sh)");
        assert!(out.status.success(), "spirv-val rejects {name}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
