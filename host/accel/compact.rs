//! The compact threaded BVH: the threaded layout (`threaded`, Smits 1998) with each
//! node in 16 bytes instead of 32, so one texel fetch reads a node and a cache line holds four.
//!
//! Why: half the node memory (for devices where traversal is bandwidth-bound, and scenes near a
//! binding's size limit), and one texel fetch per node instead of two: on lavapipe each fetch
//! is a call into a JIT-compiled function, ~7 % of a path trace per extra fetch per node step.
//! The price: boxes are rounded outwards to a 16-bit grid over the scene, so small boxes grow
//! by up to one grid cell per side (on the shared scenes rays visit within 0.1 node of the
//! threaded layout), and decoding a box costs ~30 instructions. Measured on lavapipe the decode
//! outweighs the saved fetch: 10-20 % slower than threaded (docs/experiments/per-step-cost.md).
//!
//! Encoding (`GpuCompactNode`): the box corners as 16-bit cell indices of a per-scene grid,
//! `corner = origin + q * scale` (the grid goes to the shader in the push constants), and one
//! link word. A leaf's escape is always the next node (in pre-order nothing lies below a
//! leaf), so the word holds either an interior node's escape (top bit clear) or a leaf's
//! `(first triangle << LEAF_COUNT_BITS) | count` with the top bit set. An escape past the last
//! node is the node count itself, which ends the walk.
//!
//! Exactness: decoding is two float roundings (a product, then a sum, never fused), done the
//! same way here and in the shader, and the encoder moves each cell index until the decoded
//! corner lies outside the true box in float arithmetic, so every decoded box contains its
//! node's box and traversal still finds the closest hit. Shader: traverse_compact.glsl.

use super::intersect::{intersect_box, RayPre};
use super::leaf::{leaf_count, miss, test_leaf};
use super::{LayoutKind, NodeArray};
use crate::gpu_abi::constants::{COMPACT_CELL_BITS, COMPACT_LEAF_FLAG as LEAF_FLAG, LEAF_COUNT_BITS, NODE_NONE};
use crate::gpu_abi::{GpuCompactNode, GpuHit, GpuNode, GpuPush, GpuRay, GpuTriangle};
use glam::Vec3;

/// The largest cell index.
const CELLS: u32 = (1 << COMPACT_CELL_BITS) - 1;

/// The grid the corners are quantised to: cell `q` on an axis decodes to `origin + q * scale`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct QuantGrid {
    pub origin: Vec3,
    pub scale: Vec3,
}

impl QuantGrid {
    /// A grid over `min..max` (the root box) whose last cell decodes at or past `max`.
    pub fn over(min: Vec3, max: Vec3) -> Self {
        let mut scale = (max - min) / CELLS as f32;
        for a in 0..3 {
            // Rounding may leave the last cell just short of max: widen the cells until it is not.
            while min[a] + CELLS as f32 * scale[a] < max[a] {
                scale[a] = f32::from_bits(scale[a].to_bits() + 1);
            }
        }
        Self { origin: min, scale }
    }

    /// `decode_cells` in traverse_compact.glsl: the corner coordinate of cell `q` on `axis`.
    pub fn decode(&self, q: u32, axis: usize) -> f32 {
        self.origin[axis] + q as f32 * self.scale[axis]
    }

    /// The largest cell that decodes at or below `v` (0 if none does: the grid starts at the
    /// root's minimum, so that only happens for v outside the root box).
    fn cell_below(&self, v: f32, axis: usize) -> u32 {
        if self.scale[axis] == 0.0 {
            // A flat axis: every cell decodes to the one coordinate.
            return 0;
        }
        let mut q = self.estimate(v, axis).floor().clamp(0.0, CELLS as f32) as u32;
        while q > 0 && self.decode(q, axis) > v {
            q -= 1;
        }
        while q < CELLS && self.decode(q + 1, axis) <= v {
            q += 1;
        }
        q
    }

    /// The smallest cell that decodes at or above `v`.
    fn cell_above(&self, v: f32, axis: usize) -> u32 {
        if self.scale[axis] == 0.0 {
            return 0;
        }
        let mut q = self.estimate(v, axis).ceil().clamp(0.0, CELLS as f32) as u32;
        while q < CELLS && self.decode(q, axis) < v {
            q += 1;
        }
        while q > 0 && self.decode(q - 1, axis) >= v {
            q -= 1;
        }
        q
    }

    fn estimate(&self, v: f32, axis: usize) -> f32 {
        (v - self.origin[axis]) / self.scale[axis]
    }
}

impl GpuCompactNode {
    /// The 16-bit cell indices of the box: min x, y, z, max x, y, z.
    pub fn cells(&self) -> [u32; 6] {
        [
            self.min_xy & CELLS,
            self.min_xy >> COMPACT_CELL_BITS,
            self.min_z_max_x & CELLS,
            self.min_z_max_x >> COMPACT_CELL_BITS,
            self.max_yz & CELLS,
            self.max_yz >> COMPACT_CELL_BITS,
        ]
    }

    /// The decoded (outward-rounded) box.
    pub fn bounds(&self, grid: &QuantGrid) -> (Vec3, Vec3) {
        let q = self.cells();
        let min = Vec3::new(grid.decode(q[0], 0), grid.decode(q[1], 1), grid.decode(q[2], 2));
        let max = Vec3::new(grid.decode(q[3], 0), grid.decode(q[4], 1), grid.decode(q[5], 2));
        (min, max)
    }
}

/// The compact node array and the grid its boxes are quantised to.
#[derive(Debug, Clone, PartialEq)]
pub struct Compact {
    pub nodes: Vec<GpuCompactNode>,
    pub grid: QuantGrid,
}

impl Compact {
    /// The compact form of a threaded node array (`threaded::flatten`).
    pub fn from_threaded(nodes: &[GpuNode]) -> anyhow::Result<Self> {
        let (nodes, grid) = from_threaded(nodes)?;
        Ok(Self { nodes, grid })
    }
}

impl NodeArray for Compact {
    fn kind(&self) -> LayoutKind {
        LayoutKind::Compact
    }
    fn bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.nodes)
    }
    fn count(&self) -> usize {
        self.nodes.len()
    }
    fn trace(&self, tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
        trace(&self.nodes, &self.grid, tris, ray, any_hit)
    }
    /// The grid goes to the shader in the push constants.
    fn fill_push(&self, push: &mut GpuPush) {
        push.grid_origin = self.grid.origin.to_array();
        push.grid_scale = self.grid.scale.to_array();
    }
}

/// The compact form of a threaded node array (`threaded::flatten`, base 0), and its grid.
pub fn from_threaded(nodes: &[GpuNode]) -> anyhow::Result<(Vec<GpuCompactNode>, QuantGrid)> {
    let Some(root) = nodes.first() else { return Ok((Vec::new(), QuantGrid::default())) };
    if nodes.len() >= LEAF_FLAG as usize {
        anyhow::bail!("{} BVH nodes; the compact layout addresses fewer than 2^31", nodes.len());
    }
    let grid = QuantGrid::over(Vec3::from(root.bmin), Vec3::from(root.bmax));
    let count = nodes.len() as u32;
    let max_leaf = (LEAF_FLAG - 1) >> LEAF_COUNT_BITS;
    let compact = nodes
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let link = if leaf_count(n.leaf) > 0 {
                if n.leaf >> LEAF_COUNT_BITS > max_leaf {
                    anyhow::bail!("a leaf starts at triangle {}; the compact layout addresses at most {max_leaf}", n.leaf >> LEAF_COUNT_BITS);
                }
                debug_assert!(n.escape == NODE_NONE || n.escape == i as u32 + 1, "a leaf escapes to the next node in pre-order");
                LEAF_FLAG | n.leaf
            } else if n.escape == NODE_NONE {
                count
            } else {
                n.escape
            };
            let lo = [0, 1, 2].map(|a| grid.cell_below(n.bmin[a], a));
            let hi = [0, 1, 2].map(|a| grid.cell_above(n.bmax[a], a));
            let pack = |low: u32, high: u32| low | high << COMPACT_CELL_BITS;
            Ok(GpuCompactNode { min_xy: pack(lo[0], lo[1]), min_z_max_x: pack(lo[2], hi[0]), max_yz: pack(hi[1], hi[2]), link })
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok((compact, grid))
}

/// `compact_box_hit` in traverse_compact.glsl: whether the ray enters the node's box as decoded
/// on `grid`, within [tmin, tmax].
pub fn enters(node: &GpuCompactNode, grid: &QuantGrid, r: &RayPre, tmax: f32) -> bool {
    let (bmin, bmax) = node.bounds(grid);
    intersect_box(r, bmin, bmax, tmax).is_some()
}

/// CPU twin of `traverse` in traverse_compact.glsl: the threaded walk over decoded boxes.
pub fn trace(nodes: &[GpuCompactNode], grid: &QuantGrid, tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let r = RayPre::new(ray);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    let mut index = 0u32;
    while let Some(node) = nodes.get(index as usize) {
        hit.nodes_visited += 1;
        let leaf = node.link & LEAF_FLAG != 0;
        if !enters(node, grid, &r, tmax) {
            index = if leaf { index + 1 } else { node.link };
            continue;
        }
        if !leaf {
            index += 1;
            continue;
        }
        if test_leaf(node.link & !LEAF_FLAG, tris, &r, &mut tmax, &mut hit, any_hit) && any_hit {
            return hit;
        }
        index += 1;
    }
    hit
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decoded_corners_enclose_the_true_ones() {
        let grid = QuantGrid::over(Vec3::new(-3.7, 1e-3, 1000.0), Vec3::new(12.25, 0.5, 1000.0));
        let mut x = 0x2545F491u32;
        for _ in 0..20000 {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            let f = (x >> 8) as f32 / (1 << 24) as f32;
            let v = Vec3::new(-3.7 + f * 15.95, 1e-3 + f * 0.499, 1000.0);
            for a in 0..3 {
                let lo = grid.cell_below(v[a], a);
                let hi = grid.cell_above(v[a], a);
                assert!(grid.decode(lo, a) <= v[a] && grid.decode(hi, a) >= v[a], "axis {a}: {} not in [{}, {}]", v[a], grid.decode(lo, a), grid.decode(hi, a));
                if grid.scale[a] > 0.0 {
                    // Tight: the neighbouring cells would not enclose it.
                    assert!(lo == CELLS || grid.decode(lo + 1, a) > v[a]);
                    assert!(hi == 0 || grid.decode(hi - 1, a) < v[a]);
                }
            }
        }
        // The root's own corners are cells 0 and CELLS.
        assert_eq!(grid.cell_below(-3.7, 0), 0);
        assert_eq!(grid.cell_above(12.25, 0), CELLS);
    }
}
