//! Stackless BVH layouts: a built [`crate::bvh::Bvh`] laid out as the flat arrays a shader walks
//! without a stack, each with a CPU twin that walks the same arrays with the same arithmetic.
//!
//! One file per layout ([`kinds::LAYOUTS`] lists them): its flatten step, its [`NodeArray`]
//! (the nodes ready to upload, and the CPU twin of its shader's `traverse`), and the name of its
//! GLSL walk (`shaders/include/traverse_<id>.glsl`). [`intersect`] and [`leaf`] are the parts
//! every walk shares. The node structs themselves are GPU formats and live in `crate::gpu_abi`.

pub mod compact;
pub mod intersect;
pub mod kinds;
pub mod leaf;
pub mod multi_order;
pub mod parent_link;
pub mod threaded;
pub mod triangle_list;
pub mod two_level;
pub mod walls;
pub mod wide;

pub use kinds::{LayoutInfo, LayoutKind, LAYOUTS};

use crate::bvh::{Bvh, MAX_LEAF_SIZE};
use crate::gpu_abi::constants::{LEAF_COUNT_BITS, PRIM_NONE};
use crate::gpu_abi::{GpuHit, GpuInstance, GpuPush, GpuRay, GpuTriangle};
use crate::scene::Triangle;
use anyhow::Context as _;

// Every layout packs a leaf's triangle count into LEAF_COUNT_BITS bits.
const _: () = assert!(MAX_LEAF_SIZE < (1 << LEAF_COUNT_BITS), "a BVH leaf holds more triangles than the flat layouts can count");

/// A layout's node array: what is uploaded, and the CPU twin of the shader that walks it.
pub trait NodeArray: std::fmt::Debug + Send + Sync {
    fn kind(&self) -> LayoutKind;
    /// The node array as uploaded to the GPU (`BINDING_NODES`).
    fn bytes(&self) -> &[u8];
    /// Entries in the node array (for the multi-order layout, all six orders).
    fn count(&self) -> usize;
    /// The CPU twin of this layout's `traverse`: same hit, same counters.
    fn trace(&self, tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit;
    /// Writes what this layout's shader reads from the push constants besides the node count
    /// (the compact layout's grid); most layouts need nothing.
    fn fill_push(&self, _push: &mut GpuPush) {}
    /// The instances a two-level array's top-level leaves name (`two_level`); none for the
    /// one-level layouts.
    fn instances(&self) -> &[GpuInstance] {
        &[]
    }
}

/// Declares a layout's node array as a vector of its node struct, walked by the module's own
/// `trace(nodes, tris, ray, any_hit)`: `node_array!(Threaded, GpuNode, LayoutKind::Threaded,
/// "the threaded node array")`. (The compact layout carries a grid too and writes its own.)
macro_rules! node_array {
    ($name:ident, $node:ty, $kind:expr, $doc:literal) => {
        #[doc = $doc]
        #[derive(Debug, Clone, PartialEq)]
        pub struct $name(pub Vec<$node>);

        impl $crate::accel::NodeArray for $name {
            fn kind(&self) -> $crate::accel::LayoutKind {
                $kind
            }
            fn bytes(&self) -> &[u8] {
                bytemuck::cast_slice(&self.0)
            }
            fn count(&self) -> usize {
                self.0.len()
            }
            fn trace(&self, tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
                trace(&self.0, tris, ray, any_hit)
            }
        }
    };
}
pub(crate) use node_array;

/// The flat arrays of one layout: nodes, and the triangles reordered so that each leaf's
/// triangles are contiguous (shared by every layout), followed by the triangle list
/// ([`triangle_list`]: `triangles[list_first..]`, outside the tree, tested before every walk).
#[derive(Debug)]
pub struct FlatBvh {
    pub nodes: Box<dyn NodeArray>,
    pub triangles: Vec<GpuTriangle>,
    /// Where the triangle list starts in `triangles`; `triangles.len()` without one.
    pub list_first: usize,
}

impl FlatBvh {
    pub fn layout(&self) -> LayoutKind {
        self.nodes.kind()
    }
    pub fn node_count(&self) -> usize {
        self.nodes.count()
    }
    /// Bytes the node and triangle arrays (and a two-level BVH's instances) occupy on the GPU.
    pub fn bytes(&self) -> usize {
        self.nodes.bytes().len() + std::mem::size_of_val(self.triangles.as_slice()) + std::mem::size_of_val(self.nodes.instances())
    }
    /// The triangle list (empty without one).
    pub fn list(&self) -> &[GpuTriangle] {
        &self.triangles[self.list_first..]
    }
    /// The CPU twin of `trace_scene` (shaders/include/traverse.glsl): the triangle list, then
    /// this layout's walk up to the list's hit (an any-hit query walks only if the list missed).
    /// Same hit, same counters.
    pub fn trace(&self, ray: &GpuRay, any_hit: bool) -> GpuHit {
        self.trace_skipping(ray, any_hit, 0)
    }
    /// The same with the list's triangles in `walls` left out: `trace_scene` with `between`
    /// set, for a shadow ray between two points of the scene (`walls::walls`).
    pub fn trace_skipping(&self, ray: &GpuRay, any_hit: bool, walls: u32) -> GpuHit {
        if self.list().is_empty() {
            return self.nodes.trace(&self.triangles, ray, any_hit);
        }
        let listed = triangle_list::trace(self.list(), ray, walls);
        if any_hit && listed.prim != PRIM_NONE {
            return listed;
        }
        let tmax = if listed.prim != PRIM_NONE { listed.t } else { ray.tmax };
        let walked = self.nodes.trace(&self.triangles, &GpuRay { tmax, ..*ray }, any_hit);
        let best = if walked.prim != PRIM_NONE { walked } else { listed };
        GpuHit { nodes_visited: walked.nodes_visited, tris_tested: listed.tris_tested + walked.tris_tested, ..best }
    }
    /// The push constants that describe these arrays (node count, layout data); each dispatch
    /// fills in the rest.
    pub fn push(&self) -> GpuPush {
        let mut push = GpuPush {
            node_count: self.node_count() as u32,
            list_first: self.list_first as u32,
            list_count: self.list().len() as u32,
            ..bytemuck::Zeroable::zeroed()
        };
        self.nodes.fill_push(&mut push);
        push
    }
}

/// The largest triangle count the leaf encoding can address.
pub const MAX_FLAT_TRIANGLES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// Lays `bvh` (built over `tris`) out as `layout`.
pub fn flatten(bvh: &Bvh, tris: &[Triangle], layout: LayoutKind) -> anyhow::Result<FlatBvh> {
    // The triangles in leaf order and the node array do not depend on each other: one core
    // gathers the triangles (on every core that is free) while another lays out the nodes.
    let (triangles, nodes) = rayon::join(
        || leaf_order_triangles(bvh, tris),
        || -> anyhow::Result<Box<dyn NodeArray>> {
            Ok(match layout {
                LayoutKind::Threaded => Box::new(threaded::Threaded(threaded::flatten(bvh))),
                LayoutKind::MultiOrder => Box::new(multi_order::MultiOrder(multi_order::flatten(bvh))),
                LayoutKind::ParentLink => Box::new(parent_link::ParentLink(parent_link::flatten(bvh)?)),
                LayoutKind::Compact => Box::new(compact::Compact::from_threaded(&threaded::flatten(bvh))?),
                LayoutKind::Wide => Box::new(wide::Wide(wide::flatten(bvh)?)),
            })
        },
    );
    let (triangles, nodes) = (triangles?, nodes?);
    debug_assert_eq!(nodes.kind(), layout);
    let list_first = triangles.len();
    Ok(FlatBvh { nodes, triangles, list_first })
}

/// Lays `bvh` out as `layout` with the triangle list after its triangles: `bvh` is built over
/// the triangles not in `listed` (its primitive ids index `tris`), `listed` the list's
/// triangles by index into `tris` ([`triangle_list::choose`]).
pub fn flatten_with_list(bvh: &Bvh, tris: &[Triangle], layout: LayoutKind, listed: &[u32]) -> anyhow::Result<FlatBvh> {
    let mut flat = flatten(bvh, tris, layout)?;
    for &prim in listed {
        let t = tris.get(prim as usize).with_context(|| format!("the triangle list names primitive {prim} of {}", tris.len()))?;
        flat.triangles.push(gpu_triangle(t, prim));
    }
    Ok(flat)
}

/// `t`'s positions as the device takes them, with primitive id `prim`.
pub fn gpu_triangle(t: &Triangle, prim: u32) -> GpuTriangle {
    GpuTriangle { v0: t.p[0].to_array(), prim, v1: t.p[1].to_array(), shading: 0, v2: t.p[2].to_array(), _pad1: 0 }
}

/// The triangles in `prim_indices` order, so a leaf's `first..first + count` indexes them.
fn leaf_order_triangles(bvh: &Bvh, tris: &[Triangle]) -> anyhow::Result<Vec<GpuTriangle>> {
    if tris.len() > MAX_FLAT_TRIANGLES {
        anyhow::bail!("scene has {} triangles; the flat layouts address at most {MAX_FLAT_TRIANGLES}", tris.len());
    }
    use rayon::prelude::*;
    bvh.prim_indices
        .par_iter()
        .map(|&prim| {
            let t = tris.get(prim as usize).with_context(|| format!("BVH names primitive {prim} of {} triangles", tris.len()))?;
            Ok(gpu_triangle(t, prim))
        })
        .collect()
}

impl clap::ValueEnum for LayoutKind {
    fn value_variants<'a>() -> &'a [Self] {
        &LayoutKind::ALL
    }
    fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
        Some(clap::builder::PossibleValue::new(self.name()).help(self.info().help))
    }
}
