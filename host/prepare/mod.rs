//! The prepare stage: everything a render needs from a scene, computed once. The BVH is built
//! and laid out, the shading arrays, texture atlas and light table are filled, the shader
//! features, bounds and camera frame are worked out ([`PreparedScene::new`]); [`upload`] puts
//! it on the device. Integrators and batch queries take only the uploaded result.

pub mod cache;
pub mod casters;
pub mod envmap;
pub mod features;
pub mod light_table;
pub mod mesh_shading;
pub mod mirrors;
pub mod scene_buffers;
pub mod texture_atlas;
pub mod upload;

pub use envmap::EnvLight;
pub use features::Features;
pub use upload::{GpuBvh, GpuScene};

use crate::accel::{self, triangle_list, FlatBvh, LayoutKind};
use crate::bvh::{self, BuildConfig, BuilderKind};
use crate::geom::Aabb;
use crate::gpu_abi::constants::TEXTURE_NONE;
use crate::gpu_abi::{GpuEmitter, GpuInstance, GpuLight, GpuLightPick, GpuMaterial, GpuPush, GpuShading, GpuTangents, GpuTexture, GpuTriangle, GpuUv};
use crate::scene::camera::CameraFrame;
use crate::scene::{Camera, Scene, Sky};
use anyhow::{Context as _, Result};
use glam::Vec3;
use light_table::LightTable;
use scene_buffers::SceneBuffers;
use texture_atlas::{TextureAtlas, TEXEL_BUDGET_BYTES};

/// The content hash (xxh3-64) of a file a scene was read from: how checkpoints and the
/// prepared-scene cache know that a scene's files are the ones they were made from.
pub fn content_hash(path: &std::path::Path) -> Result<u64> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {} to hash it", path.display()))?;
    Ok(xxhash_rust::xxh3::xxh3_64(&bytes))
}

/// How to build and lay out the BVH.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrepareOptions {
    /// Default: reinsertion (binned SAH, refined).
    pub builder: BuilderKind,
    /// Default: threaded.
    pub layout: LayoutKind,
    pub build: BuildConfig,
    /// Keep the largest triangles out of the tree in the triangle list
    /// (`accel::triangle_list`). Default: on.
    pub triangle_list: bool,
}

impl Default for PrepareOptions {
    fn default() -> Self {
        Self { builder: BuilderKind::default(), layout: LayoutKind::default(), build: BuildConfig::default(), triangle_list: true }
    }
}

/// What the integrators need to know about a scene besides its arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneInfo {
    /// The camera's frame, or why the scene's camera has none (a degenerate camera only stops
    /// a render, not a batch query).
    pub camera: std::result::Result<CameraFrame, String>,
    /// Constant ambient light of the Whitted integrator.
    pub ambient: Vec3,
    /// What escaping rays see: a colour, times the cube map's texel if `sky_texture` is not
    /// `TEXTURE_NONE` (`GpuFrame::sky_color`, `sky_texture`).
    pub sky_color: [f32; 3],
    pub sky_texture: u32,
    /// Bounds of all triangles.
    pub bounds: Aabb,
    /// Largest |coordinate| of the bounds: the length scale for ray offsets
    /// (`shaders/include/offset.glsl`).
    pub scale: f32,
    /// Radius of the bounding sphere: what a directional light's power is measured over.
    pub radius: f32,
    /// The shader features the scene uses.
    pub features: Features,
}

impl SceneInfo {
    pub fn of(scene: &Scene) -> Self {
        Self::new(&scene.camera, scene.ambient, &scene.sky, scene.bounds(), Features::of(scene))
    }

    /// From the parts a scene's view is made of: `features` are the scene's, with the sky
    /// feature set for `sky`.
    pub fn new(camera: &Camera, ambient: Vec3, sky: &Sky, bounds: Aabb, features: Features) -> Self {
        let (sky_color, sky_texture) = match *sky {
            Sky::None => ([0.0; 3], TEXTURE_NONE),
            Sky::Constant(c) => (c.to_array(), TEXTURE_NONE),
            Sky::CubeMap { first_texture, scale } => (scale.to_array(), first_texture),
            // Looked up in the map's own arrays (`GpuScene::set_environment`), its scale in them.
            Sky::Environment { .. } => ([0.0; 3], TEXTURE_NONE),
        };
        Self {
            camera: camera.frame().map_err(|e| format!("{e:#}")),
            ambient,
            sky_color,
            sky_texture,
            bounds,
            scale: if bounds.is_empty() { 1.0 } else { bounds.min.abs().max(bounds.max.abs()).max_element().max(f32::MIN_POSITIVE) },
            radius: if bounds.is_empty() { 0.0 } else { 0.5 * bounds.extent().length() },
            features: features.with_sky(sky),
        }
    }

    /// The same scene seen from `camera` under `sky`.
    pub fn with_view(&self, camera: &Camera, sky: &Sky) -> Self {
        Self::new(camera, self.ambient, sky, self.bounds, self.features.clone())
    }

    /// The camera frame, or an error saying why there is none.
    pub fn camera(&self) -> Result<&CameraFrame> {
        self.camera.as_ref().map_err(|e| anyhow::anyhow!("{e}")).context("camera")
    }
}

/// Seconds each step of the prepare stage took (`vkrt render --verbose` prints them).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrepareTimes {
    /// Triangle boxes and centroids, the builder's input.
    pub boxes: f64,
    /// The BVH builder.
    pub tree: f64,
    /// Laying the tree out for the GPU (`accel::flatten`).
    pub flatten: f64,
    /// Shading arrays, light table and texture atlas.
    pub shading: f64,
}

impl PrepareTimes {
    /// The BVH's part: boxes, tree and layout.
    pub fn bvh(&self) -> f64 {
        self.boxes + self.tree + self.flatten
    }
}

/// A scene prepared for the GPU, on the CPU side.
#[derive(Debug)]
pub struct PreparedScene {
    pub flat: FlatBvh,
    pub buffers: SceneBuffers,
    pub atlas: TextureAtlas,
    pub lights: LightTable,
    pub info: SceneInfo,
    pub times: PrepareTimes,
    /// For a two-level BVH, whose triangles and shading data are in their meshes' spaces: the
    /// world triangles (from `Scene::triangles`) of mirror, glass and glossy materials and
    /// their world shading entries (each triangle's `prim` indexes them), among which every
    /// upload finds the planar mirrors and caustic casters (`mirrors`, `casters`). Empty for a
    /// one-level BVH, whose own arrays serve.
    pub specular_triangles: Vec<GpuTriangle>,
    pub specular_shading: Vec<GpuShading>,
}

/// The arrays of a prepared scene as the device takes them, borrowed from a [`PreparedScene`]
/// or from a mapped cache file (`cache`).
#[derive(Debug, Clone, Copy)]
pub struct SceneArrays<'a> {
    pub layout: LayoutKind,
    /// The layout's node array (`NodeArray::bytes`).
    pub nodes: &'a [u8],
    /// The BVH's push constants (`FlatBvh::push`: node count, layout data).
    pub push: GpuPush,
    pub triangles: &'a [GpuTriangle],
    /// A two-level BVH's instances (`accel::two_level`); empty for a one-level layout.
    pub instances: &'a [GpuInstance],
    /// The world triangles the planar mirrors and caustic casters are found among, and the
    /// shading data their `prim` indexes: `triangles` and `shading` for a one-level BVH,
    /// `PreparedScene::specular_triangles` and `specular_shading` for a two-level one.
    pub world_triangles: &'a [GpuTriangle],
    pub world_shading: &'a [GpuShading],
    pub shading: &'a [GpuShading],
    pub materials: &'a [GpuMaterial],
    pub lights: &'a [GpuLight],
    pub emitters: &'a [GpuEmitter],
    pub uvs: &'a [GpuUv],
    /// Vertex tangents by primitive id; empty unless some material has a normal map.
    pub tangents: &'a [GpuTangents],
    pub textures: &'a [GpuTexture],
    pub texels: &'a [u32],
    pub picks: &'a [GpuLightPick],
    /// The light table's total weight.
    pub total_weight: f64,
}

impl PreparedScene {
    /// The arrays, borrowed.
    pub fn arrays(&self) -> SceneArrays<'_> {
        SceneArrays {
            layout: self.flat.layout(),
            nodes: self.flat.nodes.bytes(),
            push: self.flat.push(),
            triangles: &self.flat.triangles,
            instances: self.flat.nodes.instances(),
            world_triangles: if self.flat.nodes.instances().is_empty() { &self.flat.triangles } else { &self.specular_triangles },
            world_shading: if self.flat.nodes.instances().is_empty() { &self.buffers.shading } else { &self.specular_shading },
            shading: &self.buffers.shading,
            materials: &self.buffers.materials,
            lights: &self.buffers.lights,
            emitters: &self.buffers.emitters,
            uvs: &self.buffers.uvs,
            tangents: &self.buffers.tangents,
            textures: &self.atlas.table,
            texels: &self.atlas.texels,
            picks: &self.lights.picks,
            total_weight: self.lights.total_weight,
        }
    }

    /// Prepares `scene` as `options` say: a scene with instances walked in a layout of
    /// `accel::two_level::LAYOUTS` gets its two-level BVH ([`build_two_level`]), any other scene
    /// or layout the one-level tree over every triangle ([`build_bvh`]).
    pub fn new(scene: &Scene, options: &PrepareOptions) -> Result<Self> {
        // Of the scene as loaded: an expanded copy's bounds are its exact ones, a little inside
        // the placed boxes `Scene::bounds` takes, and both walks must offset rays alike.
        let info = SceneInfo::of(scene);
        if !walks_two_levels(scene, options.layout) {
            let expanded = expand(scene, options.layout)?;
            let (flat, mut times) = build_bvh(&expanded, options)?;
            let start = std::time::Instant::now();
            let buffers = SceneBuffers::new(&expanded);
            let (lights, atlas) = lights_and_atlas(&expanded, &buffers, &info);
            times.shading = start.elapsed().as_secs_f64();
            return Ok(Self { flat, buffers, atlas, lights, info, times, specular_triangles: Vec::new(), specular_shading: Vec::new() });
        }
        let (flat, mut times) = build_two_level(scene, options)?;
        let start = std::time::Instant::now();
        let buffers = mesh_shading::per_mesh(scene);
        anyhow::ensure!(buffers.shading.len() == flat.triangles.len(), "the two-level BVH's meshes and their shading data disagree");
        let (specular_triangles, specular_shading) = specular_triangles(scene, &buffers.materials);
        let (lights, atlas) = lights_and_atlas(scene, &buffers, &info);
        times.shading = start.elapsed().as_secs_f64();
        Ok(Self { flat, buffers, atlas, lights, info, times, specular_triangles, specular_shading })
    }
}

fn lights_and_atlas(scene: &Scene, buffers: &SceneBuffers, info: &SceneInfo) -> (LightTable, TextureAtlas) {
    (LightTable::new(buffers, info.radius), TextureAtlas::pack(&scene.textures, TEXEL_BUDGET_BYTES))
}

/// The scene with its instances' copies placed ([`Scene::expanded`]), for a one-level BVH in
/// `layout`; the error names the layout and the count (a two-level BVH takes any).
pub fn expand(scene: &Scene, layout: LayoutKind) -> Result<std::borrow::Cow<'_, Scene>> {
    scene
        .expanded()
        .map_err(|e| anyhow::anyhow!("{e}"))
        .with_context(|| format!("placing the scene's copies for a one-level BVH in the {} layout (a two-level BVH takes them in every layout)", layout.name()))
}

/// Builds the scene's BVH with `options.builder` and lays it out as `options.layout`: all a
/// batch query needs. Also returns the seconds its steps took (`shading` left 0).
pub fn build_bvh(scene: &Scene, options: &PrepareOptions) -> Result<(FlatBvh, PrepareTimes)> {
    let clock = std::time::Instant::now();
    let scene = &*expand(scene, options.layout)?;
    let lap = || clock.elapsed().as_secs_f64();
    let (boxes, centroids) = crate::scene::triangle_boxes(&scene.triangles);
    let t_boxes = lap();
    // The few triangles that span much of the scene go to the triangle list, the rest to the
    // tree (accel::triangle_list says why); the tree's primitive ids index scene.triangles.
    let listed = if options.triangle_list { triangle_list::choose(&boxes) } else { Vec::new() };
    let mut in_tree = vec![true; boxes.len()];
    for &i in &listed {
        in_tree[i as usize] = false;
    }
    let kept: Vec<u32> = (0..boxes.len() as u32).filter(|&i| in_tree[i as usize]).collect();
    let tree = if listed.is_empty() {
        bvh::build(options.builder, &boxes, &centroids, &options.build)
    } else {
        let kept_boxes: Vec<_> = kept.iter().map(|&i| boxes[i as usize]).collect();
        let kept_centroids: Vec<_> = kept.iter().map(|&i| centroids[i as usize]).collect();
        let mut tree = bvh::build(options.builder, &kept_boxes, &kept_centroids, &options.build);
        for p in tree.prim_indices.iter_mut() {
            *p = kept[*p as usize];
        }
        tree
    };
    drop((boxes, centroids));
    let t_tree = lap();
    let flat = accel::flatten_with_list(&tree, &scene.triangles, options.layout, &listed)
        .with_context(|| format!("flattening the BVH as {}", options.layout.name()))?;
    let t_flat = lap();
    Ok((flat, PrepareTimes { boxes: t_boxes, tree: t_tree - t_boxes, flatten: t_flat - t_tree, shading: 0.0 }))
}

/// The scene's triangles that `mirrors::planar_mirrors` and `casters::caustic_casters` may
/// keep, in the world, every copy of an instanced mesh placed, in primitive-id order, each
/// with its world shading entry (the triangle's `prim` indexes the second list): those of
/// plain mirrors and of caster materials, each kind only while the copies would not exceed
/// what its search takes. Past that the search finds nothing in the expanded scene either
/// (more than `MAX_MIRROR_PLANES` x `MAX_PLANE_TRIANGLES` mirror triangles; more than
/// `MAX_CASTERS` pieces, each copy at least one, copies taken as apart), so none of that
/// kind is placed: the host's memory does not grow with the copies (10,000 glossy statues
/// placed would take 48 GB). The choice is per material, so that `planar_mirrors` sees every
/// triangle of each material it flags (a flagged material's paths are weighed against light
/// sampling through all of its triangles).
fn specular_triangles(scene: &Scene, materials: &[GpuMaterial]) -> (Vec<GpuTriangle>, Vec<GpuShading>) {
    // The materials as the upload's `planar_mirrors` flags them (a plain mirror whose triangles
    // are all flat), found from each mesh once in its own space (placing a triangle turns its
    // face and vertex normals alike) and from plain mirrors' triangles only, the only ones it
    // looks at: a flagged mirror is no caster.
    let plain = |t: &crate::scene::Triangle| materials.get(t.material as usize).is_some_and(mirrors::plain_mirror);
    let (flagged, _) = {
        let own_and_meshes: Vec<&crate::scene::Triangle> =
            scene.triangles.iter().chain(scene.instances.iter().flat_map(|g| &g.mesh)).filter(|t| plain(t)).collect();
        let triangles: Vec<GpuTriangle> = own_and_meshes.iter().enumerate().map(|(k, t)| accel::gpu_triangle(t, k as u32)).collect();
        let shading: Vec<GpuShading> = own_and_meshes.iter().map(|t| scene_buffers::shading(t)).collect();
        mirrors::planar_mirrors(&triangles, &shading, materials)
    };
    let material = |t: &crate::scene::Triangle| flagged.get(t.material as usize);
    let mirror = |t: &crate::scene::Triangle| material(t).is_some_and(mirrors::plain_mirror);
    let caster = |t: &crate::scene::Triangle| material(t).is_some_and(casters::casts);
    let own_mirrors = scene.triangles.iter().filter(|t| mirror(t)).count() as u64;
    let placed_mirrors: u64 =
        own_mirrors + scene.instances.iter().map(|g| g.mesh.iter().filter(|t| mirror(t)).count() as u64 * g.placements.len() as u64).sum::<u64>();
    let caster_copies: u64 = scene.instances.iter().filter(|g| g.mesh.iter().any(caster)).map(|g| g.placements.len() as u64).sum();
    let place_mirrors = placed_mirrors <= (mirrors::MAX_MIRROR_PLANES * mirrors::MAX_PLANE_TRIANGLES) as u64;
    let place_casters = caster_copies <= casters::MAX_CASTERS as u64;
    let kept = |t: &crate::scene::Triangle| (place_mirrors && mirror(t)) || (place_casters && caster(t));
    let mut world: Vec<crate::scene::Triangle> = scene.triangles.iter().filter(|t| kept(t)).copied().collect();
    for g in &scene.instances {
        let specular_mesh: Vec<usize> = (0..g.mesh.len()).filter(|&i| kept(&g.mesh[i])).collect();
        for c in 0..g.placements.len() {
            world.extend(specular_mesh.iter().map(|&i| g.placed(c, i)));
        }
    }
    world.iter().enumerate().map(|(k, t)| (accel::gpu_triangle(t, k as u32), scene_buffers::shading(t))).unzip()
}

/// Whether a scene prepared for `layout` walks its two-level BVH: it has instances, and the
/// layout is one a two-level BVH's levels are laid out in (`accel::two_level::LAYOUTS`:
/// every layout).
pub fn walks_two_levels(scene: &Scene, layout: LayoutKind) -> bool {
    !scene.instances.is_empty() && accel::two_level::LAYOUTS.contains(&layout)
}

/// The BVH a batch query walks for `scene` in `options.layout`: its two-level BVH where it
/// has one in that layout ([`walks_two_levels`]), else the one-level tree ([`build_bvh`]).
pub fn build_walk(scene: &Scene, options: &PrepareOptions) -> Result<(FlatBvh, PrepareTimes)> {
    if walks_two_levels(scene, options.layout) {
        build_two_level(scene, options)
    } else {
        build_bvh(scene, options)
    }
}

/// The two-level BVH of a scene with instances (`accel::two_level`: one tree per mesh, a top
/// level over the instances), built with `options.builder` in `options.layout` (one of
/// `accel::two_level::LAYOUTS`), as a [`FlatBvh`] without a triangle
/// list whose node array names its instances: what `vkrt trace`, `vkrt bvh` and the renders
/// walk for such a scene ([`walks_two_levels`]). The time is all in `tree`.
pub fn build_two_level(scene: &Scene, options: &PrepareOptions) -> Result<(FlatBvh, PrepareTimes)> {
    let clock = std::time::Instant::now();
    let meshes = accel::two_level::meshes(scene);
    let (nodes, triangles) = accel::two_level::build(&meshes, options.builder, &options.build, options.layout).context("building the two-level BVH")?;
    Ok((nodes.into_flat(triangles), PrepareTimes { tree: clock.elapsed().as_secs_f64(), ..PrepareTimes::default() }))
}
