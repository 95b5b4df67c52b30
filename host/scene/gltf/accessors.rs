//! Buffer views and accessors checked against the bounds the spec sets (glTF 2.0 sections 3.6.2
//! "Accessors" and 3.6.2.4 "Data Alignment"), on the JSON, before the crate reads anything.
//!
//! The gltf crate (1.4.1) checks indices but not sizes: it computes an accessor's byte range as
//! `offset + stride * (count - 1) + size` unchecked, so a count of 0 or a huge one overflows
//! (a panic in builds with overflow checks, as the tests have; a wrapped range otherwise), and
//! its validator indexes a primitive's POSITION accessor without a bounds check. Each is an
//! error here, located in the JSON. Found by fuzzing (fuzz/fuzz_targets/gltf.rs).

use std::path::Path;

use ::gltf::json::{self, validation::Checked};

use super::at;

/// Every buffer view lies in its buffer; every accessor has at least one element and its
/// elements (and a sparse accessor's indices and values) lie in their buffer views; every
/// primitive's POSITION names an accessor that exists.
pub fn check(root: &json::Root, file: &Path) -> anyhow::Result<()> {
    for (i, view) in root.buffer_views.iter().enumerate() {
        let Some(buffer) = root.buffers.get(view.buffer.value()) else { continue }; // the validator's to report
        let start = view.byte_offset.map_or(0, |o| o.0);
        let end = start.checked_add(view.byte_length.0);
        if end.map_or(true, |end| end > buffer.byte_length.0) {
            let msg = format!("bytes {start} + {} lie outside buffer {}'s {} bytes", view.byte_length.0, view.buffer.value(), buffer.byte_length.0);
            return Err(at(file, format!("bufferViews[{i}]"), msg));
        }
    }
    for (i, a) in root.accessors.iter().enumerate() {
        let loc = format!("accessors[{i}]");
        if a.count.0 == 0 {
            return Err(at(file, loc, "count is 0; an accessor has at least one element"));
        }
        let (Checked::Valid(component), Checked::Valid(kind)) = (&a.component_type, &a.type_) else { continue };
        let size = (component.0.size() * kind.multiplicity()) as u64;
        if let Some(view) = a.buffer_view {
            let offset = a.byte_offset.map_or(0, |o| o.0);
            fits(root, view, offset, a.count.0, size).map_err(|msg| at(file, &loc, msg))?;
        }
        if let Some(sparse) = &a.sparse {
            let loc = format!("{loc}.sparse");
            if sparse.count.0 == 0 || sparse.count.0 > a.count.0 {
                let msg = format!("count is {}; a sparse accessor has 1 to the accessor's {} elements", sparse.count.0, a.count.0);
                return Err(at(file, loc, msg));
            }
            if let Checked::Valid(index) = &sparse.indices.component_type {
                let (view, offset) = (sparse.indices.buffer_view, sparse.indices.byte_offset.0);
                fits(root, view, offset, sparse.count.0, index.0.size() as u64).map_err(|msg| at(file, format!("{loc}.indices"), msg))?;
            }
            let (view, offset) = (sparse.values.buffer_view, sparse.values.byte_offset.0);
            fits(root, view, offset, sparse.count.0, size).map_err(|msg| at(file, format!("{loc}.values"), msg))?;
        }
    }
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let position = prim.attributes.get(&Checked::Valid(json::mesh::Semantic::Positions));
            if let Some(index) = position.filter(|i| i.value() >= root.accessors.len()) {
                let msg = format!("accessor {} does not exist (the file has {})", index.value(), root.accessors.len());
                return Err(at(file, format!("meshes[{m}].primitives[{p}].attributes.POSITION"), msg));
            }
        }
    }
    Ok(())
}

/// `count` elements of `size` bytes from `offset`, at the view's stride (else packed), lie in
/// buffer view `view`.
fn fits(root: &json::Root, view: json::Index<json::buffer::View>, offset: u64, count: u64, size: u64) -> Result<(), String> {
    let Some(v) = root.buffer_views.get(view.value()) else { return Ok(()) }; // the validator's to report
    let stride = v.byte_stride.map_or(size, |s| s.0 as u64);
    let end = stride.checked_mul(count - 1).and_then(|b| b.checked_add(size)).and_then(|b| b.checked_add(offset));
    match end {
        Some(end) if end <= v.byte_length.0 => Ok(()),
        _ => Err(format!(
            "{count} elements of {size} bytes from byte {offset} (stride {stride}) lie outside bufferView {}'s {} bytes",
            view.value(),
            v.byte_length.0
        )),
    }
}
