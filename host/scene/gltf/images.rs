//! glTF images decoded into `Scene::textures`, each once however many textures and materials
//! use it. Images come from a file (relative URI), a `data:` URI or a buffer view (glTF 2.0
//! spec section 3.9.1 "Images"); the `image` crate decodes them (PNG and JPEG, the formats
//! the core spec allows, and TGA/EXR besides).

use std::path::{Path, PathBuf};

use super::at;
use crate::scene::{Scene, Texture};

/// Every image has a source the crate can name: a `uri`, or a `bufferView` with its `mimeType`
/// (spec section 5.17, which requires exactly that). The crate's `Image::source` unwraps both
/// and would panic on a file without them.
pub fn check_sources(json: &::gltf::json::Root, file: &Path) -> anyhow::Result<()> {
    for (i, image) in json.images.iter().enumerate() {
        let msg = match (&image.uri, &image.buffer_view, &image.mime_type) {
            (None, None, _) => "has neither a uri nor a bufferView",
            (_, Some(_), None) => "is in a bufferView but has no mimeType",
            _ => continue,
        };
        return Err(at(file, format!("images[{i}]"), msg));
    }
    Ok(())
}

/// The images of one document, decoded on first use.
pub struct Images<'a> {
    buffers: &'a [Vec<u8>],
    file: &'a Path,
    dir: &'a Path,
    /// `Scene::textures` index of each image decoded so far, by image index.
    decoded: Vec<Option<u32>>,
}

impl<'a> Images<'a> {
    pub fn new(document: &'a ::gltf::Document, buffers: &'a [Vec<u8>], file: &'a Path, dir: &'a Path) -> Self {
        Self { buffers, file, dir, decoded: vec![None; document.images().len()] }
    }

    /// The `Scene::textures` index of the image a glTF texture shows; `loc` is where the
    /// texture is referenced (`materials[0].pbrMetallicRoughness.baseColorTexture`).
    pub fn texture(&mut self, scene: &mut Scene, texture: &::gltf::Texture, loc: &str) -> anyhow::Result<u32> {
        let image = texture.source();
        let i = image.index();
        if let Some(t) = self.decoded.get(i).copied().flatten() {
            return Ok(t);
        }
        let image_loc = format!("images[{i}]");
        let (bytes, name): (Vec<u8>, PathBuf) = match image.source() {
            ::gltf::image::Source::View { view, .. } => {
                let data = self.buffers.get(view.buffer().index()).map(Vec::as_slice).unwrap_or(&[]);
                let range = view.offset()..view.offset() + view.length();
                let Some(bytes) = data.get(range) else {
                    let msg = format!("bufferView {} lies outside its buffer", view.index());
                    return Err(at(self.file, image_loc, msg));
                };
                (bytes.to_vec(), embedded_name(self.file, &image_loc))
            }
            ::gltf::image::Source::Uri { uri, .. } if uri.starts_with("data:") => {
                let bytes = super::buffers::uri_bytes(uri, self.file, self.dir, &image_loc, &mut scene.stats)?;
                (bytes, embedded_name(self.file, &image_loc))
            }
            ::gltf::image::Source::Uri { uri, .. } => {
                let bytes = super::buffers::uri_bytes(uri, self.file, self.dir, &image_loc, &mut scene.stats)?;
                (bytes, super::buffers::uri_path(self.dir, uri))
            }
        };
        let decoded = Texture::from_bytes(name.clone(), &bytes).map_err(|e| {
            let what = image.name().map_or(String::new(), |n| format!(" '{n}'"));
            at(self.file, &image_loc, format!("image{what} ({}), used by {loc}: {e:#}", name.display()))
        })?;
        let t = scene.textures.len() as u32;
        scene.textures.push(decoded);
        if let Some(slot) = self.decoded.get_mut(i) {
            *slot = Some(t);
        }
        Ok(t)
    }
}

/// The name an embedded image goes by in messages: `scene.glb#images[2]`.
fn embedded_name(file: &Path, image_loc: &str) -> PathBuf {
    PathBuf::from(format!("{}#{image_loc}", file.display()))
}
