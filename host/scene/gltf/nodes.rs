//! The node hierarchy of the scene to render, flattened: each node with its world transform
//! (glTF 2.0 spec section 3.5.2, "Transformations": a node's `matrix`, or T * R * S from its
//! `translation`, `rotation` and `scale`, post-multiplied onto its parent's world matrix).
//!
//! Section 3.5.1: "the node hierarchy MUST be a set of disjoint strict trees", so "each node
//! MUST have zero or one parent". The hierarchy is checked for that before anything is placed,
//! and walked with a stack of its own, not by recursion: a node is then placed at most once (a
//! node listed under two parents would place its subtree once per path, 2^40 times for a 1.5 KB
//! file of 40 such nodes), and a chain of any depth the file can hold is walked without
//! overflowing the thread's stack.

use std::path::Path;

use glam::Mat4;

use super::at;

/// A node placed in the world.
pub struct Placed<'a> {
    pub node: ::gltf::Node<'a>,
    pub world: Mat4,
}

/// The nodes of the scene to render in depth-first order (a node, then its children in
/// order), from the default scene (`scene`), else `scenes[0]`, else every node that is no
/// other node's child (a file without scenes, which the spec allows for libraries). Fails,
/// naming the node, on a node with two parents, a cycle, a scene root that is another node's
/// child, or a world transform that is not finite.
pub fn walk<'a>(document: &'a ::gltf::Document, file: &Path) -> anyhow::Result<Vec<Placed<'a>>> {
    let parents = parents(document, file)?;
    let roots: Vec<::gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => {
            let roots: Vec<::gltf::Node> = scene.nodes().collect();
            for (k, root) in roots.iter().enumerate() {
                if let Some(p) = parents[root.index()] {
                    let msg = format!("lists nodes[{}] as a root, but nodes[{p}] has it as a child", root.index());
                    return Err(at(file, format!("scenes[{}].nodes[{k}]", scene.index()), msg));
                }
            }
            roots
        }
        None => document.nodes().filter(|n| parents[n.index()].is_none()).collect(),
    };
    let mut out = Vec::new();
    // (node, its parent's world matrix), children pushed in reverse so they pop in order.
    let mut stack: Vec<(::gltf::Node, Mat4)> = roots.into_iter().rev().map(|r| (r, Mat4::IDENTITY)).collect();
    while let Some((node, parent)) = stack.pop() {
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(at(file, format!("nodes[{}]", node.index()), "the node's world transform is not finite"));
        }
        let children: Vec<::gltf::Node> = node.children().collect();
        stack.extend(children.into_iter().rev().map(|c| (c, world)));
        out.push(Placed { node, world });
    }
    Ok(out)
}

/// Every node's parent, after checking that the hierarchy is a forest: no node listed as a
/// child twice (by two parents, or twice by one), and no cycle (a set of nodes each the child
/// of another of the set, which no root reaches).
fn parents(document: &::gltf::Document, file: &Path) -> anyhow::Result<Vec<Option<usize>>> {
    let n = document.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for node in document.nodes() {
        for (k, child) in node.children().enumerate() {
            let c = child.index();
            if let Some(p) = parent[c] {
                let why = if p == node.index() { "lists it twice".to_string() } else { format!("nodes[{p}] lists it too") };
                let msg = format!("nodes[{c}] would have two parents ({why}); glTF 2.0 section 3.5.1: each node has at most one");
                return Err(at(file, format!("nodes[{}].children[{k}]", node.index()), msg));
            }
            parent[c] = Some(node.index());
        }
    }
    // With at most one parent each, the nodes that parentless ones do not reach are on a cycle
    // or below one.
    let mut reached = vec![false; n];
    let mut stack: Vec<::gltf::Node> = document.nodes().filter(|node| parent[node.index()].is_none()).collect();
    while let Some(node) = stack.pop() {
        reached[node.index()] = true;
        stack.extend(node.children());
    }
    if let Some(i) = reached.iter().position(|r| !r) {
        // Follow parents from the first unreached node until a node repeats: that one is on
        // the cycle (at most n steps).
        let mut seen = vec![false; n];
        let mut j = i;
        while !seen[j] {
            seen[j] = true;
            j = parent[j].unwrap_or(j);
        }
        return Err(at(file, format!("nodes[{j}]"), "the node is its own ancestor (a cycle in `children`)"));
    }
    Ok(parent)
}
