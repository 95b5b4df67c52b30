//! Writes small glTF 2.0 files for the loader tests with the `gltf-json` crate's types: a
//! document, one binary buffer, and the three ways of storing it (external `.bin`, `data:`
//! URI, `.glb`).

use std::collections::BTreeMap;
use std::path::Path;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use json::Index;

/// A document being built, with the bytes of its one buffer.
pub struct Doc {
    pub root: json::Root,
    pub bin: Vec<u8>,
}

/// Where the buffer goes when the document is written.
pub enum Storage {
    /// A `.bin` file beside the `.gltf`, named by the given file name.
    External(&'static str),
    /// A base64 `data:` URI inside the JSON.
    DataUri,
}

impl Default for Doc {
    fn default() -> Self {
        Self::new()
    }
}

impl Doc {
    pub fn new() -> Self {
        let root =
            json::Root { asset: json::Asset { version: "2.0".into(), generator: Some("vkrt tests".into()), ..Default::default() }, ..Default::default() };
        Self { root, bin: Vec::new() }
    }

    /// A buffer view over `bytes`, appended to the buffer (4-byte aligned, as accessors of
    /// 4-byte components need).
    pub fn view(&mut self, bytes: &[u8]) -> Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: Index::new(0),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            name: None,
            target: None,
            extensions: None,
            extras: Default::default(),
        })
    }

    fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        min_max: Option<(json::Value, json::Value)>,
    ) -> Index<json::Accessor> {
        let view = self.view(bytes);
        let (min, max) = min_max.map_or((None, None), |(a, b)| (Some(a), Some(b)));
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64(count as u64),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    pub fn vec3(&mut self, data: &[[f32; 3]]) -> Index<json::Accessor> {
        let bytes: Vec<u8> = data.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        // POSITION needs min and max (glTF 2.0 section 3.7.2.1); harmless elsewhere.
        self.accessor(&bytes, data.len(), json::accessor::ComponentType::F32, json::accessor::Type::Vec3, Some(bounds(data)))
    }

    /// A VEC3 accessor of `base.len()` elements whose elements `indices[k]` are replaced by
    /// `values[k]` through a sparse block (glTF 2.0 section 3.6.2.3); with `base` None the
    /// accessor has no buffer view and its other elements are zeros.
    pub fn vec3_sparse(&mut self, count: usize, base: Option<&[[f32; 3]]>, indices: &[u32], values: &[[f32; 3]]) -> Index<json::Accessor> {
        let floats = |d: &[[f32; 3]]| d.iter().flatten().flat_map(|f| f.to_le_bytes()).collect::<Vec<u8>>();
        let base_view = base.map(|b| self.view(&floats(b)));
        let index_view = self.view(&indices.iter().flat_map(|i| i.to_le_bytes()).collect::<Vec<u8>>());
        let value_view = self.view(&floats(values));
        // POSITION's min and max are those of the accessor after substitution.
        let mut all: Vec<[f32; 3]> = base.map_or(vec![[0.0; 3]; count], <[_]>::to_vec);
        for (&i, v) in indices.iter().zip(values) {
            all[i as usize] = *v;
        }
        let (min, max) = bounds(&all);
        use json::accessor::sparse;
        self.root.push(json::Accessor {
            buffer_view: base_view,
            byte_offset: None,
            count: USize64(count as u64),
            component_type: Valid(json::accessor::GenericComponentType(json::accessor::ComponentType::F32)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(json::accessor::Type::Vec3),
            min: Some(min),
            max: Some(max),
            name: None,
            normalized: false,
            sparse: Some(sparse::Sparse {
                count: USize64(indices.len() as u64),
                indices: sparse::Indices {
                    buffer_view: index_view,
                    byte_offset: USize64(0),
                    component_type: Valid(json::accessor::IndexComponentType(json::accessor::ComponentType::U32)),
                    extensions: None,
                    extras: Default::default(),
                },
                values: sparse::Values { buffer_view: value_view, byte_offset: USize64(0), extensions: None, extras: Default::default() },
                extensions: None,
                extras: Default::default(),
            }),
        })
    }

    pub fn vec2(&mut self, data: &[[f32; 2]]) -> Index<json::Accessor> {
        let bytes: Vec<u8> = data.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        self.accessor(&bytes, data.len(), json::accessor::ComponentType::F32, json::accessor::Type::Vec2, None)
    }

    pub fn vec4(&mut self, data: &[[f32; 4]]) -> Index<json::Accessor> {
        let bytes: Vec<u8> = data.iter().flatten().flat_map(|f| f.to_le_bytes()).collect();
        self.accessor(&bytes, data.len(), json::accessor::ComponentType::F32, json::accessor::Type::Vec4, None)
    }

    pub fn indices(&mut self, data: &[u32]) -> Index<json::Accessor> {
        let bytes: Vec<u8> = data.iter().flat_map(|i| i.to_le_bytes()).collect();
        self.accessor(&bytes, data.len(), json::accessor::ComponentType::U32, json::accessor::Type::Scalar, None)
    }

    /// A primitive from its attribute accessors.
    pub fn primitive(
        &self,
        attributes: &[(json::mesh::Semantic, Index<json::Accessor>)],
        indices: Option<Index<json::Accessor>>,
        material: Option<Index<json::Material>>,
        mode: json::mesh::Mode,
    ) -> json::mesh::Primitive {
        let attributes: BTreeMap<_, _> = attributes.iter().map(|(s, a)| (Valid(s.clone()), *a)).collect();
        json::mesh::Primitive { attributes, extensions: None, extras: Default::default(), indices, material, mode: Valid(mode), targets: None }
    }

    pub fn mesh(&mut self, primitives: Vec<json::mesh::Primitive>) -> Index<json::Mesh> {
        self.root.push(json::Mesh { extensions: None, extras: Default::default(), name: None, primitives, weights: None })
    }

    /// A mesh of one indexed triangle list with positions and normals.
    pub fn triangles(&mut self, positions: &[[f32; 3]], normals: &[[f32; 3]], indices: &[u32], material: Option<Index<json::Material>>) -> Index<json::Mesh> {
        use json::mesh::Semantic;
        let p = self.vec3(positions);
        let n = self.vec3(normals);
        let i = self.indices(indices);
        let prim = self.primitive(&[(Semantic::Positions, p), (Semantic::Normals, n)], Some(i), material, json::mesh::Mode::Triangles);
        self.mesh(vec![prim])
    }

    pub fn node(&mut self, node: json::Node) -> Index<json::Node> {
        self.root.push(node)
    }

    /// The scene to render: `roots`, made the default scene.
    pub fn scene(&mut self, roots: Vec<Index<json::Node>>) {
        let s = self.root.push(json::Scene { extensions: None, extras: Default::default(), name: None, nodes: roots });
        self.root.scene = Some(s);
    }

    /// The scene to render: one node showing `mesh`, untransformed.
    pub fn scene_with_mesh(&mut self, mesh: Index<json::Mesh>) {
        let n = self.node(mesh_node(mesh));
        self.scene(vec![n]);
    }

    /// An image held in a buffer view (PNG bytes), and a texture showing it.
    pub fn png_texture(&mut self, png: &[u8]) -> Index<json::Texture> {
        let view = self.view(png);
        let image = self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        });
        self.root.push(json::Texture { name: None, sampler: None, source: image, extensions: None, extras: Default::default() })
    }

    pub fn material(&mut self, m: json::Material) -> Index<json::Material> {
        self.root.push(m)
    }

    /// Adds a KHR_lights_punctual light and returns the node extension that places it.
    pub fn light(&mut self, light: json::extensions::scene::khr_lights_punctual::Light) -> Option<json::extensions::scene::Node> {
        let ext = self.root.extensions.get_or_insert_with(Default::default);
        let lights = &mut ext.khr_lights_punctual.get_or_insert_with(Default::default).lights;
        lights.push(light);
        let index = Index::new(lights.len() as u32 - 1);
        if !self.root.extensions_used.iter().any(|e| e == "KHR_lights_punctual") {
            self.root.extensions_used.push("KHR_lights_punctual".into());
        }
        Some(json::extensions::scene::Node {
            khr_lights_punctual: Some(json::extensions::scene::khr_lights_punctual::KhrLightsPunctual { light: index }),
            ..Default::default()
        })
    }

    /// Writes a `.gltf` at `path` with its buffer stored as `storage` says.
    pub fn write_gltf(&self, path: &Path, storage: Storage) {
        let mut root = self.root.clone();
        let uri = match storage {
            Storage::External(name) => {
                std::fs::write(path.with_file_name(name), &self.bin).unwrap();
                name.to_string()
            }
            Storage::DataUri => {
                use base64::Engine as _;
                format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&self.bin))
            }
        };
        root.buffers = vec![buffer(self.bin.len(), Some(uri))];
        std::fs::write(path, json::serialize::to_string_pretty(&root).unwrap()).unwrap();
    }

    /// Writes a `.glb`: the 12-byte header, the JSON chunk padded with spaces and the BIN chunk
    /// padded with zeros (glTF 2.0 spec section 4.4, "Binary glTF Layout").
    pub fn write_glb(&self, path: &Path) {
        let mut root = self.root.clone();
        root.buffers = vec![buffer(self.bin.len(), None)];
        let mut json_bytes = json::serialize::to_vec(&root).unwrap();
        while json_bytes.len() % 4 != 0 {
            json_bytes.push(b' ');
        }
        let mut bin = self.bin.clone();
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_bytes);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        std::fs::write(path, out).unwrap();
    }
}

/// The per-component minimum and maximum of `data`, as an accessor's `min` and `max`.
fn bounds(data: &[[f32; 3]]) -> (json::Value, json::Value) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in data {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (json::Value::from(lo.to_vec()), json::Value::from(hi.to_vec()))
}

fn buffer(len: usize, uri: Option<String>) -> json::Buffer {
    json::Buffer { byte_length: USize64(len as u64), name: None, uri, extensions: None, extras: Default::default() }
}

/// A node with a mesh and a TRS or matrix transform (none: identity).
pub fn mesh_node(mesh: Index<json::Mesh>) -> json::Node {
    json::Node { mesh: Some(mesh), ..Default::default() }
}

/// PNG bytes of a `width` x `height` RGBA image, rows top first.
pub fn png(width: u32, height: u32, rgba: &[[u8; 4]]) -> Vec<u8> {
    let img = image::RgbaImage::from_fn(width, height, |x, y| image::Rgba(rgba[(y * width + x) as usize]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}
