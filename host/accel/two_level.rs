//! A two-level BVH over instanced meshes (issue 44): one bottom-level tree per mesh, in object
//! space, and a top-level tree over the instances' world boxes, whose leaves each name one
//! instance ([`GpuInstance`]: world-to-object rows, the mesh tree's root, the copy's first
//! primitive id), in one node array: the top level from index 0, then each mesh's tree. Both
//! levels are laid out in one of [`LAYOUTS`]: threaded arrays (Smits 1998) in the threaded
//! layout's single order, or in the multi-order layout's six near-first orders per tree
//! (`multi_order`), in which a ray takes the top level's order of its world direction and each
//! mesh's order of its object-space direction (a turned copy's dominant axis is another), one
//! multiply-add per level entered; in those a mesh tree's escape links end in NODE_NONE. Or
//! parent-linked sibling pairs (`parent_link`, Hapala et al. 2011), each tree starting at an
//! even index, in which a level's walk ends when it is done with that level's root. Or compact
//! threaded nodes (`compact`), each tree's boxes cells of a grid over its own root box (the top
//! level's in the push constants, a mesh's in its instances, in object space), in which a
//! level's walk ends where its tree does (the top level's node count, an instance's
//! `node_end`). Or wide nodes (`wide`), each tree's root without a parent, in which a level's
//! walk ends when it would go up from that root.
//!
//! The walk stays stackless with O(1) more state than the one-level walk: at a top-level leaf
//! the ray goes into object space (its direction not renormalised, so t, tmin and tmax keep
//! their world meaning and one tmax serves both levels), walks the mesh's tree from its root,
//! and when that tree is done continues in the top level where it would have gone after the
//! leaf (a threaded level: the leaf's escape link, or the next node in a compact one; a
//! parent-link level: the leaf's sibling or parent, and the state it enters it in; a wide
//! level: the leaf's node again, after the leaf's slot, as the wide walk comes back from a
//! child) with the world ray. What it carries besides: that place, whether it is in object
//! space, the level's root (parent-link) or end and grid (compact), the instance's primitive
//! base and mirror flag (Embree's and pbrt's instancing, without their stack). Shaders:
//! `shaders/include/traverse_two_level.glsl` (threaded and multi-order levels, the
//! `_two_level_threaded` build of every tracing shader), `traverse_two_level_parent_link.glsl`
//! (`_two_level_parent_link`), `traverse_two_level_compact.glsl` (`_two_level_compact`) and
//! `traverse_two_level_wide.glsl` (`_two_level_wide`).
//!
//! The scene's own triangles, which are no instance's (`scene::instance::InstanceGroup`), form
//! one more mesh under an identity instance: its object ray is the world ray to the bit (each
//! coordinate is 1 x plus zeros), so those triangles are hit at the same t as in the one-level
//! walk. Primitive ids are those of the expanded scene (`Scene::expanded`), so hits compare
//! with it directly.

use anyhow::Context as _;
use glam::{Mat4, Vec3};

use super::compact::{self, QuantGrid};
use super::intersect::{intersect_box, RayPre};
use super::leaf::{leaf_count, miss, test_leaf};
use super::multi_order::{self, ray_order};
use super::parent_link::{self, near_child, State};
use super::threaded::threaded;
use super::wide;
use super::{FlatBvh, LayoutKind, NodeArray, MAX_FLAT_TRIANGLES};
use crate::bvh::{self, BuildConfig, BuilderKind, Bvh};
use crate::geom::Aabb;
use crate::gpu_abi::constants::{COMPACT_LEAF_FLAG, INSTANCE_MIRRORED, LEAF_COUNT_BITS, NODE_NONE, WIDE_INFO_SLOT_SHIFT, WIDE_NO_SLOT};
use crate::gpu_abi::{GpuCompactNode, GpuHit, GpuInstance, GpuNode, GpuParentNode, GpuPush, GpuRay, GpuTriangle, GpuWideNode};
use crate::scene::instance::{placed_box, Placement};
use crate::scene::Scene;

/// The two-level node array: top-level nodes, then every mesh's tree; and the instances the
/// top-level leaves name.
#[derive(Debug, Clone, PartialEq)]
pub struct TwoLevel {
    pub nodes: LevelNodes,
    /// Nodes of the top-level tree (the first ones of `nodes`).
    pub top_nodes: usize,
    pub instances: Vec<GpuInstance>,
    /// Meshes with a tree of their own (the scene's instanced meshes, and the rest of its
    /// triangles if any).
    pub meshes: usize,
    /// The top-level tree's SAH cost (`bvh::stats`), in its own units: the bottom levels'
    /// boxes are in object space, so no cost adds the two.
    pub top_sah: f32,
    /// The layout both levels are in (one of [`LAYOUTS`]).
    pub layout: LayoutKind,
    /// Nodes per order of the top level in the multi-order layout; 0 in the threaded one
    /// (`GpuPush::top_order_nodes`).
    pub top_order_nodes: u32,
    /// The compact layout's grid of the top level (over its root box); zero in the others.
    pub top_grid: QuantGrid,
}

/// The layouts a two-level BVH's levels can be laid out in: those whose walk can start at any
/// tree's root in the one node array with O(1) state and tell when that tree is done, so that
/// the walk can enter a mesh's tree and come back to the top level: every layout.
/// `LayoutInfo::two_level` names the shader build of each.
pub const LAYOUTS: [LayoutKind; 5] = [LayoutKind::Threaded, LayoutKind::MultiOrder, LayoutKind::ParentLink, LayoutKind::Compact, LayoutKind::Wide];

// The shader builds (kinds.rs, read by host/build.rs) and this list name the same layouts.
const _: () = {
    let mut k = 0;
    while k < LayoutKind::ALL.len() {
        let kind = LayoutKind::ALL[k];
        let mut listed = false;
        let mut i = 0;
        while i < LAYOUTS.len() {
            listed |= LAYOUTS[i] as usize == kind as usize;
            i += 1;
        }
        assert!(listed == super::kinds::LAYOUTS[kind as usize].two_level.is_some(), "two_level::LAYOUTS and LayoutInfo::two_level disagree");
        k += 1;
    }
};

/// A two-level BVH's node array, both levels in one node format.
#[derive(Debug, Clone, PartialEq)]
pub enum LevelNodes {
    /// Threaded or multi-order levels.
    Threaded(Vec<GpuNode>),
    /// Parent-link levels.
    ParentLink(Vec<GpuParentNode>),
    /// Compact levels.
    Compact(Vec<GpuCompactNode>),
    /// Wide levels.
    Wide(Vec<GpuWideNode>),
}

impl LevelNodes {
    pub fn len(&self) -> usize {
        match self {
            LevelNodes::Threaded(n) => n.len(),
            LevelNodes::ParentLink(n) => n.len(),
            LevelNodes::Compact(n) => n.len(),
            LevelNodes::Wide(n) => n.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn bytes(&self) -> &[u8] {
        match self {
            LevelNodes::Threaded(n) => bytemuck::cast_slice(n),
            LevelNodes::ParentLink(n) => bytemuck::cast_slice(n),
            LevelNodes::Compact(n) => bytemuck::cast_slice(n),
            LevelNodes::Wide(n) => bytemuck::cast_slice(n),
        }
    }

    /// `other`'s nodes after these (both in one format, as [`lay_out`] gives them for one layout).
    fn append(&mut self, other: LevelNodes) {
        match (self, other) {
            (LevelNodes::Threaded(a), LevelNodes::Threaded(b)) => a.extend(b),
            (LevelNodes::ParentLink(a), LevelNodes::ParentLink(b)) => a.extend(b),
            (LevelNodes::Compact(a), LevelNodes::Compact(b)) => a.extend(b),
            (LevelNodes::Wide(a), LevelNodes::Wide(b)) => a.extend(b),
            _ => unreachable!("a two-level BVH's levels are in one layout"),
        }
    }

    /// Each leaf's word (`(first << LEAF_COUNT_BITS) | count`, count > 0; the same in every
    /// format, a compact node's under its leaf flag, a wide node's in its leaf slots) relabelled by `f`: a top-level leaf's to
    /// its instance, a mesh leaf's first triangle past the meshes before it. Fails where a
    /// compact leaf's new word would reach its flag bit.
    fn relabel_leaves(&mut self, f: impl Fn(u64) -> u64) -> anyhow::Result<()> {
        let word = |w: u32, limit: u64| {
            let new = f(u64::from(w));
            anyhow::ensure!(
                new < limit,
                "a leaf would start at item {}; the layout addresses at most {}",
                new >> LEAF_COUNT_BITS,
                (limit - 1) >> LEAF_COUNT_BITS
            );
            Ok(new as u32)
        };
        match self {
            LevelNodes::Threaded(n) => {
                for n in n.iter_mut().filter(|n| leaf_count(n.leaf) != 0) {
                    n.leaf = word(n.leaf, 1 << 32)?;
                }
            }
            LevelNodes::ParentLink(n) => {
                for n in n.iter_mut().filter(|n| leaf_count(n.leaf) != 0) {
                    n.leaf = word(n.leaf, 1 << 32)?;
                }
            }
            LevelNodes::Compact(n) => {
                for n in n.iter_mut().filter(|n| n.link & COMPACT_LEAF_FLAG != 0) {
                    n.link = COMPACT_LEAF_FLAG | word(n.link & !COMPACT_LEAF_FLAG, u64::from(COMPACT_LEAF_FLAG))?;
                }
            }
            LevelNodes::Wide(n) => {
                for n in n.iter_mut() {
                    let slots = wide::child_count(n.info) as usize;
                    for c in n.children[..slots].iter_mut().filter(|c| leaf_count(**c) != 0) {
                        *c = word(*c, 1 << 32)?;
                    }
                }
            }
        }
        Ok(())
    }
}

impl NodeArray for TwoLevel {
    fn kind(&self) -> LayoutKind {
        self.layout
    }
    fn bytes(&self) -> &[u8] {
        self.nodes.bytes()
    }
    fn count(&self) -> usize {
        self.nodes.len()
    }
    fn trace(&self, tris: &[GpuTriangle], ray: &GpuRay, any_hit: bool) -> GpuHit {
        match &self.nodes {
            LevelNodes::Threaded(nodes) => trace(nodes, self.top_order_nodes, tris, &self.instances, ray, any_hit),
            LevelNodes::ParentLink(nodes) => trace_parent_link(nodes, tris, &self.instances, ray, any_hit),
            LevelNodes::Compact(nodes) => trace_compact(nodes, self.top_nodes as u32, &self.top_grid, tris, &self.instances, ray, any_hit),
            LevelNodes::Wide(nodes) => trace_wide(nodes, tris, &self.instances, ray, any_hit),
        }
    }
    fn fill_push(&self, push: &mut GpuPush) {
        push.top_order_nodes = self.top_order_nodes;
        if let LevelNodes::Compact(_) = self.nodes {
            push.top_nodes = self.top_nodes as u32;
            push.grid_origin = self.top_grid.origin.to_array();
            push.grid_scale = self.top_grid.scale.to_array();
        }
    }
    fn instances(&self) -> &[GpuInstance] {
        &self.instances
    }
}

/// The most instances a top-level leaf word can name (the instance index in the bits above the
/// leaf count).
pub const MAX_INSTANCES: usize = 1 << (32 - LEAF_COUNT_BITS);

/// One mesh of a two-level BVH: its triangles in object space, their primitive ids relative
/// to an instance's `prim_base` (mesh-local for an instanced mesh, the scene's own for the
/// rest), and its copies (an instance group's: each copy's first primitive id and placement;
/// none for the rest, which is in the world already and gets the identity). Meshes come in
/// [`meshes`]' order, which is the order of their blocks of shading data
/// (`prepare::mesh_shading`).
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub positions: Vec<[Vec3; 3]>,
    pub prims: Vec<u32>,
    pub copies: Vec<(u32, Placement)>,
}

/// The meshes of a scene's two-level BVH: each instance group's, then the scene's own
/// triangles (if any), which are no copy's.
pub fn meshes(scene: &Scene) -> Vec<Mesh> {
    let mut meshes: Vec<Mesh> = Vec::with_capacity(scene.instances.len() + 1);
    for g in &scene.instances {
        meshes.push(Mesh { positions: g.mesh.iter().map(|t| t.p).collect(), prims: (0..g.mesh.len() as u32).collect(), copies: g.copies().collect() });
    }
    if !scene.triangles.is_empty() {
        meshes.push(Mesh { positions: scene.triangles.iter().map(|t| t.p).collect(), prims: (0..scene.triangles.len() as u32).collect(), copies: Vec::new() });
    }
    meshes
}

/// One level's tree as laid out for the node array.
struct Level {
    /// Its nodes (every order's).
    nodes: LevelNodes,
    /// Nodes per order (0 for the layouts with one order).
    per_order: u32,
    /// Its grid in the compact layout (zero in the others).
    grid: QuantGrid,
}

/// A level's tree laid out in `layout` (one of [`LAYOUTS`]) for a node array in which it
/// starts at `base` (even: every tree's array has an even length in the parent-link layout).
fn lay_out(tree: &Bvh, layout: LayoutKind, base: u32) -> anyhow::Result<Level> {
    let one = |nodes| Level { nodes, per_order: 0, grid: QuantGrid::default() };
    Ok(match layout {
        LayoutKind::MultiOrder => {
            Level { nodes: LevelNodes::Threaded(multi_order::orders(tree, base)), per_order: tree.nodes.len() as u32, grid: QuantGrid::default() }
        }
        LayoutKind::ParentLink => one(LevelNodes::ParentLink(parent_link::flatten_at(tree, base)?)),
        LayoutKind::Compact => {
            // The tree alone, then its interior nodes' escapes (its node count past its last
            // node: where the level ends) moved by `base`; leaves escape to the next node.
            let (mut nodes, grid) = compact::from_threaded(&threaded(tree, |_, l, r| (l, r), 0))?;
            anyhow::ensure!(u64::from(base) + nodes.len() as u64 <= u64::from(COMPACT_LEAF_FLAG), "the compact layout addresses fewer than 2^31 nodes");
            nodes.iter_mut().filter(|n| n.link & COMPACT_LEAF_FLAG == 0).for_each(|n| n.link += base);
            Level { nodes: LevelNodes::Compact(nodes), per_order: 0, grid }
        }
        LayoutKind::Wide => one(LevelNodes::Wide(wide::flatten_at(tree, base)?)),
        LayoutKind::Threaded => one(LevelNodes::Threaded(threaded(tree, |_, l, r| (l, r), base))),
    })
}

/// Builds the two-level BVH of `meshes` ([`meshes`]) in `layout` (one of [`LAYOUTS`]):
/// `builder` builds every mesh's tree and the top-level tree (one instance per leaf, so that a
/// leaf names its instance). Returns the node array and the bottom levels' triangles in leaf
/// order, object space.
pub fn build(meshes: &[Mesh], builder: BuilderKind, config: &BuildConfig, layout: LayoutKind) -> anyhow::Result<(TwoLevel, Vec<GpuTriangle>)> {
    anyhow::ensure!(LAYOUTS.contains(&layout), "a two-level BVH is laid out as {}; not as {}", LAYOUTS.map(|l| l.name()).join(" or "), layout.name());
    let triangle_total: usize = meshes.iter().map(|m| m.positions.len()).sum();
    anyhow::ensure!(triangle_total <= MAX_FLAT_TRIANGLES, "the meshes have {triangle_total} triangles; the flat layouts address at most {MAX_FLAT_TRIANGLES}");

    // The bottom levels, each built over its own triangles' boxes.
    use rayon::prelude::*;
    let trees: Vec<Bvh> = meshes
        .par_iter()
        .map(|m| {
            let boxes: Vec<Aabb> = m.positions.iter().map(|p| Aabb::from_points(p)).collect();
            let centroids: Vec<Vec3> = m.positions.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
            bvh::build(builder, &boxes, &centroids, config)
        })
        .collect();

    // The instances: every copy of every mesh, the rest under the identity; for each, its
    // mesh, object-to-world transform, first primitive id and mirror flag.
    let mut placements: Vec<(usize, Mat4, u32, bool)> = Vec::new();
    for (mesh, m) in meshes.iter().enumerate() {
        if m.copies.is_empty() {
            placements.push((mesh, Mat4::IDENTITY, 0, false));
        }
        placements.extend(m.copies.iter().map(|&(first, p)| (mesh, p.world(), first, p.mirrored())));
    }
    anyhow::ensure!(placements.len() <= MAX_INSTANCES, "{} instances; a top-level leaf names at most {MAX_INSTANCES}", placements.len());
    let world_boxes: Vec<Aabb> = placements.iter().map(|(mesh, world, ..)| world_box(world, &trees[*mesh].nodes[0].bounds)).collect();

    // The top level: one instance per leaf.
    let centroids: Vec<Vec3> = world_boxes.iter().map(|b| b.center()).collect();
    let top = bvh::build(builder, &world_boxes, &centroids, &BuildConfig { max_leaf_size: 1, ..*config });
    let Level { mut nodes, per_order: top_order_nodes, grid: top_grid } = lay_out(&top, layout, 0)?;
    nodes
        .relabel_leaves(|leaf| (u64::from(top.prim_indices[(leaf >> LEAF_COUNT_BITS) as usize]) << LEAF_COUNT_BITS) | 1)
        .context("the top level's instances")?;
    let top_nodes = nodes.len();
    let top_sah = bvh::stats::stats(&top).sah_cost;

    // Every mesh's tree after it, its leaves' triangles after the meshes before it.
    let mut roots = Vec::with_capacity(meshes.len());
    let mut order_nodes = Vec::with_capacity(meshes.len());
    let mut grids = Vec::with_capacity(meshes.len());
    let mut ends = Vec::with_capacity(meshes.len());
    let mut shading_bases = Vec::with_capacity(meshes.len());
    let mut triangles = Vec::with_capacity(triangle_total);
    for (m, tree) in meshes.iter().zip(&trees) {
        // The meshes' shading data is in the same order, a block each.
        shading_bases.push(triangles.len() as u32);
        let too_many = || anyhow::anyhow!("the two-level BVH has more than 2^32 nodes");
        let base = u32::try_from(nodes.len()).map_err(|_| too_many())?;
        let Level { nodes: mut tree_nodes, per_order, grid } = lay_out(tree, layout, base)?;
        let end = u32::try_from(nodes.len() + tree_nodes.len()).map_err(|_| too_many())?;
        roots.push(base);
        order_nodes.push(per_order);
        grids.push(grid);
        ends.push(if layout == LayoutKind::Compact { end } else { 0 });
        let tri_base = triangles.len() as u64;
        tree_nodes.relabel_leaves(|leaf| leaf + (tri_base << LEAF_COUNT_BITS)).context("the meshes' triangles")?;
        nodes.append(tree_nodes);
        triangles.extend(tree.prim_indices.iter().map(|&i| {
            let p = m.positions[i as usize];
            GpuTriangle { v0: p[0].to_array(), prim: m.prims[i as usize], v1: p[1].to_array(), shading: i, v2: p[2].to_array(), _pad1: 0 }
        }));
    }
    let instances = placements
        .iter()
        .map(|&(mesh, world, prim_base, mirrored)| {
            let rows = |m: Mat4| [m.row(0).to_array(), m.row(1).to_array(), m.row(2).to_array()];
            GpuInstance {
                world_to_object: rows(world.inverse()),
                object_to_world: rows(world),
                root: roots[mesh],
                prim_base,
                flags: if mirrored { INSTANCE_MIRRORED } else { 0 },
                shading_base: shading_bases[mesh],
                grid_origin: grids[mesh].origin.to_array(),
                order_nodes: order_nodes[mesh],
                grid_scale: grids[mesh].scale.to_array(),
                node_end: ends[mesh],
            }
        })
        .collect();
    Ok((TwoLevel { nodes, top_nodes, instances, meshes: meshes.len(), top_sah, layout, top_order_nodes, top_grid }, triangles))
}

impl TwoLevel {
    /// As a [`FlatBvh`] over `triangles` (the bottom levels', from [`build`]), without a
    /// triangle list.
    pub fn into_flat(self, triangles: Vec<GpuTriangle>) -> FlatBvh {
        let list_first = triangles.len();
        FlatBvh { nodes: Box::new(self), triangles, list_first }
    }
}

/// An object box's world box: its eight corners transformed, padded by a few ulps of its
/// largest coordinate, so that a ray the mesh's tree hits in object space (after the rounding
/// of the ray's transform) is not culled by the top level.
fn world_box(world: &Mat4, b: &Aabb) -> Aabb {
    let out = placed_box(world, b);
    let pad = out.min.abs().max(out.max.abs()).max_element() * 8.0 * f32::EPSILON;
    Aabb { min: out.min - Vec3::splat(pad), max: out.max + Vec3::splat(pad) }
}

/// `row_dot` in instance.glsl (its `transform_point` and `transform_dir`): one row of the
/// world-to-object transform, summed left to right with no fused multiply-add, as the
/// shader's `precise`.
fn row_dot(row: &[f32; 4], v: Vec3, w: f32) -> f32 {
    ((row[0] * v.x + row[1] * v.y) + row[2] * v.z) + row[3] * w
}

/// The ray in an instance's object space: same tmin and tmax, direction not renormalised.
pub fn object_ray(instance: &GpuInstance, ray: &GpuRay) -> GpuRay {
    let (o, d) = (Vec3::from(ray.origin), Vec3::from(ray.direction));
    let m = &instance.world_to_object;
    GpuRay {
        origin: [row_dot(&m[0], o, 1.0), row_dot(&m[1], o, 1.0), row_dot(&m[2], o, 1.0)],
        tmin: ray.tmin,
        direction: [row_dot(&m[0], d, 0.0), row_dot(&m[1], d, 0.0), row_dot(&m[2], d, 0.0)],
        tmax: ray.tmax,
    }
}

/// What a walk carries while in an instance's mesh (`InstanceWalk` in instance_walk.glsl): what
/// its hits need to be the scene's.
#[derive(Debug, Clone, Copy, Default)]
struct InObject {
    prim_base: u32,
    mirrored: bool,
}

impl InObject {
    fn of(instance: &GpuInstance) -> Self {
        Self { prim_base: instance.prim_base, mirrored: instance.flags & INSTANCE_MIRRORED != 0 }
    }

    /// `hit_in_world` in instance_walk.glsl: a hit in the mesh as the scene's: its primitive
    /// id among the placed copies, and its barycentrics in the placed triangle's vertex order
    /// (a mirroring instance swaps the second and third vertices).
    fn hit_in_world(self, hit: &mut GpuHit) {
        hit.prim += self.prim_base;
        if self.mirrored {
            (hit.u, hit.v) = (hit.v, hit.u);
        }
    }
}

/// `traverse` in traverse_two_level.glsl: the closest hit (or with `any_hit` the first found)
/// through both levels, whose top level has `top_order_nodes` nodes per order (0: one order).
pub fn trace(nodes: &[GpuNode], top_order_nodes: u32, tris: &[GpuTriangle], instances: &[GpuInstance], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let world = RayPre::new(ray);
    let mut r = world;
    let mut hit = miss();
    let mut tmax = ray.tmax;
    // The order of the ray's dominant direction, of which a threaded level has only one.
    let order = |r: &RayPre, ray: &GpuRay| ray_order(r, ray) as u32;
    let mut index = if nodes.is_empty() { NODE_NONE } else { top_order_nodes * order(&world, ray) };
    // While in a mesh's tree: where the top level goes on, and what the instance's hits need.
    let mut in_object = false;
    let mut resume = NODE_NONE;
    let mut inside = InObject::default();
    loop {
        let Some(node) = nodes.get(index as usize) else {
            if !in_object {
                break;
            }
            (index, in_object, r) = (resume, false, world);
            continue;
        };
        hit.nodes_visited += 1;
        if intersect_box(&r, Vec3::from(node.bmin), Vec3::from(node.bmax), tmax).is_none() {
            index = node.escape;
            continue;
        }
        if leaf_count(node.leaf) == 0 {
            index += 1;
            continue;
        }
        if !in_object {
            let Some(instance) = instances.get((node.leaf >> LEAF_COUNT_BITS) as usize) else { break };
            let object = object_ray(instance, ray);
            r = RayPre::new(&object);
            (resume, index, in_object) = (node.escape, instance.root + instance.order_nodes * order(&r, &object), true);
            inside = InObject::of(instance);
            continue;
        }
        if test_leaf(node.leaf, tris, &r, &mut tmax, &mut hit, any_hit) {
            inside.hit_in_world(&mut hit);
            if any_hit {
                return hit;
            }
        }
        index = node.escape;
    }
    hit
}

/// `traverse` in traverse_two_level_parent_link.glsl: [`trace`] with parent-link levels, each
/// walked by the state machine of `parent_link::trace` (Hapala et al. 2011) from its root (the
/// top level's at 0, a mesh's at its instance's root) until the walk is done with that root. A
/// mesh's tree orders children by the object-space direction, as it splits object space.
pub fn trace_parent_link(nodes: &[GpuParentNode], tris: &[GpuTriangle], instances: &[GpuInstance], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let world = RayPre::new(ray);
    let world_dir = Vec3::from(ray.direction);
    let (mut r, mut dir) = (world, world_dir);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    let (mut root, mut current, mut state) = (0u32, 0u32, State::FromParent);
    // While in a mesh's tree: where the top level goes on after its leaf (None: nowhere, the
    // leaf was the top level's root), and what the instance's hits need.
    let mut in_object = false;
    let mut resume = None;
    let mut inside = InObject::default();
    while let Some(node) = nodes.get(current as usize) {
        if state != State::FromChild {
            hit.nodes_visited += 1;
            let entered = intersect_box(&r, node.bmin.into(), node.bmax.into(), tmax).is_some();
            if entered && leaf_count(node.leaf) == 0 {
                (current, state) = (near_child(node.leaf >> LEAF_COUNT_BITS, (node.parent >> 2) & 3, dir), State::FromParent);
                continue;
            }
            if entered && !in_object {
                let Some(instance) = instances.get((node.leaf >> LEAF_COUNT_BITS) as usize) else { break };
                resume = next_in_level(node, current, root, dir);
                let object = object_ray(instance, ray);
                (r, dir) = (RayPre::new(&object), Vec3::from(object.direction));
                (root, current, state, in_object) = (instance.root, instance.root, State::FromParent, true);
                inside = InObject::of(instance);
                continue;
            }
            if entered && test_leaf(node.leaf, tris, &r, &mut tmax, &mut hit, any_hit) {
                inside.hit_in_world(&mut hit);
                if any_hit {
                    return hit;
                }
            }
        }
        // Done with this node (or back at it from a child): on to the next of its level, or
        // out of a mesh's tree to where the top level goes on.
        match next_in_level(node, current, root, dir) {
            Some(next) => (current, state) = next,
            None => {
                let Some(next) = resume.take().filter(|_| in_object) else { break };
                (current, state) = next;
                (in_object, root, r, dir) = (false, 0, world, world_dir);
            }
        }
    }
    hit
}

/// `traverse` in traverse_two_level_compact.glsl: [`trace`] with compact levels, the top
/// level's `top_nodes` nodes from 0 on `top_grid`, each mesh's from its instance's root to its
/// `node_end` on the instance's grid: the compact walk (`compact::trace`) of each, the top
/// level going on at the node after the leaf it left.
pub fn trace_compact(
    nodes: &[GpuCompactNode],
    top_nodes: u32,
    top_grid: &QuantGrid,
    tris: &[GpuTriangle],
    instances: &[GpuInstance],
    ray: &GpuRay,
    any_hit: bool,
) -> GpuHit {
    let world = RayPre::new(ray);
    let mut r = world;
    let mut hit = miss();
    let mut tmax = ray.tmax;
    // A level's end, never past the array (as the shader bounds it by its node count).
    let count = u32::try_from(nodes.len()).unwrap_or(u32::MAX);
    let (mut index, mut end, mut grid) = (0u32, top_nodes.min(count), *top_grid);
    // While in a mesh's tree: where the top level goes on, and what the instance's hits need.
    let mut in_object = false;
    let mut resume = 0u32;
    let mut inside = InObject::default();
    loop {
        if index >= end {
            if !in_object {
                break;
            }
            (index, end, grid, r, in_object) = (resume, top_nodes.min(count), *top_grid, world, false);
            continue;
        }
        let Some(node) = nodes.get(index as usize) else { break };
        hit.nodes_visited += 1;
        let leaf = node.link & COMPACT_LEAF_FLAG != 0;
        if !compact::enters(node, &grid, &r, tmax) {
            index = if leaf { index + 1 } else { node.link };
            continue;
        }
        if !leaf {
            index += 1;
            continue;
        }
        let word = node.link & !COMPACT_LEAF_FLAG;
        if !in_object {
            let Some(instance) = instances.get((word >> LEAF_COUNT_BITS) as usize) else { break };
            r = RayPre::new(&object_ray(instance, ray));
            (resume, index, end, in_object) = (index + 1, instance.root, instance.node_end.min(count), true);
            grid = QuantGrid { origin: instance.grid_origin.into(), scale: instance.grid_scale.into() };
            inside = InObject::of(instance);
            continue;
        }
        if test_leaf(word, tris, &r, &mut tmax, &mut hit, any_hit) {
            inside.hit_in_world(&mut hit);
            if any_hit {
                return hit;
            }
        }
        index += 1;
    }
    hit
}

/// `traverse` in traverse_two_level_wide.glsl: [`trace`] with wide levels, each walked by the
/// wide walk (`wide::trace`) from its root (the top level's at 0, a mesh's at its instance's
/// root) until it would go up from it (a root has no parent). At a top-level leaf slot the
/// walk keeps that node and slot, and after the mesh's tree comes back to the node restricted
/// to the slots after it, as the wide walk comes back from a child. A mesh's nodes order their
/// slots by the object-space direction.
pub fn trace_wide(nodes: &[GpuWideNode], tris: &[GpuTriangle], instances: &[GpuInstance], ray: &GpuRay, any_hit: bool) -> GpuHit {
    let world = RayPre::new(ray);
    let world_dir = Vec3::from(ray.direction);
    let (mut r, mut dir) = (world, world_dir);
    let mut hit = miss();
    let mut tmax = ray.tmax;
    let (mut index, mut from) = (0u32, WIDE_NO_SLOT);
    // While in a mesh's tree: the top-level node and slot to come back to, and what the
    // instance's hits need.
    let mut in_object = false;
    let (mut resume, mut resume_from) = (0u32, WIDE_NO_SLOT);
    let mut inside = InObject::default();
    while let Some(node) = nodes.get(index as usize) {
        hit.nodes_visited += 1;
        let reverse = wide::reversed(node.info, dir);
        let (hits, t_enter) = wide::box_mask(&r, node, tmax);
        let mut mask = hits & wide::slots_after(from, reverse);
        let mut next = NODE_NONE;
        while let Some((slot, child)) = wide::next_slot(&mut mask, reverse, &t_enter, tmax, node) {
            if leaf_count(child) == 0 {
                next = child >> LEAF_COUNT_BITS;
                break;
            }
            if !in_object {
                let Some(instance) = instances.get((child >> LEAF_COUNT_BITS) as usize) else { return hit };
                (resume, resume_from) = (index, slot);
                let object = object_ray(instance, ray);
                (r, dir) = (RayPre::new(&object), Vec3::from(object.direction));
                (next, in_object) = (instance.root, true);
                inside = InObject::of(instance);
                break;
            }
            if test_leaf(child, tris, &r, &mut tmax, &mut hit, any_hit) {
                inside.hit_in_world(&mut hit);
                if any_hit {
                    return hit;
                }
            }
        }
        if next != NODE_NONE {
            (index, from) = (next, WIDE_NO_SLOT);
            continue;
        }
        if node.parent != NODE_NONE {
            (index, from) = (node.parent, (node.info >> WIDE_INFO_SLOT_SHIFT) & 3);
            continue;
        }
        // Up from a root: the walk is done, or the mesh's tree is and the top level goes on.
        if !in_object {
            break;
        }
        (index, from, in_object, r, dir) = (resume, resume_from, false, world, world_dir);
    }
    hit
}

/// In a parent-link level rooted at `root`, the node after `current`, which the walk is done
/// with (`node`: its entry), and the state it enters that node in: the far sibling if `current`
/// is the near child, else the parent (to go on up); None at the root, where the level is done.
/// (From the parent the walk enters the near child, from the sibling the far one, so whether
/// a node is the near child says which way it came.)
fn next_in_level(node: &GpuParentNode, current: u32, root: u32, dir: Vec3) -> Option<(u32, State)> {
    if current == root {
        None
    } else if current == near_child(current & !1, node.parent & 3, dir) {
        Some((current ^ 1, State::FromSibling))
    } else {
        Some((node.parent >> 4, State::FromChild))
    }
}

/// What `vkrt bvh` reports of each level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelCounts {
    pub instances: usize,
    pub meshes: usize,
    pub top_nodes: usize,
    pub top_sah: f32,
    pub bottom_nodes: usize,
    /// Triangles the meshes hold (each once), against the expanded scene's.
    pub bottom_triangles: usize,
}

impl TwoLevel {
    /// Its counts, with `triangles` the bottom levels' triangle count.
    pub fn counts(&self, triangles: usize) -> LevelCounts {
        LevelCounts {
            instances: self.instances.len(),
            meshes: self.meshes,
            top_nodes: self.top_nodes,
            top_sah: self.top_sah,
            bottom_nodes: self.nodes.len() - self.top_nodes,
            bottom_triangles: triangles,
        }
    }
}
