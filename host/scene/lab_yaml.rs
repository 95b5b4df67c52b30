//! The course lab's YAML scene format (see `../shared/scenes/lab/SOURCE.md`).
//!
//! The document is walked by hand with a key path (`Lights[1].Position`) so that every error
//! and warning says where it is: an unknown key is a warning (the file still loads), a wrong
//! type or a missing file is an error. yaml-rust2 keeps no positions for nodes, so only YAML
//! syntax errors carry a line and column.
//!
//! Triangle order (= primitive ids): `Models`, then `ComplexModels`, each in file order, then
//! one triangle per `Area` light, so model ids do not depend on the light list; then the
//! copies of `Instances` (each entry's in the order of its `Transforms`), which the scene keeps
//! as one mesh and its placements (`scene::instance`).
//!
//! `Instances` is vkrt's addition to the course format: a mesh and a list of transforms, one
//! copy per transform (docs/reference.md, "Instances"):
//!
//! ```yaml
//! Instances:
//!   - Mesh: tree.obj          # with its MTL's materials, or with `Material: Name` as in Models
//!     Transforms:
//!       - Translation: [0, 0, 0]
//!         Rotation: [0, 30, 0]  # degrees about x, then y, then z
//!         Scale: 2              # one number or three
//!       - Matrix: [1, 0, 0, 5,  0, 1, 0, 0,  0, 0, 1, 0]   # by rows: 3x4, or 4x4
//! ```

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::Context;
use glam::Vec3;
use yaml_rust2::yaml::Hash;
use yaml_rust2::{Yaml, YamlLoader};

use super::assemble::{finish_scene, light_if_unlit, push_triangles, DEFAULT_AMBIENT};
use super::input_file::{read_bounded, regular_file, MAX_DESCRIPTION_BYTES};
use super::instance::{add_group, Placement};
use super::obj::{load_obj_meshes, ObjMesh};
use super::{Camera, Light, Material, Scene, Triangle, MAX_PRIMITIVES};
use crate::error::InputError;

const TOP_KEYS: &[&str] = &["Reflection", "AmbientIntensity", "Skyboxes", "Cameras", "Lights", "Materials", "Models", "ComplexModels", "Instances"];
const CAMERA_KEYS: &[&str] = &["Eye", "Target", "Up", "Fovy", "ZNear", "ZFar"];
const MATERIAL_KEYS: &[&str] = &["Name", "Blend", "Diffuse", "DiffuseMap", "Specular", "Shininess", "Emission"];
const MODEL_KEYS: &[&str] = &["Mesh", "Material", "Scale", "Translation"];
const COMPLEX_MODEL_KEYS: &[&str] = &["Mesh"];
const INSTANCE_KEYS: &[&str] = &["Mesh", "Material", "Transforms"];
const TRANSFORM_KEYS: &[&str] = &["Matrix", "Translation", "Rotation", "Scale"];

/// Loads a lab YAML scene with the meshes it names.
pub fn load_lab_yaml(path: &Path) -> anyhow::Result<Scene> {
    let bytes = read_bounded(path, MAX_DESCRIPTION_BYTES).map_err(|e| InputError::new(path, None, e))?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = bytes.get(..e.valid_up_to()).map_or(1, |b| b.iter().filter(|&&c| c == b'\n').count() + 1);
        InputError::at_line(path, line, "not UTF-8 text")
    })?;
    let docs = YamlLoader::load_from_str(text).map_err(|e| {
        let m = e.marker();
        InputError::new(path, Some(format!("line {}, column {}", m.line(), m.col() + 1)), e.info().to_string())
    })?;
    let mut lab = Lab { file: path, dir: path.parent().unwrap_or(Path::new("")).to_path_buf(), scene: Scene::default(), meshes: HashMap::new() };
    lab.scene.stats.read_input(path);
    if docs.len() > 1 {
        lab.warn_at(None, "only the first YAML document is read");
    }
    let empty = Yaml::Hash(Hash::new());
    let root = match docs.first() {
        None | Some(Yaml::Null) => &empty,
        Some(doc) => doc,
    };
    let root = lab.hash(root, "(top level)")?;
    lab.check_keys(root, "", TOP_KEYS);

    if let Some(r) = get(root, "Reflection") {
        let r = lab.string(r, "Reflection")?;
        if r != "Empirical" {
            lab.warn_at(Some("Reflection"), &format!("reflection model '{r}' is unknown; Empirical is used"));
        }
    }
    let ambient = get(root, "AmbientIntensity").map(|a| lab.vec3(a, "AmbientIntensity")).transpose()?;
    let sky_faces = match get(root, "Skyboxes") {
        Some(s) => lab.skybox(s)?,
        None => None,
    };
    let cameras = match get(root, "Cameras") {
        Some(c) => lab.cameras(c)?,
        None => Vec::new(),
    };
    let names = match get(root, "Materials") {
        Some(m) => lab.materials(m)?,
        None => HashMap::new(),
    };
    if let Some(m) = get(root, "Models") {
        lab.models(m, &names)?;
    }
    if let Some(m) = get(root, "ComplexModels") {
        lab.complex_models(m)?;
    }
    if let Some(m) = get(root, "Instances") {
        lab.instances(m, &names)?;
    }
    if let Some(l) = get(root, "Lights") {
        lab.lights(l)?;
    }

    let mut scene = lab.scene;
    finish_scene(&mut scene, path, cameras)?;
    if let Some(faces) = sky_faces {
        // Faces are decoded after the materials' textures; the six stay consecutive.
        let first_texture = scene.textures.len() as u32;
        for face in &faces {
            let t = crate::scene::Texture::load(face).with_context(|| format!("{}: Skyboxes", path.display()))?;
            scene.textures.push(t);
            scene.stats.read_input(face);
        }
        scene.sky = crate::scene::Sky::CubeMap { first_texture, scale: Vec3::ONE };
    }
    scene.ambient = ambient.unwrap_or(Vec3::ZERO);
    if light_if_unlit(&mut scene, ambient.unwrap_or(DEFAULT_AMBIENT)) {
        let msg = "no lights and no emitting material; added a directional light over the camera's shoulder";
        scene.stats.warn(InputError::new(path, None, msg).to_string());
    }
    Ok(scene)
}

/// The value under `name` in a mapping.
fn get<'y>(h: &'y Hash, name: &str) -> Option<&'y Yaml> {
    h.get(&Yaml::String(name.to_string()))
}

/// `parent.name`, or `name` at the top level.
fn child(parent: &str, name: &str) -> String {
    if parent.is_empty() {
        name.to_string()
    } else {
        format!("{parent}.{name}")
    }
}

/// How a value looks, for "expected X, found Y" messages.
fn describe(y: &Yaml) -> String {
    match y {
        Yaml::Real(s) => format!("the number {s}"),
        Yaml::Integer(i) => format!("the number {i}"),
        Yaml::String(s) => format!("the string '{s}'"),
        Yaml::Boolean(b) => format!("the boolean {b}"),
        Yaml::Array(a) => format!("a list of {}", a.len()),
        Yaml::Hash(_) => "a mapping".to_string(),
        Yaml::Alias(_) => "an alias".to_string(),
        Yaml::Null => "nothing (null)".to_string(),
        Yaml::BadValue => "an invalid value".to_string(),
    }
}

/// An entry of a mesh list: its key path (`Models[2]`), its mapping, its `Mesh` key path and file.
struct MeshEntry<'y> {
    key: String,
    h: &'y Hash,
    mesh_key: String,
    mesh_path: PathBuf,
}

/// The scene being built, and where it comes from.
struct Lab<'a> {
    file: &'a Path,
    dir: PathBuf,
    scene: Scene,
    /// `Models` meshes read so far, by file and material: a mesh placed many times (a grid
    /// of 100 statues) is parsed once.
    meshes: HashMap<(PathBuf, u32), Vec<Triangle>>,
}

impl Lab<'_> {
    fn err(&self, key: &str, message: impl Into<String>) -> anyhow::Error {
        InputError::at_key(self.file, key, message).into()
    }

    fn warn_at(&mut self, key: Option<&str>, message: &str) {
        let e = InputError::new(self.file, key.map(|k| format!("key {k}")), message);
        self.scene.stats.warn(e.to_string());
    }

    /// Warns about every key of `h` not in `known`.
    fn check_keys(&mut self, h: &Hash, path: &str, known: &[&str]) {
        for k in h.keys() {
            let name = match k {
                Yaml::String(s) => s.clone(),
                other => describe(other),
            };
            if !known.contains(&name.as_str()) {
                self.warn_at(Some(&child(path, &name)), "unknown key, ignored");
            }
        }
    }

    fn hash<'y>(&self, y: &'y Yaml, key: &str) -> anyhow::Result<&'y Hash> {
        y.as_hash().ok_or_else(|| self.err(key, format!("expected a mapping (Key: value), found {}", describe(y))))
    }

    fn list<'y>(&self, y: &'y Yaml, key: &str) -> anyhow::Result<&'y [Yaml]> {
        y.as_vec().map(Vec::as_slice).ok_or_else(|| self.err(key, format!("expected a list, found {}", describe(y))))
    }

    fn string<'y>(&self, y: &'y Yaml, key: &str) -> anyhow::Result<&'y str> {
        y.as_str().ok_or_else(|| self.err(key, format!("expected a string, found {}", describe(y))))
    }

    /// A number that is finite as an f32 (1e39 is not).
    fn number(&self, y: &Yaml, key: &str) -> anyhow::Result<f32> {
        let x = match y {
            Yaml::Integer(i) => *i as f64,
            Yaml::Real(_) => y.as_f64().unwrap_or(f64::NAN),
            _ => return Err(self.err(key, format!("expected a number, found {}", describe(y)))),
        };
        let x32 = x as f32;
        if !x32.is_finite() {
            return Err(self.err(key, format!("{x} is not a finite f32 (NaN, infinite or beyond 3.4e38)")));
        }
        Ok(x32)
    }

    /// A list of numbers whose length is one of `lengths`.
    fn numbers(&self, y: &Yaml, key: &str, lengths: &[usize]) -> anyhow::Result<Vec<f32>> {
        let wanted = lengths.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(" or ");
        let items = match y.as_vec() {
            Some(v) if lengths.contains(&v.len()) => v,
            _ => return Err(self.err(key, format!("expected a list of {wanted} numbers, found {}", describe(y)))),
        };
        items.iter().enumerate().map(|(i, v)| self.number(v, &format!("{key}[{i}]"))).collect()
    }

    fn vec3(&self, y: &Yaml, key: &str) -> anyhow::Result<Vec3> {
        let v = self.numbers(y, key, &[3])?;
        Ok(Vec3::from_slice(&v))
    }

    /// A required entry of a mapping.
    fn required<'y>(&self, h: &'y Hash, parent: &str, name: &str) -> anyhow::Result<&'y Yaml> {
        get(h, name).ok_or_else(|| self.err(&child(parent, name), "missing"))
    }

    /// A file named relative to the YAML's folder, which must exist.
    fn existing_file(&self, y: &Yaml, key: &str) -> anyhow::Result<PathBuf> {
        let p = self.dir.join(self.string(y, key)?);
        if !p.exists() {
            return Err(self.err(key, format!("file {} not found", p.display())));
        }
        regular_file(&p).map_err(|e| self.err(key, format!("{}: {e}", p.display())))?;
        Ok(p)
    }

    /// The first sky box of `Skyboxes` (a list of six-file lists: +x, -x, +y, -y, +z, -z); the
    /// lab renderer uses only the first, so the rest get a warning.
    fn skybox(&mut self, y: &Yaml) -> anyhow::Result<Option<[PathBuf; 6]>> {
        let boxes = self.list(y, "Skyboxes")?;
        if boxes.len() > 1 {
            self.warn_at(Some("Skyboxes"), "only the first sky box is used");
        }
        let Some(first) = boxes.first() else { return Ok(None) };
        let files = self.list(first, "Skyboxes[0]")?;
        if files.len() != 6 {
            let msg = format!("expected six face files (+x, -x, +y, -y, +z, -z), found {}", files.len());
            return Err(self.err("Skyboxes[0]", msg));
        }
        let mut faces: [PathBuf; 6] = Default::default();
        for (i, f) in files.iter().enumerate() {
            faces[i] = self.existing_file(f, &format!("Skyboxes[0][{i}]"))?;
        }
        Ok(Some(faces))
    }

    /// Parses every camera, in file order.
    fn cameras(&mut self, y: &Yaml) -> anyhow::Result<Vec<Camera>> {
        let mut cameras = Vec::new();
        for (i, c) in self.list(y, "Cameras")?.iter().enumerate() {
            let key = format!("Cameras[{i}]");
            let h = self.hash(c, &key)?;
            self.check_keys(h, &key, CAMERA_KEYS);
            let mut cam = Camera {
                eye: self.vec3(self.required(h, &key, "Eye")?, &child(&key, "Eye"))?,
                target: self.vec3(self.required(h, &key, "Target")?, &child(&key, "Target"))?,
                ..Camera::default()
            };
            if let Some(up) = get(h, "Up") {
                cam.up = self.vec3(up, &child(&key, "Up"))?;
            }
            if let Some(f) = get(h, "Fovy") {
                cam.fov_y_deg = self.number(f, &child(&key, "Fovy"))?;
            }
            // Accepted for the lab renderer's rasteriser; a ray tracer has no clip planes.
            for clip in ["ZNear", "ZFar"] {
                if let Some(z) = get(h, clip) {
                    self.number(z, &child(&key, clip))?;
                }
            }
            cam.frame().map_err(|e| self.err(&key, e.to_string()))?;
            cameras.push(cam);
        }
        Ok(cameras)
    }

    /// Adds the named materials; returns name -> index into `scene.materials`.
    fn materials(&mut self, y: &Yaml) -> anyhow::Result<HashMap<String, u32>> {
        let mut names = HashMap::new();
        for (i, m) in self.list(y, "Materials")?.iter().enumerate() {
            let key = format!("Materials[{i}]");
            let h = self.hash(m, &key)?;
            self.check_keys(h, &key, MATERIAL_KEYS);
            let name = self.string(self.required(h, &key, "Name")?, &child(&key, "Name"))?.to_string();
            // The lab renderer's defaults: white albedo, no highlight.
            let mut mat = Material { name: name.clone(), diffuse: Vec3::ONE, ..Material::default() };
            if let Some(b) = get(h, "Blend") {
                match self.string(b, &child(&key, "Blend"))? {
                    "Opaque" => {}
                    // The lab renderer's only see-through material is glass.
                    "Transparent" => {
                        mat.illum = 7;
                        mat.ior = 1.5;
                    }
                    other => {
                        let msg = format!("expected Opaque or Transparent, found '{other}'");
                        return Err(self.err(&child(&key, "Blend"), msg));
                    }
                }
            }
            if let Some(d) = get(h, "Diffuse") {
                mat.diffuse = self.vec3(d, &child(&key, "Diffuse"))?;
            }
            if let Some(d) = get(h, "DiffuseMap") {
                mat.diffuse_map = Some(self.existing_file(d, &child(&key, "DiffuseMap"))?);
            }
            if let Some(s) = get(h, "Specular") {
                // [r, g, b] or [r, g, b, shininess].
                let s = self.numbers(s, &child(&key, "Specular"), &[3, 4])?;
                mat.specular = Vec3::from_slice(&s);
                if let Some(&n) = s.get(3) {
                    mat.shininess = n;
                }
            }
            if let Some(n) = get(h, "Shininess") {
                mat.shininess = self.number(n, &child(&key, "Shininess"))?;
            }
            if let Some(e) = get(h, "Emission") {
                mat.emission = self.vec3(e, &child(&key, "Emission"))?;
            }
            if names.insert(name.clone(), self.scene.materials.len() as u32).is_some() {
                return Err(self.err(&child(&key, "Name"), format!("material '{name}' is defined twice")));
            }
            self.scene.materials.push(mat);
        }
        Ok(names)
    }

    /// `Models`: meshes with a named material, scaled then translated.
    fn models(&mut self, y: &Yaml, names: &HashMap<String, u32>) -> anyhow::Result<()> {
        for (i, m) in self.list(y, "Models")?.iter().enumerate() {
            let MeshEntry { key, h, mesh_key, mesh_path } = self.mesh_entry("Models", i, m, MODEL_KEYS)?;
            let material = self.material(self.required(h, &key, "Material")?, &child(&key, "Material"), names)?;
            let scale = get(h, "Scale").map(|s| self.vec3(s, &child(&key, "Scale"))).transpose()?.unwrap_or(Vec3::ONE);
            let shift = get(h, "Translation").map(|t| self.vec3(t, &child(&key, "Translation"))).transpose()?.unwrap_or(Vec3::ZERO);
            let cache_key = self.mesh_with_material(&mesh_path, material, &mesh_key)?;
            let mesh = self.meshes.get(&cache_key).map(Vec::as_slice).unwrap_or_default();
            push_triangles(&mut self.scene, mesh.iter().map(|&t| transform(t, scale, shift)));
        }
        Ok(())
    }

    /// Entry `i` of a list of meshes (`Models`, `ComplexModels`, `Instances`), unknown keys
    /// warned about, with its `Mesh` file, which must exist.
    fn mesh_entry<'y>(&mut self, list: &str, i: usize, y: &'y Yaml, known: &[&str]) -> anyhow::Result<MeshEntry<'y>> {
        let key = format!("{list}[{i}]");
        let h = self.hash(y, &key)?;
        self.check_keys(h, &key, known);
        let mesh_key = child(&key, "Mesh");
        let mesh_path = self.existing_file(self.required(h, &key, "Mesh")?, &mesh_key)?;
        Ok(MeshEntry { key, h, mesh_key, mesh_path })
    }

    /// The index of the material `y` names.
    fn material(&self, y: &Yaml, key: &str, names: &HashMap<String, u32>) -> anyhow::Result<u32> {
        let name = self.string(y, key)?;
        names.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = names.keys().map(String::as_str).collect();
            known.sort_unstable();
            self.err(key, format!("no material named '{name}' (known: {})", known.join(", ")))
        })
    }

    /// Reads the mesh at `path` (the key `mesh_key` names it), its warnings and the files it was
    /// read from going into the scene's statistics.
    fn read_mesh(&mut self, path: &Path, material: Option<u32>, mesh_key: &str) -> anyhow::Result<ObjMesh> {
        let mut mesh = load_obj_meshes(path, material).with_context(|| InputError::at_key(self.file, mesh_key, "cannot load the mesh"))?;
        for w in std::mem::take(&mut mesh.warnings) {
            self.scene.stats.warn(w);
        }
        for p in &mesh.inputs {
            self.scene.stats.read_input(p);
        }
        Ok(mesh)
    }

    /// Reads the mesh at `path` with every triangle's material `material`, once per file and
    /// material; returns its key in `self.meshes`.
    fn mesh_with_material(&mut self, path: &Path, material: u32, mesh_key: &str) -> anyhow::Result<(PathBuf, u32)> {
        let cache_key = (path.to_path_buf(), material);
        if !self.meshes.contains_key(&cache_key) {
            let mesh = self.read_mesh(path, Some(material), mesh_key)?;
            self.meshes.insert(cache_key.clone(), mesh.triangles);
        }
        Ok(cache_key)
    }

    /// Reads the mesh at `path` with its MTL's materials, which join the scene's.
    fn mesh_with_own_materials(&mut self, path: &Path, mesh_key: &str) -> anyhow::Result<Vec<Triangle>> {
        let mesh = self.read_mesh(path, None, mesh_key)?;
        let offset = self.scene.materials.len() as u32;
        self.scene.materials.extend(mesh.materials);
        Ok(mesh.triangles.into_iter().map(|t| Triangle { material: t.material + offset, ..t }).collect())
    }

    /// `ComplexModels`: meshes with the materials of their own MTL files.
    fn complex_models(&mut self, y: &Yaml) -> anyhow::Result<()> {
        for (i, m) in self.list(y, "ComplexModels")?.iter().enumerate() {
            let MeshEntry { mesh_key, mesh_path, .. } = self.mesh_entry("ComplexModels", i, m, COMPLEX_MODEL_KEYS)?;
            let triangles = self.mesh_with_own_materials(&mesh_path, &mesh_key)?;
            push_triangles(&mut self.scene, triangles);
        }
        Ok(())
    }

    /// `Instances`: a mesh (with a named material, or its MTL's) and one copy of it per entry of
    /// `Transforms`, kept as one mesh and its placements. The copies' triangles are counted
    /// against [`MAX_PRIMITIVES`] before any is placed.
    fn instances(&mut self, y: &Yaml, names: &HashMap<String, u32>) -> anyhow::Result<()> {
        for (i, m) in self.list(y, "Instances")?.iter().enumerate() {
            let MeshEntry { key, h, mesh_key, mesh_path } = self.mesh_entry("Instances", i, m, INSTANCE_KEYS)?;
            let transforms_key = child(&key, "Transforms");
            let entries = self.list(self.required(h, &key, "Transforms")?, &transforms_key)?;
            let mut placements = Vec::with_capacity(entries.len());
            for (k, t) in entries.iter().enumerate() {
                placements.push(self.placement(t, &format!("{transforms_key}[{k}]"))?);
            }
            // A named material's mesh is borrowed from the cache `Models` shares, not copied.
            let mesh: Cow<[Triangle]> = match get(h, "Material") {
                Some(name) => {
                    let material = self.material(name, &child(&key, "Material"), names)?;
                    let cache_key = self.mesh_with_material(&mesh_path, material, &mesh_key)?;
                    Cow::Borrowed(self.meshes.get(&cache_key).map(Vec::as_slice).unwrap_or_default())
                }
                None => Cow::Owned(self.mesh_with_own_materials(&mesh_path, &mesh_key)?),
            };
            let total = self.scene.placed_triangles() + mesh.len() as u64 * placements.len() as u64;
            if total > MAX_PRIMITIVES {
                let msg = format!(
                    "{} copies of a {}-triangle mesh would make the scene {total} triangles, every copy counted; a primitive id names at most {MAX_PRIMITIVES}",
                    placements.len(),
                    mesh.len()
                );
                return Err(self.err(&transforms_key, msg));
            }
            add_group(&mut self.scene, &mesh, placements);
        }
        Ok(())
    }

    /// One entry of `Transforms`: `Matrix` (by rows, 12 or 16 numbers), or any of
    /// `Translation`, `Rotation` (degrees about x, then y, then z) and `Scale` (one number or
    /// three), applied scale first.
    fn placement(&mut self, y: &Yaml, key: &str) -> anyhow::Result<Placement> {
        let h = self.hash(y, key)?;
        self.check_keys(h, key, TRANSFORM_KEYS);
        if let Some(m) = get(h, "Matrix") {
            if let Some(other) = ["Translation", "Rotation", "Scale"].into_iter().find(|k| get(h, k).is_some()) {
                return Err(self.err(&child(key, other), "give either Matrix or Translation / Rotation / Scale, not both"));
            }
            let matrix_key = child(key, "Matrix");
            let rows = self.numbers(m, &matrix_key, &[12, 16])?;
            return Placement::from_rows(&rows).map_err(|e| self.err(&matrix_key, e));
        }
        let vec = |name: &str, default: Vec3| get(h, name).map(|v| self.vec3(v, &child(key, name))).transpose().map(|v| v.unwrap_or(default));
        let scale = match get(h, "Scale") {
            Some(s) if s.as_vec().is_none() => Vec3::splat(self.number(s, &child(key, "Scale"))?),
            _ => vec("Scale", Vec3::ONE)?,
        };
        Placement::from_trs(vec("Translation", Vec3::ZERO)?, vec("Rotation", Vec3::ZERO)?, scale).map_err(|e| self.err(key, e))
    }

    fn lights(&mut self, y: &Yaml) -> anyhow::Result<()> {
        for (i, l) in self.list(y, "Lights")?.iter().enumerate() {
            let key = format!("Lights[{i}]");
            let h = self.hash(l, &key)?;
            let kind = self.string(self.required(h, &key, "Type")?, &child(&key, "Type"))?;
            let field = |name: &str| -> anyhow::Result<Vec3> { self.vec3(self.required(h, &key, name)?, &child(&key, name)) };
            let direction = |name: &str| -> anyhow::Result<Vec3> {
                let d = field(name)?.normalize_or_zero();
                if d == Vec3::ZERO {
                    return Err(self.err(&child(&key, name), "a direction cannot be zero"));
                }
                Ok(d)
            };
            let (known, light): (&[&str], Option<Light>) = match kind {
                "Point" => {
                    let light = Light::Point { position: field("Position")?, intensity: field("Intensity")? };
                    (&["Type", "Position", "Intensity"], Some(light))
                }
                "Directional" => {
                    let light = Light::Directional { direction: direction("Direction")?, intensity: field("Intensity")? };
                    (&["Type", "Direction", "Intensity"], Some(light))
                }
                "Spot" => {
                    let radius = self.number(self.required(h, &key, "Length")?, &child(&key, "Length"))?;
                    if radius <= 0.0 {
                        return Err(self.err(&child(&key, "Length"), format!("the light's radius must be positive, not {radius}")));
                    }
                    let light = Light::Spot { position: field("Position")?, direction: direction("Direction")?, intensity: field("Intensity")?, radius };
                    (&["Type", "Position", "Direction", "Intensity", "Length"], Some(light))
                }
                "Area" => {
                    let p = [field("p0")?, field("p1")?, field("p2")?];
                    let facing = direction("Direction")?;
                    self.area_light(&key, p, facing, field("Intensity")?)?;
                    (&["Type", "p0", "p1", "p2", "Direction", "Intensity"], None)
                }
                other => {
                    let msg = format!("unknown light type '{other}' (expected Point, Directional, Spot or Area)");
                    return Err(self.err(&child(&key, "Type"), msg));
                }
            };
            self.check_keys(h, &key, known);
            self.scene.lights.extend(light);
        }
        Ok(())
    }

    /// An `Area` light becomes one emitting triangle with a material of its own, wound so that
    /// its geometric normal (the emitting side) points along `facing`.
    fn area_light(&mut self, key: &str, p: [Vec3; 3], facing: Vec3, intensity: Vec3) -> anyhow::Result<()> {
        let [p0, p1, p2] = p;
        let cross = (p1 - p0).cross(p2 - p0);
        let along = cross.dot(facing);
        if cross.length() > 0.0 && along.abs() <= 1e-6 * cross.length() {
            return Err(self.err(&child(key, "Direction"), "the direction lies in the triangle's plane"));
        }
        let p = if along < 0.0 { [p0, p2, p1] } else { [p0, p1, p2] };
        let material = self.scene.materials.len() as u32;
        self.scene.materials.push(Material { name: format!("{key} (Area light)"), diffuse: Vec3::ZERO, emission: intensity, ..Material::default() });
        let before = self.scene.stats.dropped_degenerate;
        push_triangles(&mut self.scene, [Triangle { p, n: None, uv: None, material }]);
        if self.scene.stats.dropped_degenerate > before {
            self.warn_at(Some(key), "the area light's triangle has zero area; dropped");
        }
        Ok(())
    }
}

/// p' = p * scale + shift. Normals take the inverse scale (the inverse transpose of a diagonal
/// matrix) and are renormalised later. A mirroring scale (negative determinant) would turn
/// the triangles inside out, so the winding is flipped back.
fn transform(t: Triangle, scale: Vec3, shift: Vec3) -> Triangle {
    let mut t = Triangle { p: t.p.map(|p| p * scale + shift), n: t.n.map(|n| n.map(|v| v / scale)), ..t };
    if scale.x * scale.y * scale.z < 0.0 {
        t.p.swap(1, 2);
        if let Some(n) = t.n.as_mut() {
            n.swap(1, 2);
        }
        if let Some(uv) = t.uv.as_mut() {
            uv.swap(1, 2);
        }
    }
    t
}
