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
    /// All triangles. A triangle's index here is its primitive id everywhere else (hit records,
    /// `vkrt trace` output): loaders keep the file's order, faces fan-triangulated in place.
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
    /// How copies of a mesh in `triangles` were placed (lab YAML `Instances`), for a two-level
    /// BVH over one copy; empty for a scene without instances.
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
    /// Axis-aligned bounds of all triangles.
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for t in &self.triangles {
            b = b.union(&t.bounds());
        }
        b
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
            triangles: self.triangles.len(),
            materials: self.materials.len(),
            lights: self.lights.len(),
        }
    }

    /// Indices of triangles whose material emits light.
    pub fn emissive_triangles(&self) -> Vec<u32> {
        (0..self.triangles.len() as u32).filter(|&i| self.materials[self.triangles[i as usize].material as usize].is_emissive()).collect()
    }
}

/// Boxes and centroids of triangles: the only input a BVH builder sees.
pub fn triangle_boxes(tris: &[Triangle]) -> (Vec<Aabb>, Vec<Vec3>) {
    use rayon::prelude::*;
    tris.par_iter().map(|t| (t.bounds(), t.centroid())).unzip()
}
