//! Bounding volume hierarchies, built on the CPU.
//!
//! A builder sees only boxes and centroids (never triangles, never a GPU format) and returns a
//! [`Bvh`]: a node tree plus the order in which leaves reference primitives. [`validate`]
//! checks the invariants; [`sah`] scores a tree; `crate::accel` lays it out for the GPU.

pub mod build;
pub mod sah;
pub mod stats;
pub mod validate;

use crate::geom::Aabb;

/// A node of a binary BVH.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    pub bounds: Aabb,
    pub kind: NodeKind,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodeKind {
    /// Children are indices into [`Bvh::nodes`].
    Interior { left: u32, right: u32 },
    /// `count` primitives: `Bvh::prim_indices[first .. first + count]`.
    Leaf { first: u32, count: u32 },
}

/// A binary BVH. `nodes[0]` is the root (absent for an empty scene).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bvh {
    pub nodes: Vec<Node>,
    /// Primitive ids in leaf order: leaves reference contiguous ranges of this.
    pub prim_indices: Vec<u32>,
}

/// The most primitives a leaf may hold: builders split (by index, if centroids coincide)
/// rather than exceed it. 255 keeps a leaf's count in one byte; the flat layouts rely on that
/// (`crate::accel` checks at compile time that its leaf encoding holds this count).
pub const MAX_LEAF_SIZE: u32 = 255;

/// Which builder to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, clap::ValueEnum)]
pub enum BuilderKind {
    /// Split at the median centroid along the widest centroid axis: fast, lower quality.
    Median,
    /// Binned surface area heuristic: slower, better trees.
    Sah,
    /// Full-sweep SAH: every split between sorted centroids; best top-down object splits.
    SweepSah,
    /// Binned SAH, then subtrees moved to where they cost least (Bittner et al. 2013): the
    /// default, about 2-4x the binned build's time for 3-27 % fewer nodes per diffuse ray on
    /// the shared scenes (path tracing Conference 0.84x the time, Sponza 0.93x;
    /// docs/experiments/reinsertion-default.md).
    #[default]
    Reinsertion,
}

impl BuilderKind {
    /// Every builder: the three top-down ones, fastest build first, then reinsertion, which
    /// refines the binned tree.
    pub const ALL: [BuilderKind; 4] = [BuilderKind::Median, BuilderKind::Sah, BuilderKind::SweepSah, BuilderKind::Reinsertion];

    /// The name on the command line (`--builder`) and in reports.
    pub fn name(self) -> &'static str {
        match self {
            BuilderKind::Median => "median",
            BuilderKind::Sah => "sah",
            BuilderKind::SweepSah => "sweep-sah",
            BuilderKind::Reinsertion => "reinsertion",
        }
    }
}

/// Settings shared by the builders.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildConfig {
    /// Stop splitting at this many primitives or fewer (default 4: leaves of 1-4 triangles
    /// balance node visits against triangle tests for a GPU traversal).
    pub max_leaf_size: u32,
    /// SAH bins per axis (default 16: within a few percent of a full sweep at a fraction of
    /// the cost; Wald 2007, "On fast construction of SAH-based BVHs").
    pub sah_bins: u32,
    /// SAH cost of one node traversal step, relative to one triangle test (default 1.0).
    pub traversal_cost: f32,
    /// SAH cost of one triangle test (default 1.0).
    pub intersection_cost: f32,
    /// Threads the binned SAH build may use: 0 (default) for every core, 1 for the caller's
    /// thread alone. The tree does not depend on it; the other builders use one thread.
    pub threads: usize,
}

impl Default for BuildConfig {
    fn default() -> Self {
        Self { max_leaf_size: 4, sah_bins: 16, traversal_cost: 1.0, intersection_cost: 1.0, threads: 0 }
    }
}

impl BuildConfig {
    /// `threads`, with 0 read as the machine's cores.
    pub fn thread_count(&self) -> usize {
        match self.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            t => t,
        }
    }
}

/// Build a BVH over `boxes` (one per primitive; `centroids[i]` is the centre used for
/// partitioning) with the chosen builder.
pub fn build(kind: BuilderKind, boxes: &[Aabb], centroids: &[glam::Vec3], config: &BuildConfig) -> Bvh {
    match kind {
        BuilderKind::Median => build::median::build(boxes, centroids, config),
        BuilderKind::Sah => build::binned_sah::build(boxes, centroids, config),
        BuilderKind::SweepSah => build::sweep_sah::build(boxes, centroids, config),
        BuilderKind::Reinsertion => {
            // From the binned tree, not the sweep's: half the build time, and the end costs
            // are within 1-3 % either way (lower on cornell-measured, whose sweep tree is worse
            // than its binned one); reinsertion-default.md.
            let tree = build::binned_sah::build(boxes, centroids, config);
            build::reinsertion::optimize(tree, config)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    /// Reports spell builders as the flag does.
    #[test]
    fn names_are_the_flag_values() {
        for b in BuilderKind::ALL {
            assert_eq!(b.to_possible_value().map(|v| v.get_name().to_string()).as_deref(), Some(b.name()));
        }
    }
}
