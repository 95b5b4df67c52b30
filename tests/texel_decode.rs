//! The integrators read the scene's arrays as texel buffers and decode each struct field by
//! field (shaders/include/bvh_bindings.glsl, scene_bindings.glsl, path_bindings.glsl). This runs
//! every decoder on the GPU over arrays of arbitrary values, uploaded the way `GpuScene::upload`
//! and the path tracer upload them, and checks that each struct comes back as uploaded, padding
//! as 0: a field read from the wrong texel or component fails here, even one that no image test
//! looks at (a spot light's radius, a texture's height).

mod common;

use ash::vk;
use std::fmt::Debug;
use vkrt::accel::LayoutKind;
use vkrt::gpu::commands::submit_and_wait;
use vkrt::gpu::{Buffer, Context, MemoryLocation, TexelArray, TexelFormat};
use vkrt::gpu_abi::constants::*;
use vkrt::gpu_abi::*;
use vkrt::pipeline::{BindingKind, ComputePipeline};

/// `n` values of `T` from random words, each word a normal float in ±[0.5, 1) with 23 random
/// bits (so float fields round-trip exactly and no two words are likely equal), with the padding
/// that `zero_pads` clears zeroed: what the shader should read back.
fn values<T: bytemuck::Pod>(rng: &mut common::Pcg, n: usize, zero_pads: fn(&mut T)) -> Vec<T> {
    let words: Vec<u32> = (0..n * std::mem::size_of::<T>() / 4).map(|_| (rng.next_u32() & 0x807F_FFFF) | 0x3F00_0000).collect();
    let mut v: Vec<T> = bytemuck::pod_collect_to_vec(&words);
    v.iter_mut().for_each(zero_pads);
    v
}

/// One array: its input binding, texel format and data, and where the probe writes it back.
struct Case<'a> {
    name: &'static str,
    binding: u32,
    count: u32,
    array: TexelArray<'a>,
    out_binding: u32,
    out: Buffer<'a>,
    check: Box<dyn Fn(&Buffer) + 'a>,
}

fn case<'a, T: bytemuck::Pod + PartialEq + Debug>(
    ctx: &'a Context,
    name: &'static str,
    binding: u32,
    out_binding: u32,
    format: TexelFormat,
    data: Vec<T>,
) -> Case<'a> {
    let array = TexelArray::with_data(ctx, name, &data, format).unwrap();
    let bytes = std::mem::size_of_val(data.as_slice()) as u64;
    let out = Buffer::new(ctx, name, bytes, vk::BufferUsageFlags::STORAGE_BUFFER, MemoryLocation::Device).unwrap();
    let n = data.len();
    let check = Box::new(move |out: &Buffer| {
        let got: Vec<T> = out.read_as(n).unwrap();
        for (i, (g, want)) in got.iter().zip(&data).enumerate() {
            assert_eq!(g, want, "{name}[{i}]: decoded (left) vs uploaded (right)");
        }
    });
    Case { name, binding, count: n as u32, array, out_binding, out, check }
}

/// Runs `probe` over every array, with `nodes` as the node array (its layout's node type), and
/// checks every struct that comes back.
fn check_probe<'a>(ctx: &'a Context, probe: &[u8], nodes: impl FnOnce(&mut common::Pcg) -> Case<'a>) {
    let mut rng = common::Pcg::new(7);
    let rgba = TexelFormat::Rgba32Uint;
    let o = BINDING_DECODE_OUT;
    // Odd counts, none a multiple of the workgroup size.
    let cases = vec![
        nodes(&mut rng),
        case(ctx, "triangles", BINDING_TRIANGLES, o + 1, rgba, values(&mut rng, 41, |t: &mut GpuTriangle| t._pad1 = 0)),
        case(
            ctx,
            "shading",
            BINDING_SHADING,
            o + 2,
            rgba,
            values(&mut rng, 43, |s: &mut GpuShading| {
                s._pad0 = 0;
                s._pad1 = 0;
            }),
        ),
        case(
            ctx,
            "materials",
            BINDING_MATERIALS,
            o + 3,
            rgba,
            values(&mut rng, 29, |m: &mut GpuMaterial| {
                m._pad0 = 0;
                m._pad1 = 0;
                m._pad2 = 0;
            }),
        ),
        case(ctx, "lights", BINDING_LIGHTS, o + 4, rgba, values(&mut rng, 13, |_: &mut GpuLight| {})),
        case(
            ctx,
            "emitters",
            BINDING_EMITTERS,
            o + 5,
            rgba,
            values(&mut rng, 31, |e: &mut GpuEmitter| {
                e._pad1 = 0;
            }),
        ),
        case(ctx, "textures", BINDING_TEXTURES, o + 6, rgba, values(&mut rng, 11, |t: &mut GpuTexture| t._pad0 = 0)),
        case(ctx, "texels", BINDING_TEXELS, o + 7, TexelFormat::R32Uint, values(&mut rng, 101, |_: &mut u32| ())),
        case(
            ctx,
            "uvs",
            BINDING_UVS,
            o + 8,
            rgba,
            values(&mut rng, 47, |u: &mut GpuUv| {
                u._pad0 = 0;
                u._pad1 = 0;
            }),
        ),
        case(ctx, "light picks", BINDING_LIGHT_PICKS, o + 9, rgba, values(&mut rng, 53, |_: &mut GpuLightPick| ())),
        case(ctx, "tangents", BINDING_TANGENTS, BINDING_DECODE_OUT_TANGENTS, rgba, values(&mut rng, 19, |_: &mut GpuTangents| ())),
    ];
    let mut bindings: Vec<(u32, BindingKind)> = cases.iter().map(|c| (c.binding, BindingKind::Texels)).collect();
    bindings.extend(cases.iter().map(|c| (c.out_binding, BindingKind::Storage)));
    let pipeline = ComputePipeline::new(ctx, "texel decode probe", probe, &bindings, 0).unwrap();
    for c in &cases {
        pipeline.bind_texels(c.binding, &c.array.view).unwrap();
        pipeline.bind(c.out_binding, &c.out).unwrap();
    }
    let most = cases.iter().map(|c| c.count).max().unwrap_or(0);
    let groups = [most.div_ceil(ctx.workgroups.d1), 1, 1];
    submit_and_wait(ctx, "texel decode probe", |cmd| pipeline.record_dispatch(cmd, &[], groups)).unwrap();
    for c in &cases {
        eprintln!("checking {}", c.name);
        (c.check)(&c.out);
    }
    common::assert_no_validation_messages(ctx);
}

/// Every decoder, with the node decoder of each BVH layout (the probe built for that layout).
#[test]
fn every_texel_decoder_reads_back_what_the_host_uploaded() {
    let ctx = common::gpu_context();
    for layout in LayoutKind::ALL {
        eprintln!("layout {}", layout.name());
        let probe = common::probe_spirv(&format!("texel_decode_probe_{}", layout.info().id));
        let rgba = TexelFormat::Rgba32Uint;
        let out = BINDING_DECODE_OUT;
        check_probe(&ctx, &probe, |rng| match layout {
            LayoutKind::Threaded | LayoutKind::MultiOrder => case(&ctx, "nodes", BINDING_NODES, out, rgba, values(rng, 37, |_: &mut GpuNode| ())),
            LayoutKind::ParentLink => case(&ctx, "parent-link nodes", BINDING_NODES, out, rgba, values(rng, 37, |_: &mut GpuParentNode| ())),
            LayoutKind::Compact => case(&ctx, "compact nodes", BINDING_NODES, out, rgba, values(rng, 37, |_: &mut GpuCompactNode| ())),
            LayoutKind::Wide => {
                let nodes = values(rng, 37, |n: &mut GpuWideNode| {
                    n._pad0 = 0;
                    n._pad1 = 0;
                });
                case(&ctx, "wide nodes", BINDING_NODES, out, rgba, nodes)
            }
        });
    }
}
