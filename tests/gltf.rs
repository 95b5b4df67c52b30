//! The glTF 2.0 loader (host/scene/gltf/) on files the tests write themselves
//! (tests/common/gltf_writer.rs): transforms, instancing, mirroring, the three buffer storages, sparse accessors,
//! textures on the right face, cameras by index, punctual lights in both integrators, and errors
//! that name file and location (also for files the gltf crate itself would panic on).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::gltf_writer::{mesh_node, png, Doc, Storage};
use glam::{Mat4, Quat, Vec3, Vec4};
use gltf_json as json;
use json::extensions::scene::khr_lights_punctual as khr;
use json::validation::Checked::Valid;
use vkrt::integrator::{whitted, RenderSettings};
use vkrt::prepare::{GpuScene, PrepareOptions, PreparedScene};
use vkrt::scene::{load_scene, Light, Scene};

/// One triangle in the z = 0 plane, counter-clockwise seen from +z, normals +z.
const TRI: [[f32; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
const UP_Z: [[f32; 3]; 3] = [[0.0, 0.0, 1.0]; 3];

fn scratch(test: &str) -> PathBuf {
    common::scratch_dir(&format!("gltf/{test}"))
}

fn assert_near(what: &str, got: Vec3, want: Vec3) {
    assert!(got.abs_diff_eq(want, 1e-5), "{what}: got {got}, want {want}");
}

fn vkrt(args: &[&str]) -> Output {
    Command::new(common::vkrt_bin()).args(args).env_remove("VKRT_CACHE").output().expect("run vkrt")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Renders with Whitted, one sample at each pixel centre.
fn whitted_image(scene: &Scene, width: u32, height: u32) -> vkrt::integrator::Image {
    let ctx = common::gpu_context();
    let prepared = PreparedScene::new(scene, &PrepareOptions::default()).unwrap();
    let gpu = GpuScene::upload(&ctx, &prepared).unwrap();
    let settings = RenderSettings { width, height, spp: 1, ..RenderSettings::default() };
    let (image, stats) = whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap();
    assert_eq!(stats.nonfinite_samples, 0);
    common::assert_no_validation_messages(&ctx);
    image
}

#[test]
fn child_trs_under_parent_matrix_gives_exact_world_positions() {
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    // Child: translate (0, 1, 0) after a quarter turn about +z.
    let rotation = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let child =
        doc.node(json::Node { translation: Some([0.0, 1.0, 0.0]), rotation: Some(json::scene::UnitQuaternion(rotation.to_array())), ..mesh_node(mesh) });
    // Parent: scale 2, then translate (10, 0, 0), as a column-major matrix.
    let parent_m = Mat4::from_translation(Vec3::new(10.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(2.0));
    let parent = doc.node(json::Node { matrix: Some(parent_m.to_cols_array()), children: Some(vec![child]), ..Default::default() });
    doc.scene(vec![parent]);
    let path = scratch("hierarchy").join("hierarchy.gltf");
    doc.write_gltf(&path, Storage::External("hierarchy.bin"));

    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.triangles.len(), 1);
    let p = scene.triangles[0].p;
    // Child: (0,0,0) -> (0,1,0), (1,0,0) -> (0,2,0), (0,1,0) -> (-1,1,0); parent: x2, +10 in x.
    assert_near("vertex 0", p[0], Vec3::new(10.0, 2.0, 0.0));
    assert_near("vertex 1", p[1], Vec3::new(10.0, 4.0, 0.0));
    assert_near("vertex 2", p[2], Vec3::new(8.0, 2.0, 0.0));
    assert!(scene.stats.inputs.iter().any(|i| i.ends_with("hierarchy.bin")), "the .bin is not among the inputs: {:?}", scene.stats.inputs);
}

#[test]
fn a_mesh_used_by_two_nodes_is_placed_twice_and_a_mirrored_copy_keeps_its_front_face() {
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let a = doc.node(json::Node { translation: Some([0.0, 0.0, 5.0]), ..mesh_node(mesh) });
    let b = doc.node(json::Node { translation: Some([3.0, 0.0, 0.0]), scale: Some([-1.0, 1.0, 1.0]), ..mesh_node(mesh) });
    doc.scene(vec![a, b]);
    let path = scratch("instances").join("instances.gltf");
    doc.write_gltf(&path, Storage::External("instances.bin"));

    let scene = load_scene(&path).unwrap();
    assert!(scene.triangles.is_empty(), "the mesh is kept once, as an instance group");
    let placed = scene.expanded().unwrap();
    assert_eq!(placed.triangles.len(), 2, "one triangle per node using the mesh");
    let (first, mirrored) = (placed.triangles[0], placed.triangles[1]);
    assert!(first.p.iter().all(|p| p.z == 5.0), "first copy: {:?}", first.p);
    let mut xs: Vec<f32> = mirrored.p.iter().map(|p| p.x).collect();
    xs.sort_by(f32::total_cmp);
    assert_eq!(xs, vec![2.0, 3.0, 3.0], "mirrored copy at x = 3 - x: {:?}", mirrored.p);
    // The front face (counter-clockwise) still faces +z, as the (inverse-transposed) normals do.
    assert!(first.cross().z > 0.0 && mirrored.cross().z > 0.0, "geometric normals {} {}", first.cross(), mirrored.cross());
    let n = mirrored.n.expect("normals");
    assert!(n.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)), "mirrored normals {n:?}");
    // The two copies are one instance group: the second mirrored.
    assert_eq!(scene.instances.len(), 1);
    let copies: Vec<_> = scene.instances[0].copies().map(|c| (c.0, c.1.mirrored())).collect();
    assert_eq!(copies, vec![(0, false), (1, true)]);
    every_copy_is_hit_through_the_two_level_bvh(&scene);
}

/// Copies three levels down a node tree (root, two children, two grandchildren each, each
/// placing two meshes that share their geometry under different materials): each mesh is one
/// instance group of four copies, placed by the product of its ancestors' transforms, and keeps
/// its own material.
#[test]
fn copies_nested_three_levels_deep_with_shared_geometry_under_two_materials() {
    use json::mesh::{Mode, Semantic};
    let mut doc = Doc::new();
    let colour = |doc: &mut Doc, rgb: [f32; 3]| {
        doc.material(json::Material {
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor([rgb[0], rgb[1], rgb[2], 1.0]),
                ..Default::default()
            },
            ..Default::default()
        })
    };
    let (red, blue) = (colour(&mut doc, [1.0, 0.0, 0.0]), colour(&mut doc, [0.0, 0.0, 1.0]));
    let (p, n, i) = (doc.vec3(&TRI), doc.vec3(&UP_Z), doc.indices(&[0, 1, 2]));
    let attributes = [(Semantic::Positions, p), (Semantic::Normals, n)];
    let red_mesh = doc.mesh(vec![doc.primitive(&attributes, Some(i), Some(red), Mode::Triangles)]);
    let blue_mesh = doc.mesh(vec![doc.primitive(&attributes, Some(i), Some(blue), Mode::Triangles)]);
    let mut want: Vec<(json::Index<json::Mesh>, Mat4)> = Vec::new();
    let root_m = Mat4::from_translation(Vec3::new(0.0, 0.0, 10.0));
    let mut children = Vec::new();
    for (a, x) in [(0.5f32, -5.0f32), (-1.0, 5.0)] {
        let child_m = Mat4::from_translation(Vec3::new(x, 0.0, 0.0)) * Mat4::from_rotation_z(a);
        let mut grandchildren = Vec::new();
        for (s, y) in [(2.0f32, 3.0f32), (0.5, -3.0)] {
            let grand_m = Mat4::from_translation(Vec3::new(0.0, y, 0.0)) * Mat4::from_scale(Vec3::splat(s));
            // The blue copy beside the red one, so that each is hit on its own.
            let leaves: Vec<_> = [(red_mesh, 0.0), (blue_mesh, 1.5)]
                .into_iter()
                .map(|(mesh, dx)| {
                    want.push((mesh, root_m * child_m * grand_m * Mat4::from_translation(Vec3::new(dx, 0.0, 0.0))));
                    doc.node(json::Node { translation: Some([dx, 0.0, 0.0]), ..mesh_node(mesh) })
                })
                .collect();
            grandchildren.push(doc.node(json::Node { matrix: Some(grand_m.to_cols_array()), children: Some(leaves), ..Default::default() }));
        }
        children.push(doc.node(json::Node { matrix: Some(child_m.to_cols_array()), children: Some(grandchildren), ..Default::default() }));
    }
    let root = doc.node(json::Node { matrix: Some(root_m.to_cols_array()), children: Some(children), ..Default::default() });
    doc.scene(vec![root]);
    let path = scratch("nested").join("nested.gltf");
    doc.write_gltf(&path, Storage::External("nested.bin"));

    let scene = load_scene(&path).unwrap();
    assert!(scene.triangles.is_empty());
    assert_eq!(scene.instances.iter().map(|g| g.placements.len()).collect::<Vec<_>>(), vec![4, 4]);
    let colours: Vec<Vec3> = scene.instances.iter().map(|g| scene.materials[g.mesh[0].material as usize].diffuse).collect();
    assert_eq!(colours, vec![Vec3::X, Vec3::Z], "each mesh keeps its own material");
    // Copies in depth-first order, the red mesh's first.
    let expanded = scene.expanded().unwrap();
    let ordered: Vec<Mat4> = [red_mesh, blue_mesh].iter().flat_map(|m| want.iter().filter(move |(w, _)| w == m).map(|(_, t)| *t)).collect();
    for (t, world) in expanded.triangles.iter().zip(&ordered) {
        for k in 0..3 {
            assert_near("nested copy", t.p[k], world.transform_point3(Vec3::from(TRI[k])));
        }
    }
    every_copy_is_hit_through_the_two_level_bvh(&scene);
}

/// Rays straight down -z onto each triangle's centroid hit that triangle through the scene's
/// two-level BVH (`accel::two_level`), as they do in the expanded scene.
fn every_copy_is_hit_through_the_two_level_bvh(scene: &vkrt::scene::Scene) {
    let flat = vkrt::prepare::build_two_level(scene, &Default::default()).unwrap().0;
    assert!(!flat.nodes.instances().is_empty());
    let placed = scene.expanded().unwrap();
    for (prim, t) in placed.triangles.iter().enumerate() {
        let c = t.centroid();
        let ray = vkrt::gpu_abi::GpuRay { origin: [c.x, c.y, c.z + 20.0], tmin: 0.0, direction: [0.0, 0.0, -1.0], tmax: f32::INFINITY };
        let hit = flat.trace(&ray, false);
        let expected = vkrt::accel::leaf::brute_force(&placed.triangles, &ray);
        assert_eq!(hit.prim, prim as u32, "{ray:?}");
        assert!(
            (hit.t - expected.t).abs() <= 1e-5 * expected.t && (hit.u - expected.u).abs() < 1e-5 && (hit.v - expected.v).abs() < 1e-5,
            "{hit:?} against {expected:?}"
        );
    }
}

/// A textured quad doc: 2 triangles over [-1, 1]^2 at z = 0, UVs with glTF's v = 0 at the top.
fn quad_doc(doc: &mut Doc, material: Option<json::Index<json::Material>>, tangents: bool) -> json::Index<json::Mesh> {
    use json::mesh::Semantic;
    let p = doc.vec3(&[[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
    let n = doc.vec3(&[[0.0, 0.0, 1.0]; 4]);
    let uv = doc.vec2(&[[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    let i = doc.indices(&[0, 1, 2, 0, 2, 3]);
    let mut attributes = vec![(Semantic::Positions, p), (Semantic::Normals, n), (Semantic::TexCoords(0), uv)];
    if tangents {
        let t = doc.vec4(&[[1.0, 0.0, 0.0, 1.0]; 4]);
        attributes.push((Semantic::Tangents, t));
    }
    let prim = doc.primitive(&attributes, Some(i), material, json::mesh::Mode::Triangles);
    doc.mesh(vec![prim])
}

fn textured_material(doc: &mut Doc, texture: json::Index<json::Texture>) -> json::Index<json::Material> {
    doc.material(json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_texture: Some(json::texture::Info { index: texture, tex_coord: 0, extensions: None, extras: Default::default() }),
            metallic_factor: json::material::StrengthFactor(0.0),
            ..Default::default()
        },
        ..Default::default()
    })
}

/// Sparse accessors (glTF 2.0 section 3.6.2.3): a base buffer view with some elements
/// substituted, and one with no buffer view at all (zeros, then the substitutions).
#[test]
fn sparse_accessors_substitute_their_elements() {
    use json::mesh::Semantic;
    let mut doc = Doc::new();
    // A quad whose corner 2 is moved from (1, 1, 0) to (2, 3, 0) by the sparse block.
    let quad = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let p = doc.vec3_sparse(4, Some(&quad), &[2], &[[2.0, 3.0, 0.0]]);
    // Normals from zeros: every element substituted with +z.
    let n = doc.vec3_sparse(4, None, &[0, 1, 2, 3], &[[0.0, 0.0, 1.0]; 4]);
    let i = doc.indices(&[0, 1, 2, 0, 2, 3]);
    let prim = doc.primitive(&[(Semantic::Positions, p), (Semantic::Normals, n)], Some(i), None, json::mesh::Mode::Triangles);
    let mesh = doc.mesh(vec![prim]);
    let node = doc.node(mesh_node(mesh));
    doc.scene(vec![node]);
    let path = scratch("sparse").join("sparse.gltf");
    doc.write_gltf(&path, Storage::External("sparse.bin"));
    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.triangles.len(), 2);
    assert_near("substituted corner", scene.triangles[0].p[2], Vec3::new(2.0, 3.0, 0.0));
    assert_near("kept corner", scene.triangles[1].p[2], Vec3::new(0.0, 1.0, 0.0));
    for t in &scene.triangles {
        let normals = t.n.expect("the sparse normals are read");
        for v in normals {
            assert_near("normal from a view-less sparse accessor", v, Vec3::Z);
        }
    }
}

#[test]
fn glb_and_data_uri_load_the_same_triangles_as_an_external_buffer() {
    let mut doc = Doc::new();
    let tex = doc.png_texture(&png(1, 1, &[[200, 100, 50, 255]]));
    let m = textured_material(&mut doc, tex);
    let mesh = quad_doc(&mut doc, Some(m), false);
    let node = doc.node(json::Node { translation: Some([1.0, 2.0, 3.0]), ..mesh_node(mesh) });
    doc.scene(vec![node]);
    let dir = scratch("storage");
    doc.write_gltf(&dir.join("external.gltf"), Storage::External("external.bin"));
    doc.write_gltf(&dir.join("embedded.gltf"), Storage::DataUri);
    doc.write_glb(&dir.join("binary.glb"));
    let external = load_scene(&dir.join("external.gltf")).unwrap();
    assert_eq!(external.triangles.len(), 2);
    assert_eq!(external.textures.len(), 1);
    for name in ["embedded.gltf", "binary.glb"] {
        let other = load_scene(&dir.join(name)).unwrap();
        assert_eq!(other.triangles, external.triangles, "{name}");
        assert_eq!(other.materials, external.materials, "{name}");
        assert_eq!(other.textures[0].texels, external.textures[0].texels, "{name}");
        assert_eq!(other.stats.inputs, vec![dir.join(name)], "{name} reads no other file");
    }
}

/// Renders the 2x2 texture red | green over blue | black on a quad filling the view, lit by a
/// directional light from the camera, and checks each quadrant: a flipped v swaps top and
/// bottom, a flipped u left and right.
#[test]
fn base_colour_texture_lands_on_the_right_face_the_right_way_up() {
    let mut doc = Doc::new();
    let texels = [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [0, 0, 0, 255]];
    let tex = doc.png_texture(&png(2, 2, &texels));
    let m = textured_material(&mut doc, tex);
    let mesh = quad_doc(&mut doc, Some(m), false);
    let quad = doc.node(mesh_node(mesh));
    let camera = doc.root.push(perspective(30f32.to_radians()));
    let cam_node = doc.node(json::Node { camera: Some(camera), translation: Some([0.0, 0.0, 3.0]), ..Default::default() });
    let sun = doc.light(light(khr::Type::Directional, 1.0, None));
    let sun_node = doc.node(json::Node { extensions: sun, ..Default::default() });
    doc.scene(vec![quad, cam_node, sun_node]);
    let path = scratch("texture").join("texture.glb");
    doc.write_glb(&path);

    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.cameras.len(), 1);
    let image = whitted_image(&scene, 32, 32);
    let dominant = |x: u32, y: u32| -> usize {
        let c = image.get(x, y);
        (0..3).max_by(|&a, &b| c[a].total_cmp(&c[b])).unwrap()
    };
    assert_eq!(dominant(8, 8), 0, "top left is red: {:?}", image.get(8, 8));
    assert_eq!(dominant(24, 8), 1, "top right is green: {:?}", image.get(24, 8));
    assert_eq!(dominant(8, 24), 2, "bottom left is blue: {:?}", image.get(8, 24));
    let black = image.get(24, 24);
    // A black base colour keeps only the glTF dielectric's specular term (Ks 0.04 in Whitted).
    assert!(black.iter().all(|&c| c < 0.15) && black.iter().all(|&c| c < 0.25 * image.get(8, 8)[0]), "bottom right is black: {black:?}");
    assert!(image.get(8, 8)[0] > 0.5, "the red texel is lit: {:?}", image.get(8, 8));
}

fn perspective(yfov: f32) -> json::Camera {
    json::Camera {
        name: None,
        orthographic: None,
        perspective: Some(json::camera::Perspective { aspect_ratio: Some(1.0), yfov, zfar: None, znear: 0.01, extensions: None, extras: Default::default() }),
        type_: Valid(json::camera::Type::Perspective),
        extensions: None,
        extras: Default::default(),
    }
}

fn light(type_: khr::Type, intensity: f32, spot: Option<khr::Spot>) -> khr::Light {
    khr::Light { color: [1.0, 1.0, 1.0], extensions: None, extras: Default::default(), intensity, name: None, range: None, spot, type_: Valid(type_) }
}

/// Two cameras; the CLI's `--camera 1` renders from the second, `--camera 2` is refused.
#[test]
fn camera_picked_by_index_has_its_own_eye() {
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let tri = doc.node(mesh_node(mesh));
    let c0 = doc.root.push(perspective(0.8));
    let c1 = doc.root.push(perspective(0.5));
    let n0 = doc.node(json::Node { camera: Some(c0), translation: Some([0.0, 0.0, 4.0]), ..Default::default() });
    // The second camera hangs under a parent that moves it; it looks down -z of its node.
    let n1 = doc.node(json::Node { camera: Some(c1), translation: Some([0.25, 0.25, 2.0]), ..Default::default() });
    let parent = doc.node(json::Node { translation: Some([0.0, 0.0, 1.0]), children: Some(vec![n1]), ..Default::default() });
    doc.scene(vec![tri, n0, parent]);
    let path = scratch("cameras").join("cameras.gltf");
    doc.write_gltf(&path, Storage::External("cameras.bin"));

    let scene = load_scene(&path).unwrap();
    assert_eq!(scene.cameras.len(), 2);
    assert_near("camera 0 eye", scene.cameras[0].eye, Vec3::new(0.0, 0.0, 4.0));
    assert_near("camera 1 eye", scene.cameras[1].eye, Vec3::new(0.25, 0.25, 3.0));
    assert_near("camera 1 view", (scene.cameras[1].target - scene.cameras[1].eye).normalize(), -Vec3::Z);
    assert!((scene.cameras[1].fov_y_deg - 0.5f32.to_degrees()).abs() < 1e-4);
    assert_eq!(scene.camera, scene.cameras[0], "the first camera renders by default");

    let out = scratch("cameras").join("one.png");
    let o = vkrt(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "--width", "8", "--height", "8", "--camera", "1", "--verbose"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("camera: --eye 0.25,0.25,3 "), "{}", stderr(&o));
    let o = vkrt(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "--width", "8", "--height", "8", "--camera", "2"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--camera 2: the scene file defines 2 camera(s)"), "{}", stderr(&o));
}

/// A floor (y = 0, base colour 0.5, not metallic) seen from straight above by a glTF camera,
/// and the given light node extension at `light_node`.
fn floor_scene(test: &str, light: khr::Light, light_node: json::Node) -> Scene {
    let mut doc = Doc::new();
    let floor = doc.material(json::Material {
        pbr_metallic_roughness: json::material::PbrMetallicRoughness {
            base_color_factor: json::material::PbrBaseColorFactor([0.5, 0.5, 0.5, 1.0]),
            metallic_factor: json::material::StrengthFactor(0.0),
            ..Default::default()
        },
        ..Default::default()
    });
    let s = 4.0;
    let mesh = doc.triangles(&[[-s, 0.0, s], [s, 0.0, s], [s, 0.0, -s], [-s, 0.0, -s]], &[[0.0, 1.0, 0.0]; 4], &[0, 1, 2, 0, 2, 3], Some(floor));
    let floor_node = doc.node(mesh_node(mesh));
    let camera = doc.root.push(perspective(90f32.to_radians()));
    let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let cam = doc.node(json::Node {
        camera: Some(camera),
        translation: Some([0.0, 3.0, 0.0]),
        rotation: Some(json::scene::UnitQuaternion(down.to_array())),
        ..Default::default()
    });
    let ext = doc.light(light);
    let l = doc.node(json::Node { extensions: ext, ..light_node });
    doc.scene(vec![floor_node, cam, l]);
    let path = scratch(test).join(format!("{test}.gltf"));
    doc.write_gltf(&path, Storage::External(Box::leak(format!("{test}.bin").into_boxed_str())));
    load_scene(&path).unwrap()
}

/// Where the ray through the centre of pixel (x, y) meets the floor y = 0.
fn floor_point(scene: &Scene, x: u32, y: u32, size: u32) -> Vec3 {
    let f = scene.camera.frame().unwrap();
    let d = f.ray_direction(x as f32 + 0.5, y as f32 + 0.5, size, size);
    f.origin + d * (-f.origin.y / d.y)
}

const SIZE: u32 = 32;

#[test]
fn point_light_falls_off_with_the_inverse_square_of_distance() {
    let scene = floor_scene("point", light(khr::Type::Point, 2.0, None), json::Node { translation: Some([0.0, 1.0, 0.0]), ..Default::default() });
    assert_eq!(scene.lights, vec![Light::Point { position: Vec3::Y, intensity: Vec3::splat(2.0) }]);
    let image = whitted_image(&scene, SIZE, SIZE);
    // Whitted: (Kd cos + Ks) I / d^2 (scene::Light; the glTF floor's Ks = 0.04 with Ns = 0 at
    // roughness 1, shaders/whitted.comp). Two pixels at different distances.
    let expect = |x: u32, y: u32| {
        let p = floor_point(&scene, x, y, SIZE);
        let to = Vec3::Y - p;
        (0.5 * to.normalize().y + 0.04) * 2.0 / to.length_squared()
    };
    let (near, far) = ((16, 16), (30, 16));
    let (gn, gf) = (image.get(near.0, near.1)[0], image.get(far.0, far.1)[0]);
    let (wn, wf) = (expect(near.0, near.1), expect(far.0, far.1));
    assert!(wn / wf > 4.0, "the test points are far enough apart ({wn} vs {wf})");
    assert!(((gn / gf) / (wn / wf) - 1.0).abs() < 0.02, "ratio near/far {} want {}", gn / gf, wn / wf);
    assert!((gn / wn - 1.0).abs() < 0.02, "near value {gn} want {wn}");
}

#[test]
fn spot_light_lights_its_inner_cone_fades_to_its_outer_cone_and_is_dark_outside() {
    let (inner, outer) = (20f32.to_radians(), 40f32.to_radians());
    let spot = khr::Spot { inner_cone_angle: inner, outer_cone_angle: outer };
    // The light shines down its node's -z: rotate -z onto -y.
    let down = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2);
    let node = json::Node { translation: Some([0.0, 1.0, 0.0]), rotation: Some(json::scene::UnitQuaternion(down.to_array())), ..Default::default() };
    let scene = floor_scene("spot", light(khr::Type::Spot, 3.0, Some(spot)), node);
    let Light::Cone { direction, cos_inner, cos_outer, .. } = scene.lights[0] else { panic!("not a cone light: {:?}", scene.lights) };
    assert_near("spot direction", direction, -Vec3::Y);
    assert!((cos_inner - inner.cos()).abs() < 1e-6 && (cos_outer - outer.cos()).abs() < 1e-6);
    let image = whitted_image(&scene, SIZE, SIZE);
    let angle_and_expect = |x: u32| {
        let p = floor_point(&scene, x, 16, SIZE);
        let to = Vec3::Y - p;
        let cos = to.normalize().y;
        let ramp = ((cos - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        // Whitted's reading of the glTF floor (shaders/whitted.comp): Kd = 0.5 and, at roughness
        // 1, a Blinn-Phong term Ks = 0.04 with Ns = 0, so Kd cos + 0.04 times the irradiance I f / d^2.
        let e = 3.0 * ramp * ramp / to.length_squared();
        (cos.acos().to_degrees(), (0.5 * cos + 0.04) * e, 0.5 * cos * e)
    };
    // Pixel columns whose floor points are inside, between and outside the cones.
    let mut seen = [false; 3];
    for x in 16..SIZE {
        let (deg, want, _) = angle_and_expect(x);
        let got = image.get(x, 16)[0];
        if deg < 20.0 {
            seen[0] = true;
            assert!(got > 0.0 && (got / want - 1.0).abs() < 0.02, "inside at {deg} degrees: {got}, want {want}");
        } else if deg > 20.5 && deg < 39.5 {
            seen[1] = true;
            assert!((got - want).abs() < 0.02 * want + 1e-4, "between at {deg} degrees: {got}, want {want}");
        } else if deg > 40.0 {
            seen[2] = true;
            assert_eq!(got, 0.0, "outside at {deg} degrees");
        }
    }
    assert_eq!(seen, [true; 3], "the row crosses all three zones");

    // The path tracer: radiance Kd / pi * E with E = I f cos / d^2 (next-event estimation of the
    // one delta light; everything else escapes to a black sky).
    let acc = common::render_path(&scene, &common::path_settings(SIZE, SIZE, 16));
    let img = acc.image();
    for x in [17u32, 24, 31] {
        let (deg, _, want) = angle_and_expect(x);
        let got = img.get(x, 16)[0];
        let want = want / std::f32::consts::PI;
        assert!((got - want).abs() <= 0.05 * want + 2e-3, "path tracer at {deg} degrees: {got}, want {want}");
    }
}

#[test]
fn directional_light_shines_along_its_node_minus_z() {
    // Tilted 60 degrees from the vertical: E cos = 2 * 0.5 on the floor.
    let tilt = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2 + 60f32.to_radians());
    let node = json::Node { rotation: Some(json::scene::UnitQuaternion(tilt.to_array())), ..Default::default() };
    let scene = floor_scene("directional", light(khr::Type::Directional, 2.0, None), node);
    let Light::Directional { direction, .. } = scene.lights[0] else { panic!("{:?}", scene.lights) };
    assert!((direction.y - 0.5).abs() < 1e-5, "toward the light, 60 degrees from the normal: {direction}");
    let image = whitted_image(&scene, SIZE, SIZE);
    let got = image.get(16, 16)[0];
    // Whitted's glTF floor: Kd E cos plus the roughness-1 Blinn-Phong term Ks E = 0.04 * 2.
    assert!((got - (0.5 * 2.0 * 0.5 + 0.04 * 2.0)).abs() < 1e-3, "Kd * E * cos + Ks * E: {got}");
}

#[test]
fn a_file_without_lights_gets_the_default_light_of_a_bare_obj() {
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    doc.scene_with_mesh(mesh);
    let dir = scratch("unlit");
    doc.write_gltf(&dir.join("unlit.gltf"), Storage::External("unlit.bin"));
    std::fs::write(dir.join("unlit.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n").unwrap();
    let gltf = load_scene(&dir.join("unlit.gltf")).unwrap();
    let obj = load_scene(&dir.join("unlit.obj")).unwrap();
    assert_eq!(gltf.lights.len(), 1);
    assert_eq!(gltf.lights, obj.lights);
    // Recorded, so that --envmap replaces it (tests/cli.rs) as it does the OBJ's.
    assert!(gltf.stats.default_light && obj.stats.default_light);
    assert_eq!(gltf.ambient, obj.ambient);
    assert_eq!(gltf.camera, obj.camera);
    // The primitive has no material: the spec's default (white, metallic 1, roughness 1).
    let m = &gltf.materials[gltf.triangles[0].material as usize];
    assert_eq!(m.diffuse, Vec3::ONE);
    assert_eq!(m.metallic_roughness.map(|mr| (mr.metallic, mr.roughness)), Some((1.0, 1.0)));
}

#[test]
fn tangents_are_kept_per_triangle_and_flip_handedness_when_mirrored() {
    let mut doc = Doc::new();
    let tex = doc.png_texture(&png(1, 1, &[[128, 128, 255, 255]]));
    let m = doc.material(json::Material {
        normal_texture: Some(json::material::NormalTexture { index: tex, scale: 0.5, tex_coord: 0, extensions: None, extras: Default::default() }),
        ..Default::default()
    });
    let with = quad_doc(&mut doc, Some(m), true);
    let without = quad_doc(&mut doc, Some(m), false);
    let a = doc.node(mesh_node(with));
    let b = doc.node(json::Node { scale: Some([-1.0, 1.0, 1.0]), translation: Some([5.0, 0.0, 0.0]), ..mesh_node(with) });
    let c = doc.node(json::Node { translation: Some([0.0, 5.0, 0.0]), ..mesh_node(without) });
    doc.scene(vec![a, b, c]);
    let path = scratch("tangents").join("tangents.glb");
    doc.write_glb(&path);
    let loaded = load_scene(&path).unwrap();
    // The quad placed twice is an instance group, its tangents kept once in object space.
    assert_eq!((loaded.triangles.len(), loaded.instances.len()), (2, 1));
    assert_eq!(loaded.instances[0].tangents.len(), 2);
    // Placed: the quad placed once first, then the two copies.
    let scene = loaded.expanded().unwrap();
    assert_eq!(scene.triangles.len(), 6);
    assert_eq!(scene.tangents.len(), scene.triangles.len(), "one tangent triple per triangle");
    assert_eq!(scene.materials[0].normal_texture, Some(0));
    assert_eq!(scene.materials[0].normal_scale, 0.5);
    for t in &scene.tangents[2..4] {
        assert!(t.iter().all(|t| t.abs_diff_eq(Vec4::new(1.0, 0.0, 0.0, 1.0), 1e-6)), "{t:?}");
    }
    for t in &scene.tangents[4..6] {
        assert!(t.iter().all(|t| t.abs_diff_eq(Vec4::new(-1.0, 0.0, 0.0, -1.0), 1e-6)), "mirrored: {t:?}");
    }
    // Without TANGENT in the file, MikkTSpace (scene::tangents) fills them in: unit, with a sign.
    assert!(scene.tangents[..2].iter().flatten().all(|t| (t.truncate().length() - 1.0).abs() < 1e-4 && t.w.abs() == 1.0), "no TANGENT: MikkTSpace's");

    // Without a normal map, no tangents at all.
    let mut doc = Doc::new();
    let mesh = quad_doc(&mut doc, None, true);
    doc.scene_with_mesh(mesh);
    let path = scratch("tangents").join("plain.glb");
    doc.write_glb(&path);
    assert!(load_scene(&path).unwrap().tangents.is_empty());
}

/// Loads `path` through the library and the CLI: both fail, naming the file and `location`.
fn assert_fails_naming(path: &Path, location: &str, words: &str) {
    let e = format!("{:#}", load_scene(path).expect_err("the file must not load"));
    assert!(e.contains(&path.display().to_string()) && e.contains(location) && e.contains(words), "{e}");
    let out = path.with_extension("png");
    let o = vkrt(&["render", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "--width", "4", "--height", "4"]);
    assert!(!o.status.success(), "the CLI must fail");
    let err = stderr(&o);
    assert!(err.contains(location) && err.contains(words) && !err.contains("panicked"), "{err}");
}

#[test]
fn unsupported_mode_required_extension_and_missing_bin_are_errors_naming_file_and_location() {
    let dir = scratch("errors");
    // A LINES primitive, as the second primitive of mesh 0.
    let mut doc = Doc::new();
    let p = doc.vec3(&TRI);
    let tris = doc.primitive(&[(json::mesh::Semantic::Positions, p)], None, None, json::mesh::Mode::Triangles);
    let lines = doc.primitive(&[(json::mesh::Semantic::Positions, p)], None, None, json::mesh::Mode::Lines);
    let mesh = doc.mesh(vec![tris, lines]);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("lines.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("lines.gltf"), "meshes[0].primitives[1]", "LINES");

    // A required extension vkrt does not have.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    doc.scene_with_mesh(mesh);
    doc.root.extensions_used = vec!["KHR_draco_mesh_compression".into()];
    doc.root.extensions_required = vec!["KHR_draco_mesh_compression".into()];
    doc.write_gltf(&dir.join("draco.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("draco.gltf"), "extensionsRequired[0]", "KHR_draco_mesh_compression");

    // The same extension only used: one warning, and the file loads.
    doc.root.extensions_required.clear();
    doc.write_gltf(&dir.join("draco_optional.gltf"), Storage::DataUri);
    let scene = load_scene(&dir.join("draco_optional.gltf")).unwrap();
    let warnings: Vec<&String> = scene.stats.warnings.iter().filter(|w| w.contains("KHR_draco_mesh_compression")).collect();
    assert_eq!(warnings.len(), 1, "{:?}", scene.stats.warnings);
    assert!(warnings[0].contains("extensionsUsed[0]"));

    // An image `image` cannot decode, in an external file.
    let mut doc = Doc::new();
    let image = doc.root.push(json::Image {
        buffer_view: None,
        mime_type: None,
        name: Some("broken".into()),
        uri: Some("broken.png".into()),
        extensions: None,
        extras: Default::default(),
    });
    let tex = doc.root.push(json::Texture { name: None, sampler: None, source: image, extensions: None, extras: Default::default() });
    let m = textured_material(&mut doc, tex);
    let mesh = quad_doc(&mut doc, Some(m), false);
    doc.scene_with_mesh(mesh);
    std::fs::write(dir.join("broken.png"), b"not an image at all").unwrap();
    doc.write_gltf(&dir.join("broken_image.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("broken_image.gltf"), "images[0]", "broken.png");

    // A .bin that is not there.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("nobin.gltf"), Storage::External("nobin.bin"));
    std::fs::remove_file(dir.join("nobin.bin")).unwrap();
    assert_fails_naming(&dir.join("nobin.gltf"), "buffers[0]", "nobin.bin");
}

/// Files the gltf crate (1.4.1) would panic on, found by fuzzing (fuzz/regressions/gltf/):
/// each is an error naming the file and the primitive instead.
#[test]
fn files_the_gltf_crate_would_panic_on_are_errors_naming_file_and_location() {
    use json::accessor::{ComponentType, GenericComponentType};
    use json::mesh::Semantic;
    let dir = scratch("panics");
    let component = |doc: &mut Doc, a: json::Index<json::Accessor>, t: ComponentType| {
        doc.root.accessors[a.value()].component_type = Valid(GenericComponentType(t));
    };

    // POSITION names an accessor past the end (the crate's validator indexes it unchecked).
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    doc.scene_with_mesh(mesh);
    doc.root.meshes[0].primitives[0].attributes.insert(Valid(Semantic::Positions), json::Index::new(99));
    doc.write_gltf(&dir.join("position.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("position.gltf"), "meshes[0].primitives[0].attributes.POSITION", "accessor 99 does not exist");

    // Indices stored as floats (the crate's index reader knows unsigned integers only).
    let mut doc = Doc::new();
    let p = doc.vec3(&TRI);
    let i = doc.indices(&[0, 1, 2]);
    component(&mut doc, i, ComponentType::F32);
    let prim = doc.primitive(&[(Semantic::Positions, p)], Some(i), None, json::mesh::Mode::Triangles);
    let mesh = doc.mesh(vec![prim]);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("float_indices.gltf"), Storage::DataUri);
    assert_fails_naming(
        &dir.join("float_indices.gltf"),
        "meshes[0].primitives[0]",
        "indices accessor 1 is FLOAT, not UNSIGNED_BYTE or UNSIGNED_SHORT or UNSIGNED_INT",
    );

    // Texture coordinates as signed bytes (the crate's reader knows FLOAT and unsigned only).
    let mut doc = Doc::new();
    let mesh = quad_doc(&mut doc, None, false);
    let uv = doc.root.meshes[mesh.value()].primitives[0].attributes[&Valid(Semantic::TexCoords(0))];
    component(&mut doc, uv, ComponentType::I8);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("byte_uvs.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("byte_uvs.gltf"), "meshes[0].primitives[0]", "TEXCOORD_0 accessor 2 is BYTE, not FLOAT or UNSIGNED_BYTE or UNSIGNED_SHORT");

    // Texture coordinates with three components.
    let mut doc = Doc::new();
    let p = doc.vec3(&TRI);
    let uv = doc.vec3(&TRI);
    let prim = doc.primitive(&[(Semantic::Positions, p), (Semantic::TexCoords(0), uv)], None, None, json::mesh::Mode::Triangles);
    let mesh = doc.mesh(vec![prim]);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("vec3_uvs.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("vec3_uvs.gltf"), "meshes[0].primitives[0]", "TEXCOORD_0 accessor 1 is Vec3, not Vec2");

    // An image in a buffer view without the mimeType the spec requires there.
    let mut doc = Doc::new();
    let view = doc.view(&png(1, 1, &[[255, 0, 0, 255]]));
    let image = doc.root.push(json::Image { buffer_view: Some(view), mime_type: None, name: None, uri: None, extensions: None, extras: Default::default() });
    let tex = doc.root.push(json::Texture { name: None, sampler: None, source: image, extensions: None, extras: Default::default() });
    let m = textured_material(&mut doc, tex);
    let mesh = quad_doc(&mut doc, Some(m), false);
    doc.scene_with_mesh(mesh);
    doc.write_gltf(&dir.join("no_mime.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("no_mime.gltf"), "images[0]", "no mimeType");
    doc.root.images[0].buffer_view = None;
    doc.write_gltf(&dir.join("no_source.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("no_source.gltf"), "images[0]", "neither a uri nor a bufferView");

    // Sizes the crate computes unchecked: an accessor of no elements, a sparse block of none,
    // elements past their buffer view's end, a view past its buffer's.
    let sized = |name: &str, edit: &dyn Fn(&mut Doc)| {
        let mut doc = Doc::new();
        let p = doc.vec3_sparse(3, Some(&TRI), &[1], &[[2.0, 0.0, 0.0]]);
        let prim = doc.primitive(&[(Semantic::Positions, p)], None, None, json::mesh::Mode::Triangles);
        let mesh = doc.mesh(vec![prim]);
        doc.scene_with_mesh(mesh);
        edit(&mut doc);
        let path = dir.join(name);
        doc.write_gltf(&path, Storage::DataUri);
        path
    };
    let path = sized("count_0.gltf", &|doc| doc.root.accessors[0].count = json::validation::USize64(0));
    assert_fails_naming(&path, "accessors[0]", "count is 0");
    let path = sized("sparse_0.gltf", &|doc| doc.root.accessors[0].sparse.as_mut().unwrap().count = json::validation::USize64(0));
    assert_fails_naming(&path, "accessors[0].sparse", "count is 0");
    let path = sized("huge_count.gltf", &|doc| doc.root.accessors[0].count = json::validation::USize64(u64::MAX / 4));
    assert_fails_naming(&path, "accessors[0]", "lie outside bufferView 0's 36 bytes");
    let path = sized("long_view.gltf", &|doc| doc.root.buffer_views[2].byte_length = json::validation::USize64(1 << 40));
    assert_fails_naming(&path, "bufferViews[2]", "lie outside buffer 0");
    assert!(load_scene(&sized("sparse_ok.gltf", &|_| ())).is_ok(), "the unedited file loads");

    // A GLB header whose total length is shorter than the header (the crate subtracts unchecked).
    let glb = dir.join("short_header.glb");
    std::fs::write(&glb, [&b"glTF"[..], &2u32.to_le_bytes(), &4u32.to_le_bytes(), &[0u8; 20]].concat()).unwrap();
    assert_fails_naming(&glb, "GLB container", "length of 4 bytes, less than the header's own 12");
}

/// The README's glTF scene (scenes/gltf/showcase.gltf, tools/make_gltf_showcase.py) loads with
/// every feature it was made to show, and both integrators see the file's camera: the red
/// sphere red and the gold sphere gold where the camera puts them.
#[test]
fn the_readme_showcase_loads_with_its_features_and_renders_in_both_integrators() {
    use vkrt::prepare::features::{self, Features};
    let scene = load_scene(&common::repo_path("scenes/gltf/showcase.gltf")).unwrap();
    assert!(!scene.stats.default_light, "the file has lights of its own");
    assert_eq!(scene.lights.len(), 3, "spot, point and directional");
    let f = Features::of(&scene);
    for on in
        [features::TEXTURES, features::METALLIC_ROUGHNESS, features::NORMAL_MAP, features::EMITTERS, features::POINT, features::DIRECTIONAL, features::CONE]
    {
        assert!(f.has(on), "{} is off:\n{}", on.name, f.report());
    }
    assert_near("camera eye", scene.camera.eye, Vec3::new(0.0, 1.5, 4.2));
    // Pixel centres on the spheres in a 64 x 48 image of the file's camera (the README's
    // 640 x 480 view: the red sphere's centre near (365, 285), and the gold sphere's lower half,
    // which mirrors the lit floor, near (190, 300)).
    let (red, gold) = ((36, 28), (19, 30));
    let whitted = whitted_image(&scene, 64, 48);
    let mut settings = common::path_settings(64, 48, 16);
    settings.max_depth = Some(4);
    let path = common::render_path(&scene, &settings).image();
    for (name, image) in [("Whitted", &whitted), ("path", &path)] {
        let r = image.get(red.0, red.1);
        assert!(r[0] > 3.0 * r[1] && r[0] > 3.0 * r[2], "{name}: the red sphere is {r:?}");
        let g = image.get(gold.0, gold.1);
        assert!(g[0] > g[2] && g[1] > g[2], "{name}: the gold sphere is {g:?}");
    }
}

/// Node hierarchies that are not the strict trees glTF 2.0 asks for (section 3.5.1), and one
/// that is but is very deep (issue 44): each bad one is an error naming the node before any
/// mesh is placed, and the deep one loads.
#[test]
fn node_hierarchies_that_are_not_trees_are_errors_and_any_depth_loads() {
    let dir = scratch("hierarchies");
    // A legal chain of 100,000 nodes, each the only child of the one before, the mesh at its
    // end: it used to overflow the thread's stack (SIGABRT).
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    const DEPTH: usize = 100_000;
    let mut below = doc.node(json::Node { translation: Some([0.0, 0.0, 1.0]), ..mesh_node(mesh) });
    for _ in 1..DEPTH {
        below = doc.node(json::Node { translation: Some([0.0, 0.0, 1.0]), children: Some(vec![below]), ..Default::default() });
    }
    doc.scene(vec![below]);
    doc.write_gltf(&dir.join("chain.gltf"), Storage::External("chain.bin"));
    let scene = load_scene(&dir.join("chain.gltf")).expect("a deep chain loads");
    assert_eq!(scene.triangles.len(), 1);
    assert_near("the chain's sum of translations", scene.triangles[0].p[0], Vec3::new(0.0, 0.0, DEPTH as f32));

    // 40 nodes, each listing the next one twice: 2^40 paths to the mesh. Refused at once.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let mut below = doc.node(mesh_node(mesh));
    for _ in 0..40 {
        below = doc.node(json::Node { children: Some(vec![below, below]), ..Default::default() });
    }
    doc.scene(vec![below]);
    doc.write_gltf(&dir.join("doubled.gltf"), Storage::DataUri);
    let started = std::time::Instant::now();
    assert_fails_naming(&dir.join("doubled.gltf"), "nodes[1].children[1]", "nodes[0] would have two parents (lists it twice)");
    assert!(started.elapsed().as_secs() < 30, "the check comes before any expansion");

    // A node under two different parents.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let shared = doc.node(mesh_node(mesh));
    let a = doc.node(json::Node { children: Some(vec![shared]), ..Default::default() });
    let b = doc.node(json::Node { children: Some(vec![shared]), ..Default::default() });
    doc.scene(vec![a, b]);
    doc.write_gltf(&dir.join("two_parents.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("two_parents.gltf"), "nodes[2].children[0]", "nodes[0] would have two parents (nodes[1] lists it too)");

    // A cycle outside the scene's tree: nodes 1 and 2 are each other's child.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let shown = doc.node(mesh_node(mesh));
    doc.node(json::Node { children: Some(vec![json::Index::new(2)]), ..Default::default() });
    doc.node(json::Node { children: Some(vec![json::Index::new(1)]), ..Default::default() });
    doc.scene(vec![shown]);
    doc.write_gltf(&dir.join("cycle.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("cycle.gltf"), "nodes[", "is its own ancestor");

    // A scene root that is another node's child.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let child = doc.node(mesh_node(mesh));
    let parent = doc.node(json::Node { children: Some(vec![child]), ..Default::default() });
    doc.scene(vec![parent, child]);
    doc.write_gltf(&dir.join("child_root.gltf"), Storage::DataUri);
    assert_fails_naming(&dir.join("child_root.gltf"), "scenes[0].nodes[1]", "nodes[1] has it as a child");
}

/// A camera the loader cannot use is an error at its JSON location (issue 44), not a message
/// about `--eye` that names neither the file nor the field.
#[test]
fn a_zero_field_of_view_is_an_error_naming_the_camera_field() {
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let tri = doc.node(mesh_node(mesh));
    let camera = doc.root.push(perspective(0.0));
    let eye = doc.node(json::Node { camera: Some(camera), translation: Some([0.0, 0.0, 4.0]), ..Default::default() });
    doc.scene(vec![tri, eye]);
    let path = scratch("camera_errors").join("yfov0.gltf");
    doc.write_gltf(&path, Storage::DataUri);
    assert_fails_naming(&path, "cameras[0].perspective.yfov", "0 radians is outside (0, pi)");
}

/// A mesh of 2^20 - 2 (degenerate) triangles in a 4 MB strip.
fn million_triangle_strip(doc: &mut Doc) -> json::Index<json::Mesh> {
    use json::mesh::{Mode, Semantic};
    let p = doc.vec3(&TRI);
    let strip = doc.indices(&vec![0u32; 1 << 20]);
    let prim = doc.primitive(&[(Semantic::Positions, p)], Some(strip), None, Mode::TriangleStrip);
    doc.mesh(vec![prim])
}

/// A file that places one large mesh so many times that its triangles, every copy counted,
/// pass what a primitive id names is refused with the count before anything is read: 4100
/// placements of a million-triangle strip (a 4 MB file). (Instances are not copied, so fewer
/// placements load.)
#[test]
fn a_file_that_places_too_many_triangles_is_refused_with_the_count() {
    let mut doc = Doc::new();
    let mesh = million_triangle_strip(&mut doc);
    let nodes: Vec<_> = (0..4100).map(|_| doc.node(mesh_node(mesh))).collect();
    doc.scene(nodes);
    let path = scratch("placed_triangles").join("many.gltf");
    doc.write_gltf(&path, Storage::External("many.bin"));
    let count = 4100 * ((1u64 << 20) - 2);
    assert_fails_naming(&path, "nodes", &format!("places 4100 meshes with {count} triangles in all"));
}

/// A node with `EXT_mesh_gpu_instancing` attributes (accessor indices by name).
fn instancing_node(mesh: json::Index<json::Mesh>, attributes: serde_json::Value) -> json::Node {
    let mut others = serde_json::Map::new();
    others.insert("EXT_mesh_gpu_instancing".into(), serde_json::json!({ "attributes": attributes }));
    json::Node { translation: Some([0.0, 0.0, 5.0]), extensions: Some(json::extensions::scene::Node { others, ..Default::default() }), ..mesh_node(mesh) }
}

#[test]
fn ext_mesh_gpu_instancing_draws_the_mesh_once_per_instance_as_child_nodes_would() {
    let turn = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2).to_array();
    let translations = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]];
    let rotations = [[0.0, 0.0, 0.0, 1.0], turn, [0.0, 0.0, 0.0, 1.0]];
    let scales = [[1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [1.0, -1.0, 1.0]];
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let (t, r, s) = (doc.vec3(&translations), doc.vec4(&rotations), doc.vec3(&scales));
    let attributes = serde_json::json!({ "TRANSLATION": t.value(), "ROTATION": r.value(), "SCALE": s.value() });
    let node = doc.node(instancing_node(mesh, attributes));
    doc.scene(vec![node]);
    doc.root.extensions_used.push("EXT_mesh_gpu_instancing".into());
    let dir = scratch("gpu_instancing");
    doc.write_gltf(&dir.join("instanced.gltf"), Storage::External("instanced.bin"));
    let instanced = load_scene(&dir.join("instanced.gltf")).unwrap();
    assert!(instanced.stats.warnings.is_empty(), "{:?}", instanced.stats.warnings);

    // The same three placements as children of a node at z = 5.
    let mut doc = Doc::new();
    let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
    let children: Vec<_> = (0..3)
        .map(|i| {
            doc.node(json::Node {
                translation: Some(translations[i]),
                rotation: Some(json::scene::UnitQuaternion(rotations[i])),
                scale: Some(scales[i]),
                ..mesh_node(mesh)
            })
        })
        .collect();
    let parent = doc.node(json::Node { translation: Some([0.0, 0.0, 5.0]), children: Some(children), ..Default::default() });
    doc.scene(vec![parent]);
    doc.write_gltf(&dir.join("expanded.gltf"), Storage::External("expanded.bin"));
    let expanded = load_scene(&dir.join("expanded.gltf")).unwrap();

    // Both are one instance group of three copies, traced as such.
    for scene in [&instanced, &expanded] {
        assert_eq!(scene.instances.iter().map(|g| g.placements.len()).collect::<Vec<_>>(), vec![3]);
        every_copy_is_hit_through_the_two_level_bvh(scene);
    }
    let (instanced, expanded) = (instanced.expanded().unwrap(), expanded.expanded().unwrap());
    assert_eq!(instanced.triangles.len(), 3);
    assert_eq!(expanded.triangles.len(), 3);
    for (a, b) in instanced.triangles.iter().zip(&expanded.triangles) {
        for k in 0..3 {
            assert_near("position", a.p[k], b.p[k]);
            assert_near("normal", a.n.unwrap()[k], b.n.unwrap()[k]);
        }
        // Front faces stay out, the mirrored copy's too.
        assert!(a.cross().dot(a.n.unwrap()[0]) > 0.0, "{a:?}");
    }
    // The turned, doubled copy: (1, 0, 0) -> (0, 2, 0), then moved by (10, 0, 5).
    assert_near("turned copy", instanced.triangles[1].p[1], Vec3::new(10.0, 2.0, 5.0));
}

#[test]
fn bad_ext_mesh_gpu_instancing_is_an_error_naming_the_attribute() {
    let dir = scratch("gpu_instancing_errors");
    let at = "nodes[0].extensions.EXT_mesh_gpu_instancing.attributes";
    type Attributes<'a> = &'a dyn Fn(&mut Doc) -> serde_json::Value;
    let cases: [(&str, Attributes, String, &str); 4] = [
        ("rotation_vec3", &|d: &mut Doc| serde_json::json!({ "ROTATION": d.vec3(&[[0.0; 3]; 2]).value() }), format!("{at}.ROTATION"), "FLOAT VEC4"),
        (
            "counts",
            &|d: &mut Doc| serde_json::json!({ "TRANSLATION": d.vec3(&[[0.0; 3]; 2]).value(), "SCALE": d.vec3(&[[1.0; 3]; 3]).value() }),
            format!("{at}.TRANSLATION"),
            "one element per instance",
        ),
        ("missing_accessor", &|_: &mut Doc| serde_json::json!({ "TRANSLATION": 99 }), format!("{at}.TRANSLATION"), "accessor 99 does not exist"),
        ("zero_quaternion", &|d: &mut Doc| serde_json::json!({ "ROTATION": d.vec4(&[[0.0; 4]]).value() }), format!("{at}.ROTATION"), "not a rotation"),
    ];
    for (name, attributes, location, words) in cases {
        let mut doc = Doc::new();
        let mesh = doc.triangles(&TRI, &UP_Z, &[0, 1, 2], None);
        let attributes = attributes(&mut doc);
        let node = doc.node(instancing_node(mesh, attributes));
        doc.scene(vec![node]);
        let path = dir.join(format!("{name}.gltf"));
        doc.write_gltf(&path, Storage::External("b.bin"));
        assert_fails_naming(&path, &location, words);
    }
}

#[test]
fn instance_counts_are_in_the_placed_triangle_bound() {
    let mut doc = Doc::new();
    let mesh = million_triangle_strip(&mut doc);
    let t = doc.vec3(&vec![[0.0; 3]; 4100]);
    let node = doc.node(instancing_node(mesh, serde_json::json!({ "TRANSLATION": t.value() })));
    doc.scene(vec![node]);
    let path = scratch("instanced_triangles").join("many.gltf");
    doc.write_gltf(&path, Storage::External("many.bin"));
    let count = 4100 * ((1u64 << 20) - 2);
    assert_fails_naming(&path, "nodes", &format!("places 4100 meshes with {count} triangles in all"));
}
