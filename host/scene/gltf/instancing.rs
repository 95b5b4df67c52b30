//! `EXT_mesh_gpu_instancing`: a node that draws its mesh once per element of its TRANSLATION,
//! ROTATION and SCALE accessors, each copy placed by the node's world matrix times the copy's
//! own T * R * S (the extension's specification, "Extending Nodes"). Like every other
//! placement the copies are expanded at load ([`super::mesh::check_placed_triangles`] counts
//! them first, from the accessors' counts).
//!
//! The three accessors are FLOAT (VEC3, VEC4 for the unit quaternion x, y, z, w, VEC3); the
//! extension also allows normalized integer rotations, which vkrt refuses with the accessor's
//! name rather than misread.

use std::path::Path;

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::json::Value;
use glam::{Mat4, Quat, Vec3};

use super::at;

pub const EXTENSION: &str = "EXT_mesh_gpu_instancing";

/// The attributes the extension defines, their element shapes.
const ATTRIBUTES: [(&str, Dimensions); 3] = [("TRANSLATION", Dimensions::Vec3), ("ROTATION", Dimensions::Vec4), ("SCALE", Dimensions::Vec3)];

/// The node's instancing accessors, checked: (attribute name, accessor), all with one count.
struct Attributes<'a> {
    accessors: Vec<(&'static str, ::gltf::Accessor<'a>)>,
    count: usize,
}

fn attributes<'a>(node: &::gltf::Node<'a>, document: &'a ::gltf::Document, file: &Path) -> anyhow::Result<Option<Attributes<'a>>> {
    let Some(ext) = node.extension_value(EXTENSION) else { return Ok(None) };
    let loc = format!("nodes[{}].extensions.{EXTENSION}", node.index());
    let Some(attrs) = ext.get("attributes").and_then(Value::as_object) else {
        return Err(at(file, format!("{loc}.attributes"), "missing, or not an object of accessor indices"));
    };
    let mut accessors = Vec::new();
    for (name, value) in attrs {
        let key = format!("{loc}.attributes.{name}");
        let Some(&(name, dimensions)) = ATTRIBUTES.iter().find(|(n, _)| n == name) else {
            // Custom attributes (names starting with `_`) carry data vkrt has no use for.
            if name.starts_with('_') {
                continue;
            }
            return Err(at(file, key, "not an attribute of the extension (TRANSLATION, ROTATION, SCALE, or _CUSTOM ones)"));
        };
        let index = value.as_u64().ok_or_else(|| at(file, &key, format!("{value} is not an accessor index")))?;
        let accessor = usize::try_from(index)
            .ok()
            .and_then(|i| document.accessors().nth(i))
            .ok_or_else(|| at(file, &key, format!("accessor {index} does not exist (the file has {})", document.accessors().len())))?;
        if accessor.data_type() != DataType::F32 || accessor.dimensions() != dimensions || accessor.normalized() {
            let msg = format!(
                "accessor {index} holds {} {}{}; vkrt reads {name} as FLOAT {}",
                super::mesh::type_names(&[accessor.data_type()]),
                format!("{:?}", accessor.dimensions()).to_uppercase(),
                if accessor.normalized() { " (normalized)" } else { "" },
                format!("{dimensions:?}").to_uppercase()
            );
            return Err(at(file, key, msg));
        }
        if let Some(stride) = accessor.view().and_then(|v| v.stride()).filter(|&s| s < accessor.size()) {
            return Err(at(file, key, format!("accessor {index}: byteStride {stride} is less than its {}-byte element", accessor.size())));
        }
        accessors.push((name, accessor));
    }
    let Some(count) = accessors.first().map(|(_, a)| a.count()) else {
        return Err(at(file, format!("{loc}.attributes"), "no TRANSLATION, ROTATION or SCALE accessor"));
    };
    if let Some((name, a)) = accessors.iter().find(|(_, a)| a.count() != count) {
        let msg = format!("{} elements, but {} has {count}: every attribute gives one element per instance", a.count(), accessors[0].0);
        return Err(at(file, format!("{loc}.attributes.{name}"), msg));
    }
    Ok(Some(Attributes { accessors, count }))
}

/// How many copies of its mesh the node draws: its instance count, or 1 without the extension.
pub fn copies(node: &::gltf::Node, document: &::gltf::Document, file: &Path) -> anyhow::Result<u64> {
    Ok(attributes(node, document, file)?.map_or(1, |a| a.count as u64))
}

/// The world matrices of the node's copies: `world` alone without the extension, else `world`
/// times each instance's T * R * S.
pub fn worlds(node: &::gltf::Node, document: &::gltf::Document, buffers: &[Vec<u8>], world: Mat4, file: &Path) -> anyhow::Result<Vec<Mat4>> {
    let Some(attrs) = attributes(node, document, file)? else { return Ok(vec![world]) };
    let loc = |name: &str| format!("nodes[{}].extensions.{EXTENSION}.attributes.{name}", node.index());
    let get = |b: ::gltf::Buffer| buffers.get(b.index()).map(Vec::as_slice);
    let mut translations = vec![Vec3::ZERO; attrs.count];
    let mut rotations = vec![Quat::IDENTITY; attrs.count];
    let mut scales = vec![Vec3::ONE; attrs.count];
    for (name, accessor) in &attrs.accessors {
        let unreadable = || at(file, loc(name), format!("accessor {} cannot be read: it lies outside its buffer or buffer view", accessor.index()));
        match *name {
            "ROTATION" => {
                let items = ::gltf::accessor::Iter::<[f32; 4]>::new(accessor.clone(), get).ok_or_else(unreadable)?;
                for (i, q) in items.enumerate().take(attrs.count) {
                    let q = Quat::from_array(q);
                    // The extension asks for unit quaternions; a little drift is normalised
                    // away, a zero or non-finite one is an error.
                    if !q.is_finite() || q.length() < 1e-3 {
                        return Err(at(file, loc(name), format!("element {i} ({q}) is not a rotation (a unit quaternion x, y, z, w)")));
                    }
                    rotations[i] = q.normalize();
                }
            }
            _ => {
                let items = ::gltf::accessor::Iter::<[f32; 3]>::new(accessor.clone(), get).ok_or_else(unreadable)?;
                let target = if *name == "TRANSLATION" { &mut translations } else { &mut scales };
                for (i, v) in items.enumerate().take(attrs.count) {
                    target[i] = Vec3::from(v);
                }
            }
        }
    }
    let mut out = Vec::with_capacity(attrs.count);
    for i in 0..attrs.count {
        let m = world * Mat4::from_scale_rotation_translation(scales[i], rotations[i], translations[i]);
        if !m.is_finite() || scales[i].element_product() == 0.0 {
            let msg = format!("instance {i}'s transform is not finite or flattens the mesh (scale {})", scales[i]);
            return Err(at(file, format!("nodes[{}].extensions.{EXTENSION}", node.index()), msg));
        }
        out.push(m);
    }
    Ok(out)
}
