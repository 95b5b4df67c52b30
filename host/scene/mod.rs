//! The renderer's view of a scene: triangles, materials, lights, a camera.
//!
//! Loaders ([`obj`], [`lab_yaml`], [`gltf`]) produce a [`Scene`]; everything after them (the prepare
//! stage, `vkrt trace`'s ray sets) reads only this. Coordinates are world space, right-handed,
//! any unit. Depends on `geom` only: no BVH, no GPU format.

pub mod assemble;
pub mod camera;
pub mod envmap;
pub mod gltf;
pub mod input_file;
pub mod instance;
pub mod lab_yaml;
pub mod light;
pub mod load;
pub mod material;
pub mod material_textures;
pub mod obj;
pub mod obj_geometry;
pub mod sky;
pub mod tangents;
pub mod texture;

pub use camera::Camera;
pub use light::Light;
pub use load::load_scene;
pub use material::{Material, MetallicRoughness};
pub use sky::Sky;
pub use texture::Texture;

use crate::geom::Aabb;
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};

/// One triangle, with the per-vertex data shading needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// Vertex positions in the order they appear in the file (counter-clockwise = front face).
    pub p: [Vec3; 3],
    /// Per-vertex shading normals, if the file has them.
    pub n: Option<[Vec3; 3]>,
    /// Per-vertex texture coordinates, if the file has them.
    pub uv: Option<[Vec2; 3]>,
    /// Index into [`Scene::materials`].
    pub material: u32,
}

impl Triangle {
    /// The unnormalised geometric normal, (p1 - p0) x (p2 - p0); its length is twice the area.
    pub fn cross(&self) -> Vec3 {
        (self.p[1] - self.p[0]).cross(self.p[2] - self.p[0])
    }
    pub fn area(&self) -> f32 {
        0.5 * self.cross().length()
    }
    pub fn centroid(&self) -> Vec3 {
        (self.p[0] + self.p[1] + self.p[2]) / 3.0
    }
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(&self.p)
    }
}

/// Everything a render needs from the scene file.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// The triangles that are no instance's. A triangle's index here is its primitive id
    /// everywhere else (hit records, `vkrt trace` output): loaders keep the file's order, faces
    /// fan-triangulated in place; the copies of `instances` come after them.
    pub triangles: Vec<Triangle>,
    pub materials: Vec<Material>,
    /// Lights that are not triangles (point, directional, spot, cone). Emissive triangles are found
    /// from their materials; lab `Area` lights are added as emissive triangles.
    pub lights: Vec<Light>,
    /// The camera renders use: the file's first, or for a file without one a default
    /// (`assemble::default_camera`: inside a room, outside an object).
    pub camera: Camera,
    /// Every camera the file defines, in file order (`vkrt render --camera N` picks one).
    pub cameras: Vec<Camera>,
    /// Constant ambient light added to every surface by the Whitted integrator (lab `AmbientIntensity`).
    pub ambient: Vec3,
    /// Per-vertex tangents (xyz, and w = +-1 the bitangent's handedness, as glTF's TANGENT),
    /// by triangle index: empty when no material has a normal map, else one entry per triangle
    /// (zero where the file has none; `tangents` fills those in with MikkTSpace).
    pub tangents: Vec<[glam::Vec4; 3]>,
    /// Decoded textures, indexed by `Material::diffuse_texture`/`alpha_texture` and the sky.
    pub textures: Vec<Texture>,
    /// What rays that leave the scene see.
    pub sky: Sky,
    /// Meshes placed as copies (lab YAML `Instances`, glTF meshes placed more than once), each
    /// held once in object space with its placements: their triangles are not in `triangles`,
    /// and their primitive ids follow its ([`instance::InstanceGroup`]). Empty for a scene
    /// without instances.
    pub instances: Vec<instance::InstanceGroup>,
    /// Counts of what the loader dropped or changed, for the log.
    pub stats: LoadStats,
}

/// A scene without its triangles, materials and textures: what the command line still needs
/// after the prepare stage (and all a prepared-scene cache entry keeps of the CPU scene).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneSummary {
    pub camera: Camera,
    pub cameras: Vec<Camera>,
    pub ambient: Vec3,
    pub sky: Sky,
    pub stats: LoadStats,
    pub triangles: usize,
    pub materials: usize,
    pub lights: usize,
}

/// What a loader did besides reading: dropped triangles, warnings, the files it read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LoadStats {
    /// Zero-area triangles dropped (they can never be hit and would break sampling by area).
    pub dropped_degenerate: usize,
    /// Warnings, for the caller to show (the command line prints them unless `--quiet`).
    pub warnings: Vec<String>,
    /// Every file the loader read (scene file, meshes, material libraries, textures, sky
    /// faces), each once, in the order first read: what a checkpoint hashes to know that a
    /// resumed or merged run renders the same scene.
    pub inputs: Vec<PathBuf>,
    /// The file has no camera and looks like a room from its bounds' centre
    /// (`assemble::looks_like_a_room`): the default camera and light are inside it.
    pub interior: bool,
    /// Nothing in the file emits, so the loader added `default_light` as the last of
    /// `Scene::lights`, and a little ambient light: an environment map replaces both.
    pub default_light: bool,
}

impl LoadStats {
    /// Records a warning (loaders print nothing themselves).
    pub fn warn(&mut self, message: String) {
        self.warnings.push(message);
    }

    /// Records that the loader read `path` (once, however often it is read).
    pub fn read_input(&mut self, path: &Path) {
        if !self.inputs.iter().any(|p| p == path) {
            self.inputs.push(path.to_path_buf());
        }
    }
}

impl Scene {
    /// Axis-aligned bounds of all triangles, each copy of an instanced mesh by its object
    /// bounds' placed corners (`instance::placed_box`).
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for t in &self.triangles {
            b = b.union(&t.bounds());
        }
        for g in &self.instances {
            let object = g.object_bounds();
            for p in &g.placements {
                b = b.union(&instance::placed_box(&p.world(), &object));
            }
        }
        b
    }

    /// Triangles in the scene, every copy of an instanced mesh counted.
    pub fn placed_triangles(&self) -> u64 {
        self.triangles.len() as u64 + self.instances.iter().map(|g| g.placed_triangles()).sum::<u64>()
    }

    /// What is left of the scene once its arrays are prepared for the GPU: cameras, sky,
    /// ambient light, counts and the loader's report.
    pub fn summary(&self) -> SceneSummary {
        SceneSummary {
            camera: self.camera,
            cameras: self.cameras.clone(),
            ambient: self.ambient,
            sky: self.sky,
            stats: self.stats.clone(),
            triangles: self.placed_triangles() as usize,
            materials: self.materials.len(),
            lights: self.lights.len(),
        }
    }

    /// Indices of the triangles (of `triangles`, not of instances) whose material emits light.
    pub fn emissive_triangles(&self) -> Vec<u32> {
        (0..self.triangles.len() as u32).filter(|&i| self.is_emissive(&self.triangles[i as usize])).collect()
    }

    /// Whether some triangle, of the scene's own or of an instanced mesh, emits light.
    pub fn emits(&self) -> bool {
        self.triangles.iter().chain(self.instances.iter().flat_map(|g| &g.mesh)).any(|t| self.is_emissive(t))
    }

    /// Whether `t`'s material emits light.
    pub fn is_emissive(&self, t: &Triangle) -> bool {
        self.materials.get(t.material as usize).is_some_and(Material::is_emissive)
    }

    /// Primitive `prim` in the world: one of `triangles`, or a copy's triangle placed.
    pub fn triangle(&self, prim: u32) -> Option<Triangle> {
        if let Some(t) = self.triangles.get(prim as usize) {
            return Some(*t);
        }
        let g = self.instances.iter().find(|g| prim >= g.first && u64::from(prim - g.first) < g.placed_triangles())?;
        let k = (prim - g.first) as usize;
        Some(g.placed(k / g.mesh.len(), k % g.mesh.len()))
    }

    /// Gives each instance group the primitive ids after the scene's own triangles and the
    /// groups before it; fails if they would pass what a primitive id can name.
    pub fn number_instances(&mut self) -> Result<(), String> {
        let mut next = self.triangles.len() as u64;
        for g in &mut self.instances {
            g.first = u32::try_from(next).map_err(|_| too_many(next))?;
            next += g.placed_triangles();
        }
        if next > MAX_PRIMITIVES {
            return Err(too_many(next));
        }
        Ok(())
    }

    /// The scene with every copy of its instanced meshes placed into `triangles` (and their
    /// tangents into `tangents`), in primitive-id order, and no instances: what a one-level BVH
    /// is built over. Borrowed when there are no instances. Fails if the copies would pass
    /// [`assemble::MAX_PLACED_TRIANGLES`] (only a two-level BVH takes more).
    pub fn expanded(&self) -> Result<std::borrow::Cow<'_, Scene>, String> {
        if self.instances.is_empty() {
            return Ok(std::borrow::Cow::Borrowed(self));
        }
        let placed = self.placed_triangles();
        if placed > assemble::MAX_PLACED_TRIANGLES {
            return Err(format!(
                "the scene places {placed} triangles, every copy of its instanced meshes ({}) counted; a one-level BVH holds every copy and takes at most {}",
                self.instances.len(),
                assemble::MAX_PLACED_TRIANGLES
            ));
        }
        let mut scene = Scene { instances: Vec::new(), triangles: Vec::with_capacity(placed as usize), ..self.clone_without_geometry() };
        scene.triangles.extend_from_slice(&self.triangles);
        let tangents = !self.tangents.is_empty();
        if tangents {
            scene.tangents = self.tangents.clone();
            scene.tangents.resize(self.triangles.len(), [glam::Vec4::ZERO; 3]);
        }
        for g in &self.instances {
            for c in 0..g.placements.len() {
                for i in 0..g.mesh.len() {
                    scene.triangles.push(g.placed(c, i));
                    if tangents {
                        scene.tangents.push(g.placed_tangents(c, i));
                    }
                }
            }
        }
        Ok(std::borrow::Cow::Owned(scene))
    }

    /// Everything but the triangles, tangents and instances.
    fn clone_without_geometry(&self) -> Scene {
        Scene {
            triangles: Vec::new(),
            materials: self.materials.clone(),
            lights: self.lights.clone(),
            camera: self.camera,
            cameras: self.cameras.clone(),
            ambient: self.ambient,
            tangents: Vec::new(),
            textures: self.textures.clone(),
            sky: self.sky,
            instances: Vec::new(),
            stats: self.stats.clone(),
        }
    }
}

/// The most triangles a scene may hold, every copy counted: primitive ids are 32-bit, and the
/// largest is `PRIM_NONE` (no hit).
pub const MAX_PRIMITIVES: u64 = u32::MAX as u64;

fn too_many(count: u64) -> String {
    format!("the scene places {count} triangles, every copy counted; a primitive id names at most {MAX_PRIMITIVES}")
}

/// Boxes and centroids of triangles: the only input a BVH builder sees.
pub fn triangle_boxes(tris: &[Triangle]) -> (Vec<Aabb>, Vec<Vec3>) {
    use rayon::prelude::*;
    tris.par_iter().map(|t| (t.bounds(), t.centroid())).unzip()
}
