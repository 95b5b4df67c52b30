//! The node hierarchy of the scene to render, flattened: each node with its world transform
//! (glTF 2.0 spec section 3.5.2, "Transformations": a node's `matrix`, or T * R * S from its
//! `translation`, `rotation` and `scale`, post-multiplied onto its parent's world matrix).

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
/// other node's child (a file without scenes, which the spec allows for libraries).
pub fn walk<'a>(document: &'a ::gltf::Document, file: &Path) -> anyhow::Result<Vec<Placed<'a>>> {
    let roots: Vec<::gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; document.nodes().len()];
            for n in document.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            document.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    };
    let mut out = Vec::new();
    let mut on_path = vec![false; document.nodes().len()];
    for root in roots {
        visit(root, Mat4::IDENTITY, file, &mut on_path, &mut out)?;
    }
    Ok(out)
}

fn visit<'a>(
    node: ::gltf::Node<'a>,
    parent: Mat4,
    file: &Path,
    on_path: &mut [bool],
    out: &mut Vec<Placed<'a>>,
) -> anyhow::Result<()> {
    let i = node.index();
    if on_path[i] {
        // Section 3.5.1: the node hierarchy is a set of disjoint strict trees.
        return Err(at(file, format!("nodes[{i}]"), "the node is its own ancestor (a cycle in `children`)"));
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    let world = parent * local;
    if !world.is_finite() {
        return Err(at(file, format!("nodes[{i}]"), "the node's world transform is not finite"));
    }
    on_path[i] = true;
    out.push(Placed { node: node.clone(), world });
    for child in node.children() {
        visit(child, world, file, on_path, out)?;
    }
    on_path[i] = false;
    Ok(())
}
