//! Everything that crosses to the GPU: every struct the shaders read or write, and every shared
//! number (binding indices, workgroup sizes, encodings: [`constants`]).
//!
//! Each struct is `#[repr(C)]`, bytemuck `Pod`, built from 4-byte scalars and 16-byte vectors,
//! with explicit `_pad` fields and a size assert. `shaders/include/gpu_abi.glsl` mirrors them
//! with the same names and field order; the [`gpu_structs!`] macro that defines them also
//! records each one's field offsets ([`StructLayout`]), and `tests/layout.rs` checks every one
//! of [`ALL_STRUCTS`] against the compiled SPIR-V. Nobody keeps the two in sync by hand, and a
//! struct cannot be added here without being checked.
//!
//! Only this module and the layers above the GPU (accel, pipeline, prepare, query, integrator)
//! use these formats: `geom`, `scene` and `bvh` know nothing of them.

/// A struct's layout as Rust lays it out: its name (the same in GLSL), size, and each field's
/// name and byte offset in declaration order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StructLayout {
    pub name: &'static str,
    pub size: usize,
    pub fields: &'static [(&'static str, usize)],
}

/// Defines GPU structs: each gets `#[repr(C)]`, `Debug, Clone, Copy, PartialEq, Pod,
/// Zeroable`, and a `LAYOUT` constant ([`StructLayout`]); the invocation also defines
/// `STRUCTS`, the layouts of all of them, which [`ALL_STRUCTS`] collects.
macro_rules! gpu_structs {
    ($( $(#[$meta:meta])* pub struct $name:ident { $( $(#[$fmeta:meta])* pub $field:ident : $ty:ty ),* $(,)? } )*) => {
        $(
            $(#[$meta])*
            #[repr(C)]
            #[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
            pub struct $name { $( $(#[$fmeta])* pub $field: $ty ),* }

            impl $name {
                /// This struct's layout, for the mirror check.
                pub const LAYOUT: $crate::gpu_abi::StructLayout = $crate::gpu_abi::StructLayout {
                    name: stringify!($name),
                    size: std::mem::size_of::<$name>(),
                    fields: &[$((stringify!($field), std::mem::offset_of!($name, $field))),*],
                };
            }
        )*
        /// The layouts of the structs defined in this file.
        pub(super) const STRUCTS: &[$crate::gpu_abi::StructLayout] = &[$($name::LAYOUT),*];
    };
}

// After the macro: `macro_rules!` is visible only below its definition.
pub mod constants;
mod dispatch;
mod nodes;
mod scene_data;

pub use dispatch::*;
pub use nodes::*;
pub use scene_data::*;

/// Rec. 709 luminance of linear RGB ([`constants::REC709_LUMINANCE`]) in f32, the products
/// summed in the order of the shaders' `dot(c, REC709_LUMINANCE)`: the host's half of the
/// environment map's distribution, and automatic exposure.
pub fn luminance(c: [f32; 3]) -> f32 {
    let [r, g, b] = constants::REC709_LUMINANCE;
    r * c[0] + g * c[1] + b * c[2]
}

/// Every GPU struct's layout: what `tests/layout.rs` checks against the SPIR-V.
pub const ALL_STRUCTS: &[&[StructLayout]] = &[nodes::STRUCTS, scene_data::STRUCTS, dispatch::STRUCTS];

/// Vulkan guarantees 128 bytes of push constants on every device.
const _: () = assert!(std::mem::size_of::<GpuPush>() <= 128);
