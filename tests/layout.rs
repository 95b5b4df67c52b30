//! The GLSL mirror of every GPU struct (shaders/include/gpu_abi.glsl) checked against Rust:
//! member names, offsets, struct sizes and array strides as the compiled SPIR-V says them,
//! and every binding number. Also runs `spirv-val` on every shader variant.
//!
//! The Rust side comes from `gpu_abi::ALL_STRUCTS`, which the macro that defines the structs
//! fills, so no struct can escape the check; the node struct of each BVH layout comes from the
//! layout probe built for that layout (`accel::LAYOUTS`).

mod common;

use std::collections::HashMap;
use std::mem::size_of;
use vkrt::accel::LAYOUTS;
use vkrt::gpu_abi::constants::*;
use vkrt::gpu_abi::*;

struct SpirvStruct {
    members: Vec<(String, u32)>,
    span: u32,
}

/// The layout probe built for the threaded layout: every struct and binding but the other
/// layouts' node structs.
fn probe_module() -> naga::Module {
    parse(&common::probe_spirv("layout_probe_threaded"))
}

fn parse(spv: &[u8]) -> naga::Module {
    naga::front::spv::parse_u8_slice(spv, &naga::front::spv::Options::default()).expect("naga reads the layout probe")
}

/// Checks one struct of `structs` (from the SPIR-V) against its Rust layout.
fn check_struct(structs: &HashMap<String, SpirvStruct>, rust: &StructLayout) {
    let name = rust.name;
    let s = structs.get(name).unwrap_or_else(|| panic!("struct {name} is missing from the SPIR-V"));
    let fields: Vec<(String, u32)> = rust.fields.iter().map(|(n, o)| (n.to_string(), *o as u32)).collect();
    assert_eq!(s.members, fields, "members and offsets of {name}: SPIR-V (left) vs Rust (right)");
    assert_eq!(s.span as usize, rust.size, "size of {name}: SPIR-V {} vs Rust {}", s.span, rust.size);
}

/// Every GPU struct Rust defines, by name.
fn rust_structs() -> HashMap<&'static str, StructLayout> {
    ALL_STRUCTS.iter().flat_map(|group| group.iter()).map(|s| (s.name, *s)).collect()
}

/// Each layout's node struct, from the probe built for that layout (where the node binding
/// holds it), with the node binding's number and the array's stride.
#[test]
fn every_layout_node_matches_its_glsl_mirror() {
    let rust = rust_structs();
    for layout in &LAYOUTS {
        let module = parse(&common::probe_spirv(&format!("layout_probe_{}", layout.id)));
        let name = layout.node_struct;
        let node = rust.get(name).unwrap_or_else(|| panic!("layout {}: no GPU struct {name} in gpu_abi", layout.name));
        check_struct(&spirv_structs(&module), node);
        let nodes = module.global_variables.iter().find(|(_, v)| module.types[v.ty].name.as_deref() == Some("Nodes")).map(|(_, v)| v).expect("the Nodes block");
        assert_eq!(nodes.binding.as_ref().map(|b| b.binding), Some(BINDING_NODES));
        let naga::TypeInner::Struct { members, .. } = &module.types[nodes.ty].inner else { panic!("Nodes is not a block") };
        let naga::TypeInner::Array { base, stride, .. } = &module.types[members[0].ty].inner else { panic!("Nodes holds no array") };
        assert_eq!(module.types[*base].name.as_deref(), Some(name), "layout {}: the node binding's struct", layout.name);
        assert_eq!(*stride as usize, node.size, "layout {}: node stride", layout.name);
    }
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

/// Every struct of `gpu_abi` but the other layouts' nodes, from one probe.
#[test]
fn every_gpu_struct_matches_its_glsl_mirror() {
    let structs = spirv_structs(&probe_module());
    let mut other_nodes: Vec<&str> = LAYOUTS.iter().map(|l| l.node_struct).filter(|&n| n != LAYOUTS[0].node_struct).collect();
    other_nodes.dedup();
    let rust = rust_structs();
    let mut checked = 0;
    for s in rust.values() {
        // A node struct other than the threaded layout's is only in its own layout's probe.
        if !other_nodes.contains(&s.name) {
            check_struct(&structs, s);
            checked += 1;
        }
    }
    assert_eq!(checked + other_nodes.len(), rust.len());
    assert!(rust.contains_key("GpuPathParams") && rust.contains_key("GpuTriangle"), "ALL_STRUCTS misses a file's structs");
}

/// Binding number -> (block name in GLSL, element struct for arrays, Rust element size).
#[test]
fn bindings_and_array_strides_match() {
    let module = probe_module();
    let expected: Vec<(u32, &str, usize)> = vec![
        (BINDING_NODES, "Nodes", size_of::<GpuNode>()),
        (BINDING_TRIANGLES, "Triangles", size_of::<GpuTriangle>()),
        (BINDING_TRIANGLE_LIST, "TriangleList", size_of::<GpuTriangle>()),
        (BINDING_INSTANCES, "Instances", size_of::<GpuInstance>()),
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
        (BINDING_SUM_EVEN_R, "SumEvenR", 8),
        (BINDING_SUM_EVEN_G, "SumEvenG", 8),
        (BINDING_SUM_EVEN_B, "SumEvenB", 8),
        (BINDING_SUM_ODD_R, "SumOddR", 8),
        (BINDING_SUM_ODD_G, "SumOddG", 8),
        (BINDING_SUM_ODD_B, "SumOddB", 8),
        (BINDING_SAMPLE_COUNTS, "SampleCounts", 8),
        (BINDING_BLOCK_SAMPLES, "BlockSamples", 8),
        (BINDING_RAY_COUNTS, "RayCounts", 4),
        (BINDING_MIRROR_PROBE, "MirrorProbe", 4),
        (BINDING_MIRRORS, "Mirrors", size_of::<GpuMirror>()),
        (BINDING_MIRROR_PLANES, "MirrorPlanes", size_of::<GpuMirrorPlane>()),
        (BINDING_CASTERS, "Casters", size_of::<GpuCaster>()),
        (BINDING_TEXTURES, "Textures", size_of::<GpuTexture>()),
        (BINDING_TEXELS, "Texels", 4),
        (BINDING_UVS, "Uvs", size_of::<GpuUv>()),
        (BINDING_TANGENTS, "Tangents", size_of::<GpuTangents>()),
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
fn every_shader_variant_passes_spirv_val() {
    let dir = std::env::temp_dir().join(format!("vkrt-spirv-val-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    assert!(!vkrt::pipeline::shaders::ALL.is_empty());
    let mut files = Vec::new();
    for (name, spv) in vkrt::pipeline::shaders::ALL {
        let path = dir.join(format!("{name}.spv"));
        std::fs::write(&path, spv).unwrap();
        files.push((name.to_string(), path));
    }
    // The test probes too (built, never embedded).
    let probes = std::path::Path::new(env!("OUT_DIR")).join("probes");
    for entry in std::fs::read_dir(&probes).expect("the probes folder") {
        let path = entry.unwrap().path();
        files.push((path.display().to_string(), path));
    }
    assert!(files.len() > vkrt::pipeline::shaders::ALL.len(), "no probes in {}", probes.display());
    for (name, path) in files {
        let out = std::process::Command::new("spirv-val")
            .args(["--target-env", "vulkan1.2"])
            .arg(&path)
            .output()
            .expect("spirv-val runs (install spirv-tools: tools/ensure-deps.sh)");
        assert!(out.status.success(), "spirv-val rejects {name}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The triangle list's uniform block (declared in bvh_bindings.glsl, which the probe includes):
/// MAX_LIST_TRIANGLES GpuTriangles, what `prepare::GpuBvh` uploads. (Its binding and its
/// std140 stride are checked with the other bindings above.)
#[test]
fn the_triangle_list_block_holds_what_is_uploaded() {
    let module = probe_module();
    let var =
        module.global_variables.iter().map(|(_, v)| v).find(|v| module.types[v.ty].name.as_deref() == Some("TriangleList")).expect("the TriangleList block");
    let naga::TypeInner::Struct { members, .. } = &module.types[var.ty].inner else { panic!("TriangleList is not a block") };
    let naga::TypeInner::Array { base, size, .. } = &module.types[members[0].ty].inner else { panic!("TriangleList holds no array") };
    assert_eq!(module.types[*base].name.as_deref(), Some("GpuTriangle"));
    let naga::ArraySize::Constant(n) = size else { panic!("TriangleList's array has no fixed size") };
    assert_eq!(n.get(), MAX_LIST_TRIANGLES);
}
