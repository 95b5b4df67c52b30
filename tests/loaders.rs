//! Scene loaders: the real scenes load with the expected counts, cameras, lights and materials;
//! bad files fail with an error that names the file and the line or key, and never panic.

mod common;

use std::path::{Path, PathBuf};

use common::procedural;
use glam::Vec3;
use vkrt::error::InputError;
use vkrt::scene::{load_scene, Camera, Light, Scene};

/// A scene kept in this repository (`scenes/`).
fn repo(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes")).join(rel)
}

/// A scene from the shared folder beside the repository (always present in CI).
fn shared(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenes")).join(rel)
}

/// Writes `files` into a fresh folder of its own (tests run in parallel) and returns the path
/// of the first one.
fn write_files(test: &str, files: &[(&str, &[u8])]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("loaders").join(test);
    let _ = std::fs::remove_dir_all(&dir);
    for (name, contents) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, contents).unwrap();
    }
    dir.join(files[0].0)
}

fn load(path: &Path) -> Scene {
    load_scene(path).unwrap_or_else(|e| panic!("{}: {e:#}", path.display()))
}

/// Loads a file that must fail; returns the whole error chain as text and the InputError in it.
fn load_err(path: &Path) -> (String, InputError) {
    let err = match load_scene(path) {
        Ok(s) => panic!("{} loaded ({} triangles) but should fail", path.display(), s.triangles.len()),
        Err(e) => e,
    };
    let text = format!("{err:#}");
    let input = err.chain().find_map(|c| c.downcast_ref::<InputError>()).unwrap_or_else(|| panic!("no InputError in: {text}")).clone();
    (text, input)
}

/// The error names `file` (by file name) and `location` (`line 3`, `key Lights[0].Position`).
fn assert_located(path: &Path, location: &str) -> String {
    let (text, _) = load_err(path);
    let name = path.file_name().unwrap().to_str().unwrap();
    assert!(text.contains(name), "error does not name {name}: {text}");
    assert!(text.contains(location), "error does not say '{location}': {text}");
    text
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-5 * (1.0 + b.abs().max_element())
}

fn material_named<'a>(scene: &'a Scene, name: &str) -> &'a vkrt::scene::Material {
    scene.materials.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("no material {name}"))
}

fn count_lights(scene: &Scene) -> [usize; 3] {
    let mut n = [0; 3];
    for l in &scene.lights {
        match l {
            Light::Point { .. } => n[0] += 1,
            Light::Directional { .. } => n[1] += 1,
            Light::Spot { .. } | Light::Cone { .. } => n[2] += 1,
        }
    }
    n
}

/// The light a scene without one gets: directional, from over the camera's shoulder.
fn assert_default_light(scene: &Scene) {
    let c = scene.camera;
    let expected = (c.up.normalize() + (c.eye - c.target).normalize()).normalize();
    match scene.lights.as_slice() {
        [Light::Directional { direction, intensity }] => {
            assert!(close(*direction, expected), "{direction} != {expected}");
            assert_eq!(*intensity, Vec3::ONE);
        }
        other => panic!("expected one default directional light, found {other:?}"),
    }
    assert_eq!(scene.ambient, Vec3::splat(0.05));
}

// ---------------------------------------------------------------- the lab scenes (YAML)

#[test]
fn lab_cornell_box() {
    let s = load(&repo("lab/cornell_box/cornell_box.yaml"));
    // wall 3 quads, left 1, right 1, each block 5 quads: 15 quads. (The light.obj in the folder
    // is not named by this YAML.)
    assert_eq!(s.triangles.len(), 30);
    assert_eq!(s.stats.dropped_degenerate, 0);
    assert!(s.stats.warnings.is_empty(), "{:?}", s.stats.warnings);
    assert_eq!(
        s.camera,
        Camera { eye: Vec3::new(278.0, 273.0, -800.0), target: Vec3::new(278.0, 273.0, 0.0), up: Vec3::Y, fov_y_deg: 39.307_648, ..Camera::default() }
    );
    assert_eq!(s.lights, vec![Light::Point { position: Vec3::new(278.0, 520.0, 279.5), intensity: Vec3::splat(100000.0) }]);
    assert_eq!(s.ambient, Vec3::splat(0.05));
    assert_eq!(s.materials.len(), 4);
    let bx = material_named(&s, "box");
    assert_eq!((bx.diffuse, bx.specular, bx.shininess), (Vec3::splat(0.5), Vec3::splat(0.4), 32.0));
    assert_eq!(material_named(&s, "left").diffuse, Vec3::new(0.5, 0.0, 0.0));
    assert!(s.emissive_triangles().is_empty());
    // Models in file order: wall.obj first, its first face `f 3//1 1//1 2//1 4//1`.
    assert_eq!(s.triangles[0].p, [Vec3::new(0.0, 0.0, 559.2), Vec3::new(549.6, 0.0, 559.2), Vec3::new(552.0, 0.0, 0.0)]);
    assert_eq!(s.triangles[0].n, Some([Vec3::Y; 3]));
    assert_eq!(s.triangles[0].material, 0);
    assert_eq!(s.triangles[29].material, 3);
}

#[test]
fn lab_box_ver_path_area_lights() {
    let s = load(&repo("lab/Box_ver_path/Box_ver_path.yaml"));
    // 32 from the meshes (light.obj adds 2), then one triangle per Area light.
    assert_eq!(s.triangles.len(), 34);
    assert_eq!(s.stats.dropped_degenerate, 0);
    assert!(s.lights.is_empty(), "area lights are triangles, not Light entries");
    assert_eq!(s.ambient, Vec3::splat(0.05));
    // light.obj (Emission material) and the two Area triangles.
    assert_eq!(s.emissive_triangles(), vec![0, 1, 32, 33]);
    assert_eq!(material_named(&s, "light").emission, Vec3::new(17.0, 12.0, 4.0));
    assert_eq!(material_named(&s, "box").shininess, 32.0);
    for (k, intensity) in [(32, 400.0), (33, 500.0)] {
        let t = &s.triangles[k];
        let m = &s.materials[t.material as usize];
        assert_eq!(m.emission, Vec3::splat(intensity));
        assert_eq!(m.diffuse, Vec3::ZERO);
        // Direction [0, -1, 0]: the emitting side faces down into the box.
        assert!(close(t.cross().normalize(), -Vec3::Y), "{}", t.cross());
    }
    // Both are given counter-clockwise seen from below, so they keep the file's vertex order.
    let y = 548.788_9;
    assert_eq!(s.triangles[32].p, [Vec3::new(343.0, y, 227.0), Vec3::new(343.0, y, 332.0), Vec3::new(213.0, y, 332.0)]);
    assert_eq!(s.triangles[33].p, [Vec3::new(343.0, y, 227.0), Vec3::new(213.0, y, 332.0), Vec3::new(213.0, y, 227.0)]);
}

#[test]
fn shared_lab_white_oak() {
    if common::skip_without_shared("shared_lab_white_oak") {
        return;
    }
    let s = load(&shared("lab/white_oak/white_oak.yaml"));
    assert_eq!(s.triangles.len() + s.stats.dropped_degenerate, 36_760);
    assert_eq!(s.triangles.len(), 36_760);
    assert_eq!(count_lights(&s), [0, 1, 0]);
    assert_eq!(s.camera.eye, Vec3::new(0.0, 500.0, 1100.0));
    // Materials from the MTL, textures resolved beside it and recorded (not yet used).
    assert_eq!(s.materials.len(), 4);
    let bark = material_named(&s, "WhiteOakBark");
    assert_eq!(bark.diffuse_map.as_deref(), Some(shared("lab/white_oak/T_WhiteOakBark_D.png").as_path()));
    assert_eq!((bark.diffuse, bark.specular, bark.shininess, bark.ior, bark.illum), (Vec3::splat(0.8), Vec3::splat(0.01), 10.0, 1.5, 2));
    let leaves = material_named(&s, "White_Oak_Leaves_Hero_3");
    assert!(leaves.alpha_map.as_ref().unwrap().ends_with("T_White_Oak_Leaves_Hero_3_A.png"));
    // The MTL's map_d files were never shipped: the diffuse texture's alpha cuts the leaves out.
    let texture_warnings = s.stats.warnings.iter().filter(|w| w.contains("_A.png not found")).count();
    assert_eq!(texture_warnings, 1, "{:?}", s.stats.warnings);
    assert!(leaves.alpha_texture.is_some() && leaves.alpha_texture == leaves.diffuse_texture);
    assert!(material_named(&s, "White_Oak_Leaves_Hero_1").alpha_texture.is_some());
    assert_eq!(bark.alpha_texture, None, "the bark texture is opaque");
}

#[test]
fn shared_lab_bunny_scale_translation() {
    if common::skip_without_shared("shared_lab_bunny_scale_translation") {
        return;
    }
    let s = load(&shared("lab/bunny/bunny.yaml"));
    assert_eq!(s.triangles.len() + s.stats.dropped_degenerate, 69_451);
    assert_eq!(s.lights, vec![Light::Directional { direction: Vec3::ONE.normalize(), intensity: Vec3::ONE }]);
    // The six sky-box faces, after the (no) material textures.
    assert!(matches!(s.sky, vkrt::scene::Sky::CubeMap { first_texture: 0, .. }), "{:?}", s.sky);
    assert_eq!(s.textures.len(), 6);
    assert!(s.textures[0].path.ends_with("rt.jpg") && s.textures[5].path.ends_with("bk.jpg"));
    assert_eq!(material_named(&s, "bunny").specular, Vec3::splat(0.4));
    assert_eq!(material_named(&s, "bunny").shininess, 32.0);
    // p' = 10 p + (0.1, -1, 0): compare with the raw OBJ.
    let raw = load(&shared("lab/bunny/bunny.obj"));
    let (a, b) = (s.bounds(), raw.bounds());
    assert!(close(a.min, b.min * 10.0 + Vec3::new(0.1, -1.0, 0.0)), "{:?} vs {:?}", a, b);
    assert!(close(a.max, b.max * 10.0 + Vec3::new(0.1, -1.0, 0.0)));
    assert!(s.triangles.iter().all(|t| t.n.map_or(true, |n| n.iter().all(|v| (v.length() - 1.0).abs() < 1e-5))));
}

#[test]
fn shared_lab_teapot_and_floor() {
    if common::skip_without_shared("shared_lab_teapot_and_floor") {
        return;
    }
    let t = load(&shared("lab/teapot/teapot.yaml"));
    assert_eq!(t.triangles.len() + t.stats.dropped_degenerate, 4_032);
    let m = material_named(&t, "teapot");
    assert_eq!((m.specular, m.shininess), (Vec3::splat(0.25), 64.0));
    assert_eq!(t.camera.eye, Vec3::new(0.0, 0.0, -80.0));

    let f = load(&shared("lab/floor/floor.yaml"));
    assert_eq!(f.triangles.len(), 2);
    assert_eq!(count_lights(&f), [1, 0, 0]);
    let wood = material_named(&f, "wood");
    assert_eq!(wood.diffuse_map.as_deref(), Some(shared("lab/floor/wood.png").as_path()));
    assert_eq!((wood.specular, wood.shininess), (Vec3::splat(0.3), 32.0));
    assert!(f.triangles.iter().all(|t| t.uv.is_some() && t.n.is_some()));
    assert_eq!(f.triangles[0].uv.unwrap()[0], glam::Vec2::new(10.0, -9.0));
}

#[test]
fn cornell_measured_yaml_and_obj() {
    let s = load(&repo("cornell-measured/cornell.yaml"));
    assert_eq!(s.triangles.len(), 32);
    assert_eq!(s.camera.fov_y_deg, 39.3077);
    assert!(s.lights.is_empty());
    assert_eq!(s.ambient, Vec3::ZERO, "an emitter, so no ambient");
    let lit = s.emissive_triangles();
    assert_eq!(lit.len(), 2);
    for &i in &lit {
        let t = &s.triangles[i as usize];
        assert_eq!(s.materials[t.material as usize].emission, Vec3::new(17.0, 12.0, 4.0));
        assert!(close(t.cross().normalize(), -Vec3::Y), "the light faces down");
    }
    assert_eq!(material_named(&s, "red").diffuse, Vec3::new(0.63, 0.065, 0.05));
    assert!(s.stats.warnings.is_empty(), "{:?}", s.stats.warnings);

    let o = load(&repo("cornell-measured/cornell.obj"));
    assert_eq!(o.triangles, s.triangles);
    assert!(o.lights.is_empty());
    assert_eq!(o.camera, Camera::framing(&o.bounds()));
}

// ---------------------------------------------------------------- shared OBJ scenes

#[test]
fn shared_cornell_box_variants_negative_indices_and_quads() {
    if common::skip_without_shared("shared_cornell_box_variants_negative_indices_and_quads") {
        return;
    }
    let expected = [
        ("Original", 36),
        ("Sphere", 2188),
        ("Glossy", 1112),
        ("Mirror", 36),
        ("Water", 7088),
        ("Empty-CO", 12),
        ("Empty-RG", 12),
        ("Empty-White", 12),
        ("Empty-Squashed", 12),
    ];
    for (variant, count) in expected {
        let path = shared(&format!("cornell-box/CornellBox-{variant}.obj"));
        let s = load(&path);
        assert_eq!(s.triangles.len() + s.stats.dropped_degenerate, count, "{variant}");
        assert!(!s.emissive_triangles().is_empty(), "{variant} has a light");
        assert!(s.lights.is_empty() && s.ambient == Vec3::ZERO, "{variant}: no default light");
    }
    let s = load(&shared("cornell-box/CornellBox-Original.obj"));
    assert_eq!(s.stats.dropped_degenerate, 0);
    // The floor `f -4 -3 -2 -1`, fan-triangulated: (a b c) (a c d).
    let [a, b, c, d] = [Vec3::new(-1.01, 0.0, 0.99), Vec3::new(1.0, 0.0, 0.99), Vec3::new(1.0, 0.0, -1.04), Vec3::new(-0.99, 0.0, -1.04)];
    assert_eq!(s.triangles[0].p, [a, b, c]);
    assert_eq!(s.triangles[1].p, [a, c, d]);
    assert_eq!(s.materials[s.triangles[0].material as usize].name, "floor");
    let light = material_named(&s, "light");
    assert_eq!((light.emission, light.diffuse), (Vec3::new(17.0, 12.0, 4.0), Vec3::splat(0.78)));
    assert_eq!(s.camera, Camera::framing(&s.bounds()));

    // Mirror: the tall box is `illum 5` with Ks 0.95.
    let m = load(&shared("cornell-box/CornellBox-Mirror.obj"));
    assert!(m.materials.iter().any(|m| m.is_mirror()));
}

#[test]
fn shared_embree_cornell_box_without_ke_gets_default_light() {
    if common::skip_without_shared("shared_embree_cornell_box_without_ke_gets_default_light") {
        return;
    }
    // Its `light` material has only `Ka 20 20 20`: no emitter, so the bare-OBJ light is added.
    let s = load(&shared("cornell-box-embree/cornell_box.obj"));
    assert_eq!(s.triangles.len() + s.stats.dropped_degenerate, 36);
    assert!(s.emissive_triangles().is_empty());
    assert_default_light(&s);
}

#[test]
fn shared_scanned_models_with_tr_are_not_transparent() {
    if common::skip_without_shared("shared_scanned_models_with_tr_are_not_transparent") {
        return;
    }
    // dragon.mtl has `Tr 1` next to `d 1`; Tr must not be read as transparency.
    let s = load(&shared("stanford-dragon-100k/dragon.obj"));
    assert_eq!(s.triangles.len() + s.stats.dropped_degenerate, 100_000);
    assert!(s.materials.iter().all(|m| m.dissolve == 1.0));
    assert_default_light(&s);
}

// ---------------------------------------------------------------- synthetic OBJ files

#[test]
fn bare_obj_gets_framing_camera_and_default_light() {
    let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    let path = write_files("bare_obj", &[("quad.obj", obj)]);
    let s = load(&path);
    assert_eq!(s.triangles.len(), 2);
    assert_eq!(s.materials.len(), 1);
    assert_eq!(s.triangles[0].material, 0);
    assert_eq!(s.camera, Camera::framing(&s.bounds()));
    assert_default_light(&s);
    assert!(s.triangles.iter().all(|t| t.n.is_none() && t.uv.is_none()));
    assert!(s.stats.warnings.is_empty(), "{:?}", s.stats.warnings);
}

#[test]
fn obj_normals_uvs_degenerates_comments_and_file_order() {
    let obj = b"\xEF\xBB\xBFmtllib sub/m.mtl # a BOM, and a comment on a data line\n\
        v 0 0 0 # origin\n\
        v 1 0 0\n\
        v 0 1 0\n\
        v 2 2 2 1 0 0\n\
        vn 0 0 2\n\
        vn 0 0 0\n\
        vt 0.5\n\
        vt 1 1 0\n\
        usemtl glow\n\
        f 1/1/1 2/2/1 3/1/1\n\
        f 1//2 2//1 3//1\n\
        f 1 2 -4\n\
        l 1 2 3\n\
        usemtl plain\n\
        f 3/2 2/2 1/1\n\
        f 3 2/2 1\n";
    let mtl = b"newmtl glow\nKe 1 2 3\nKd 0.5\nTr 1\nmap_Kd -s 2 2 2 tex.png\n\
        newmtl plain\nKd 0.1 0.2 0.3\nNs 20\nNi 1.33\nd 0.5\nillum 7\nmap_d alpha.png\n";
    let path = write_files("obj_features", &[("scene.obj", obj), ("sub/m.mtl", mtl)]);
    image::RgbaImage::new(1, 1).save(path.parent().unwrap().join("sub/tex.png")).unwrap();
    let s = load(&path);
    // `f 1 2 -4` repeats vertex 1 (-4 of 4): zero area, dropped. The `l` line is no face.
    assert_eq!(s.triangles.len(), 4);
    assert_eq!(s.stats.dropped_degenerate, 1);
    let t = &s.triangles;
    // Normals normalised; a zero normal drops the normals of that triangle only.
    assert_eq!(t[0].n, Some([Vec3::Z; 3]));
    assert_eq!(t[1].n, None);
    // `vt 0.5` reads as (0.5, 0).
    assert_eq!(t[0].uv, Some([glam::Vec2::new(0.5, 0.0), glam::Vec2::ONE, glam::Vec2::new(0.5, 0.0)]));
    // File order: the last two faces are clockwise copies of the first.
    assert_eq!(t[2].p, [Vec3::Y, Vec3::X, Vec3::ZERO]);
    assert!(t[2].uv.is_some() && t[2].n.is_none());
    assert!(t[3].uv.is_none(), "only some corners have uvs: none are trusted");
    let glow = &s.materials[t[0].material as usize];
    assert_eq!((glow.name.as_str(), glow.emission, glow.diffuse, glow.dissolve), ("glow", Vec3::new(1.0, 2.0, 3.0), Vec3::splat(0.5), 1.0));
    assert_eq!(glow.diffuse_map.as_deref(), Some(path.parent().unwrap().join("sub/tex.png").as_path()));
    let plain = &s.materials[t[2].material as usize];
    assert_eq!((plain.shininess, plain.ior, plain.dissolve, plain.illum), (20.0, 1.33, 0.5, 7));
    assert!(plain.is_dielectric());
    assert!(plain.alpha_map.as_ref().unwrap().ends_with("sub/alpha.png"));
    // An emitter: no default light.
    assert!(s.lights.is_empty() && s.ambient == Vec3::ZERO);
    let w = &s.stats.warnings;
    // map_d names a file that is not there: a warning, and the material stays opaque.
    assert_eq!(w.iter().filter(|w| w.contains("alpha.png not found")).count(), 1, "{w:?}");
    assert_eq!(plain.alpha_texture, None);
    assert!(glow.diffuse_texture.is_some());
    assert!(w.iter().any(|w| w.contains("polyline")), "{w:?}");
}

#[test]
fn obj_missing_mtl_warns_and_uses_default_material() {
    let obj = b"mtllib nowhere.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let path = write_files("missing_mtl", &[("a.obj", obj)]);
    let s = load(&path);
    assert_eq!(s.triangles.len(), 1);
    assert_eq!(s.materials[s.triangles[0].material as usize], vkrt::scene::Material::default());
    assert!(s.stats.warnings.iter().any(|w| w.contains("nowhere.mtl") && w.contains("line 1")), "{:?}", s.stats.warnings);
}

#[test]
fn obj_unknown_usemtl_warns() {
    let obj = b"mtllib m.mtl\nusemtl nosuch\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let path = write_files("unknown_usemtl", &[("a.obj", obj), ("m.mtl", b"newmtl other\nKd 1 0 0\n")]);
    let s = load(&path);
    assert_eq!(s.materials[s.triangles[0].material as usize].name, "default");
    assert!(s.stats.warnings.iter().any(|w| w.contains("line 2: usemtl nosuch")), "{:?}", s.stats.warnings);
}

// ---------------------------------------------------------------- bad OBJ files

/// Writes one bad OBJ file and checks the error names it and `location`.
fn bad_obj(test: &str, contents: &[u8], location: &str) -> String {
    let path = write_files(test, &[("bad.obj", contents)]);
    assert_located(&path, location)
}

#[test]
fn obj_empty_and_triangle_free_files() {
    let t = bad_obj("empty", b"", "bad.obj");
    assert!(t.contains("no triangles"), "{t}");
    let t = bad_obj("only_vertices", b"# nothing here\nv 0 0 0\nv 1 1 1\n", "no triangles");
    assert!(!t.contains("degenerate"), "{t}");
    let t = bad_obj("all_degenerate", b"v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n", "no triangles");
    assert!(t.contains("degenerate"), "{t}");
}

#[test]
fn obj_binary_and_wrong_encodings() {
    // A PNG's header after a vertex: its first control character (^Z) is on line 3. (Bytes
    // that are only not UTF-8 are read as Latin-1 instead: obj_names_in_latin1_still_match.)
    let t = bad_obj("garbage", b"v 0 0 0\n\x89PNG\r\n\x1a\n\x00\x00\xff\xfe", "line 3");
    assert!(t.contains("binary"), "{t}");
    // Valid UTF-8 but with NUL bytes.
    bad_obj("nul", b"v 0 0 0\nv 1 0 0\nv\x000 1 0\n", "line 3");
    // UTF-16 (little endian, with BOM), as Windows Notepad writes it.
    let utf16: Vec<u8> = "\u{feff}v 0 0 0\r\n".encode_utf16().flat_map(u16::to_le_bytes).collect();
    let t = bad_obj("utf16", &utf16, "line 1");
    assert!(t.contains("UTF-16"), "{t}");
}

#[test]
fn obj_bad_numbers() {
    let t = bad_obj("nan", b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n", "line 3");
    assert!(t.contains("NaN"), "{t}");
    bad_obj("inf", b"v 0 0 0\nv inf 0 0\n", "line 2");
    // 1e39 overflows f32 to inf.
    let t = bad_obj("huge", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e39\nf 1 2 3\n", "line 4");
    assert!(t.contains("1e39"), "{t}");
    bad_obj("word", b"v 0 0 0\nv 1 zero 0\n", "line 2");
    bad_obj("short_vertex", b"v 0 0\n", "line 1");
    bad_obj("bad_normal", b"vn 0 0 NaN\n", "line 1");
    bad_obj("short_normal", b"vn 0 1\n", "line 1");
    bad_obj("bad_uv", b"vt 0.5 x\n", "line 1");
    bad_obj("zero_w", b"v 1 1 1 0\n", "line 1");
}

#[test]
fn obj_bad_faces() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let t = bad_obj("index_high", format!("{tri}f 1 2 4\n").as_bytes(), "line 4");
    assert!(t.contains("out of range"), "{t}");
    let t = bad_obj("index_zero", format!("{tri}f 0 1 2\n").as_bytes(), "line 4");
    assert!(t.contains("index 0"), "{t}");
    bad_obj("index_negative", format!("{tri}f -1 -2 -4\n").as_bytes(), "line 4");
    // A relative index counts only the vertices defined so far.
    bad_obj("index_forward", format!("v 0 0 0\nf -1 2 3\n{tri}").as_bytes(), "line 2");
    bad_obj("normal_index", format!("{tri}vn 0 0 1\nf 1//1 2//2 3//1\n").as_bytes(), "line 5");
    bad_obj("uv_index_without_uvs", format!("{tri}f 1/1 2/1 3/1\n").as_bytes(), "line 4");
    bad_obj("two_vertices", format!("{tri}f 1 2\n").as_bytes(), "line 4");
    bad_obj("not_integer", format!("{tri}f 1 2 3.5\n").as_bytes(), "line 4");
    bad_obj("four_parts", format!("{tri}f 1/1/1/1 2 3\n").as_bytes(), "line 4");
    bad_obj("no_position", format!("{tri}f /1 2 3\n").as_bytes(), "line 4");
    bad_obj("huge_index", format!("{tri}f 1 2 99999999999999999999\n").as_bytes(), "line 4");
}

#[test]
fn bad_mtl_is_located_in_the_mtl() {
    let obj = b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n";
    let path = write_files("bad_mtl", &[("a.obj", obj), ("m.mtl", b"newmtl a\n\nKd 1 0\n")]);
    let (text, e) = load_err(&path);
    assert!(e.file.ends_with("m.mtl") && e.location.as_deref() == Some("line 3"), "{text}");
    let path = write_files("bad_mtl_nan", &[("a.obj", obj), ("m.mtl", b"newmtl a\nNs nan\n")]);
    let (_, e) = load_err(&path);
    assert_eq!(e.location.as_deref(), Some("line 2"));
}

// ---------------------------------------------------------------- YAML files

const TRI_OBJ: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";

/// Each case `(test, from, to, key, what)`: `yaml` with `from` replaced by `to` fails with an
/// error that names `key` and says `what`.
fn assert_edits_fail(yaml: &str, cases: &[(&str, &str, &str, &str, &str)]) {
    for &(test, from, to, key, what) in cases {
        let edited = yaml.replace(from, to);
        assert_ne!(edited, yaml, "{test}: nothing replaced");
        let text = assert_located(&yaml_scene(test, &edited), key);
        assert!(text.contains(what), "{test}: '{what}' not in: {text}");
    }
}

/// Writes a lab YAML scene with a one-triangle mesh beside it.
fn yaml_scene(test: &str, yaml: &str) -> PathBuf {
    write_files(test, &[("scene.yaml", yaml.as_bytes()), ("tri.obj", TRI_OBJ)])
}

const GOOD_YAML: &str = "\
Cameras:
  - Eye: [0, 0, 5]
    Target: [0, 0, 0]
    Up: [0, 1, 0]
    Fovy: 30
Lights:
  - Type: Point
    Position: [0, 2, 2]
    Intensity: [3, 3, 3]
  - Type: Spot
    Position: [0, 3, 0]
    Direction: [0, -2, 0]
    Intensity: [1, 2, 3]
    Length: 0.5
Materials:
  - Name: glass
    Blend: Transparent
    Diffuse: [0.9, 0.9, 0.9]
    Specular: [1, 1, 1, 100]
    Shininess: 50
Models:
  - Mesh: tri.obj
    Material: glass
    Scale: [2, -1, 1]
    Translation: [1, 1, 1]
";

#[test]
fn yaml_lights_materials_and_transforms() {
    let s = load(&yaml_scene("yaml_good", GOOD_YAML));
    assert!(s.stats.warnings.is_empty(), "{:?}", s.stats.warnings);
    assert_eq!(s.camera.fov_y_deg, 30.0);
    assert_eq!(s.lights[0], Light::Point { position: Vec3::new(0.0, 2.0, 2.0), intensity: Vec3::splat(3.0) });
    assert_eq!(s.lights[1], Light::Spot { position: Vec3::new(0.0, 3.0, 0.0), direction: -Vec3::Y, intensity: Vec3::new(1.0, 2.0, 3.0), radius: 0.5 });
    assert_eq!(s.ambient, Vec3::ZERO);
    let m = &s.materials[0];
    assert!(m.is_dielectric() && m.ior == 1.5);
    assert_eq!((m.diffuse, m.specular, m.shininess), (Vec3::splat(0.9), Vec3::ONE, 50.0), "Shininess wins over Specular[3]");
    // Scale [2, -1, 1] mirrors: positions move, and the winding is flipped back so that the
    // geometric normal still agrees with the shading normal.
    let t = &s.triangles[0];
    assert_eq!(t.p, [Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, 0.0, 1.0), Vec3::new(3.0, 1.0, 1.0)]);
    assert!(t.cross().dot(t.n.unwrap()[0]) > 0.0);
}

#[test]
fn yaml_area_light_is_wound_along_its_direction() {
    let yaml = "\
Lights:
  - Type: Area
    p0: [0, 2, 0]
    p1: [1, 2, 0]
    p2: [0, 2, 1]
    Direction: [0, 1, 0]
    Intensity: [5, 5, 5]
  - Type: Area
    p0: [0, 2, 0]
    p1: [1, 2, 0]
    p2: [0, 2, 1]
    Direction: [0, -1, 0]
    Intensity: [5, 5, 5]
Materials:
  - Name: m
Models:
  - Mesh: tri.obj
    Material: m
";
    let s = load(&yaml_scene("yaml_area", yaml));
    assert_eq!(s.triangles.len(), 3);
    // (p1-p0) x (p2-p0) = (1,0,0) x (0,0,1) = (0,-1,0): the first light had to be swapped.
    assert_eq!(s.triangles[1].cross().normalize(), Vec3::Y);
    assert_eq!(s.triangles[2].cross().normalize(), -Vec3::Y);
    assert_eq!(s.triangles[2].p, [Vec3::new(0.0, 2.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.0, 2.0, 1.0)]);
    assert_eq!(s.emissive_triangles(), vec![1, 2]);
    // No camera: one framed on the scene.
    assert_eq!(s.camera, Camera::framing(&s.bounds()));
}

#[test]
fn yaml_without_lights_warns_and_adds_the_default_light() {
    let yaml = "Materials:\n  - Name: m\nModels:\n  - Mesh: tri.obj\n    Material: m\n";
    let s = load(&yaml_scene("yaml_no_lights", yaml));
    assert_default_light(&s);
    assert!(s.stats.warnings.iter().any(|w| w.contains("no lights")), "{:?}", s.stats.warnings);
}

#[test]
fn yaml_unknown_key_warns_and_still_loads() {
    let yaml = GOOD_YAML.replace("    Fovy: 30\n", "    Fovy: 30\n    Aperture: 2\n").replace("Lights:", "Fog: true\nLights:");
    let path = yaml_scene("yaml_unknown_key", &yaml);
    let s = load(&path);
    assert_eq!(s.triangles.len(), 1);
    let w = &s.stats.warnings;
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w.iter().any(|w| w.ends_with("scene.yaml: key Cameras[0].Aperture: unknown key, ignored")), "{w:?}");
    assert!(w.iter().any(|w| w.ends_with("scene.yaml: key Fog: unknown key, ignored")), "{w:?}");
}

#[test]
fn yaml_wrong_types() {
    let cases = [
        ("yaml_string_position", "Position: [0, 2, 2]", "Position: up", "key Lights[0].Position", "the string 'up'"),
        ("yaml_short_vector", "Position: [0, 2, 2]", "Position: [0, 2]", "key Lights[0].Position", "a list of 2"),
        ("yaml_long_vector", "Eye: [0, 0, 5]", "Eye: [0, 0, 5, 1]", "key Cameras[0].Eye", "list of 3"),
        ("yaml_text_element", "Intensity: [3, 3, 3]", "Intensity: [3, x, 3]", "key Lights[0].Intensity[1]", "number"),
        ("yaml_huge", "Fovy: 30", "Fovy: 1e39", "key Cameras[0].Fovy", "f32"),
        ("yaml_nan", "Length: 0.5", "Length: .nan", "key Lights[1].Length", "NaN"),
        ("yaml_specular_5", "Specular: [1, 1, 1, 100]", "Specular: [1, 1, 1, 100, 1]", "key Materials[0].Specular", "3 or 4"),
        ("yaml_blend", "Blend: Transparent", "Blend: Glass", "key Materials[0].Blend", "Opaque or Transparent"),
        ("yaml_models_map", "Models:\n  - Mesh", "Models:\n    Mesh", "key Models", "list"),
        ("yaml_light_type", "Type: Spot", "Type: Laser", "key Lights[1].Type", "Laser"),
        ("yaml_missing_type", "  - Type: Point\n    Position", "  - Position", "key Lights[0].Type", "missing"),
        ("yaml_null_light", "  - Type: Point\n    Position: [0, 2, 2]\n    Intensity: [3, 3, 3]\n", "  -\n", "key Lights[0]", "expected a mapping"),
        ("yaml_missing_eye", "  - Eye: [0, 0, 5]\n    Target", "  - Target", "key Cameras[0].Eye", "missing"),
        ("yaml_bad_camera", "Target: [0, 0, 0]", "Target: [0, 0, 5]", "key Cameras[0]", "degenerate camera"),
        ("yaml_zero_direction", "Direction: [0, -2, 0]", "Direction: [0, 0, 0]", "key Lights[1].Direction", "zero"),
    ];
    assert_edits_fail(GOOD_YAML, &cases);
}

#[test]
fn yaml_missing_files_and_unknown_material() {
    let yaml = GOOD_YAML.replace("Mesh: tri.obj", "Mesh: tri.obj\n    Material: glass\n  - Mesh: nowhere.obj");
    let t = assert_located(&yaml_scene("yaml_missing_mesh", &yaml), "key Models[1].Mesh");
    assert!(t.contains("nowhere.obj") && t.contains("not found"), "{t}");

    let yaml = GOOD_YAML.replace("Material: glass", "Material: gold");
    let t = assert_located(&yaml_scene("yaml_unknown_material", &yaml), "key Models[0].Material");
    assert!(t.contains("gold") && t.contains("glass"), "{t}");

    let yaml = GOOD_YAML.replace("    Shininess: 50\n", "    DiffuseMap: missing.png\n");
    assert_located(&yaml_scene("yaml_missing_map", &yaml), "key Materials[0].DiffuseMap");

    let yaml = "ComplexModels:\n  - Mesh: tri.obj\n  - Mesh: gone.obj\n";
    assert_located(&yaml_scene("yaml_missing_complex", yaml), "key ComplexModels[1].Mesh");
}

#[test]
fn yaml_bad_mesh_names_the_key_and_the_obj_line() {
    let yaml = GOOD_YAML.replace("tri.obj", "bad.obj");
    let path = write_files("yaml_bad_mesh", &[("scene.yaml", yaml.as_bytes()), ("bad.obj", b"v 0 0 0\nv 1 0 0\nf 1 2 3\n")]);
    let (text, e) = load_err(&path);
    assert!(text.contains("scene.yaml: key Models[0].Mesh"), "{text}");
    assert!(e.file.ends_with("bad.obj") && e.location.as_deref() == Some("line 3"), "{text}");
}

#[test]
fn yaml_syntax_error_names_line_and_column() {
    let yaml = "Cameras:\n  - Eye: [0, 0, 5\n    Target: [0, 0, 0]\nModels: ]\n";
    let path = yaml_scene("yaml_syntax", yaml);
    let (text, e) = load_err(&path);
    assert!(text.contains("scene.yaml"), "{text}");
    let loc = e.location.unwrap();
    assert!(loc.starts_with("line ") && loc.contains("column"), "{text}");
    // The wrong top level is a type error, not a crash.
    assert_located(&yaml_scene("yaml_list_root", "- 1\n- 2\n"), "top level");
    let t = assert_located(&yaml_scene("yaml_empty", ""), "scene.yaml");
    assert!(t.contains("no triangles"), "{t}");
}

// ---------------------------------------------------------------- dispatch

#[test]
fn unsupported_extension_and_missing_files() {
    let path = write_files("unsupported", &[("scene.ply", b"ply\n")]);
    let t = assert_located(&path, ".obj, .yaml");
    assert!(t.contains(".ply"), "{t}");
    let path = write_files("no_extension", &[("scene", b"")]);
    assert_located(&path, "no extension");
    for name in ["missing.obj", "missing.yaml", "missing.YML"] {
        let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join("loaders/absent").join(name);
        let t = assert_located(&path, "cannot read");
        assert!(t.contains(name), "{t}");
    }
    // A folder named like a scene is unreadable too.
    let dir = write_files("folder.obj", &[("x", b"")]).parent().unwrap().to_path_buf();
    assert_located(&dir, "cannot read");
}

// ---------------------------------------------------------------- procedural scenes

#[test]
fn random_soup_is_deterministic_and_clean() {
    let a = procedural::random_soup(500, 7);
    let b = procedural::random_soup(500, 7);
    let c = procedural::random_soup(500, 8);
    assert_eq!(a.triangles, b.triangles);
    assert_ne!(a.triangles, c.triangles);
    assert_eq!(a.triangles.len(), 500);
    assert!(a.triangles.iter().all(|t| t.area() > 0.0 && t.p.iter().all(|p| p.is_finite())));
    let bounds = a.bounds();
    assert!(bounds.min.min_element() >= -0.1 && bounds.max.max_element() <= 1.1);
    assert_eq!(a.materials.len(), 1);
    assert!(a.camera.frame().is_ok());

    let q = procedural::quad(Vec3::ZERO, Vec3::X, Vec3::Y, 0);
    assert!(q.iter().all(|t| t.cross().normalize() == Vec3::Z));
    assert_eq!(q[0].area() + q[1].area(), 1.0);
}

/// A file big enough to be parsed in many chunks at once: faces with negative indices that
/// reach back across chunk ends, `usemtl` lines in every chunk, quads fanned into triangles.
/// Every triangle must come out in file order with the positions and the material the file
/// gives it, and the first error in line order must win whichever chunk holds it.
#[test]
fn obj_files_parsed_in_chunks_keep_order_indices_materials_and_the_first_error() {
    use std::fmt::Write as _;
    let quads = 120_000; // ~6 MB: more than one chunk per core
    let mut obj = String::from("mtllib m.mtl\n");
    let mut expected = Vec::new();
    for q in 0..quads {
        let (x, y) = ((q % 400) as f32, (q / 400) as f32);
        let corners = [(x, y), (x + 1.0, y), (x + 1.0, y + 1.0), (x, y + 1.0)];
        for (cx, cy) in corners {
            writeln!(obj, "v {cx} {cy} {}", q % 7).unwrap();
        }
        if q % 1000 == 0 {
            // Every 1000 quads the material changes: red, blue, red, ... and once an unknown
            // name, which falls back to the default material.
            let name = match (q / 1000) % 3 {
                0 => "red",
                1 => "blue",
                _ => "nope",
            };
            writeln!(obj, "usemtl {name}").unwrap();
        }
        // Half the faces count back, half use absolute indices.
        if q % 2 == 0 {
            obj.push_str("f -4 -3 -2 -1\n");
        } else {
            let b = 4 * q + 1;
            writeln!(obj, "f {} {} {} {}", b, b + 1, b + 2, b + 3).unwrap();
        }
        let material = match (q / 1000) % 3 {
            0 => "red",
            1 => "blue",
            _ => "default",
        };
        let p = corners.map(|(cx, cy)| Vec3::new(cx, cy, (q % 7) as f32));
        expected.push(([p[0], p[1], p[2]], material));
        expected.push(([p[0], p[2], p[3]], material));
    }
    let mtl = b"newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n";
    let path = write_files("chunked", &[("big.obj", obj.as_bytes()), ("m.mtl", mtl)]);
    let mesh = vkrt::scene::obj::load_obj_meshes(&path, None).unwrap();
    assert_eq!(mesh.triangles.len(), expected.len());
    for (i, (t, (p, material))) in mesh.triangles.iter().zip(&expected).enumerate() {
        assert_eq!(t.p, *p, "triangle {i}");
        let name = &mesh.materials[t.material as usize].name;
        let name = if name.is_empty() || name == "default" { "default" } else { name.as_str() };
        assert_eq!(name, *material, "triangle {i}'s material");
    }

    // Two errors in different chunks: the earlier line is reported, then the later alone.
    let lines: Vec<&str> = obj.lines().collect();
    let (early, late) = (lines.len() / 5, lines.len() * 4 / 5);
    let mut bad: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    bad[late] = "v 1 2 x".into();
    let path = write_files("chunked-late", &[("big.obj", bad.join("\n").as_bytes()), ("m.mtl", mtl)]);
    assert_located(&path, &format!("line {}:", late + 1));
    bad[early] = "f 1 2".into();
    let path = write_files("chunked-both", &[("big.obj", bad.join("\n").as_bytes()), ("m.mtl", mtl)]);
    assert_located(&path, &format!("line {}:", early + 1));
}

/// Scene inputs that are not regular files are refused by name, before they are opened or read
/// (issue 45: an `mtllib /dev/zero` was read until the kernel killed vkrt; a FIFO would block).
#[test]
fn inputs_that_are_not_regular_files_are_errors_naming_them() {
    // A device as the material library: an error naming it, not a read without end.
    let obj = write_files("device_mtllib", &[("scene.obj", b"mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")]);
    let (text, input) = load_err(&obj);
    assert_eq!(input.file, Path::new("/dev/zero"), "{text}");
    assert!(text.contains("a character device is not a regular file"), "{text}");

    // A FIFO as the scene itself: refused without opening it (opening would wait for a writer).
    let dir = obj.parent().unwrap();
    let fifo = dir.join("pipe.obj");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status().expect("mkfifo runs");
    assert!(made.success(), "mkfifo {}", fifo.display());
    let (text, input) = load_err(&fifo);
    assert_eq!(input.file, fifo, "{text}");
    assert!(text.contains("a FIFO is not a regular file"), "{text}");

    // The same FIFO as an environment map.
    let map = dir.join("sky.hdr");
    std::fs::rename(&fifo, &map).unwrap();
    let err = vkrt::scene::envmap::EnvMap::load(&map).expect_err("a FIFO is no environment map");
    assert!(format!("{err:#}").contains("sky.hdr: cannot read it: a FIFO is not a regular file"), "{err:#}");

    // A directory as a lab YAML scene's mesh.
    std::fs::create_dir_all(dir.join("mesh.obj")).unwrap();
    let yaml = dir.join("scene.yaml");
    std::fs::write(&yaml, "Models:\n  - Mesh: mesh.obj\n").unwrap();
    let (text, _) = load_err(&yaml);
    assert!(text.contains("mesh.obj") && text.contains("a directory is not a regular file"), "{text}");
}

// ---------------------------------------------------------------- YAML instances

const INSTANCES_YAML: &str = "\
Materials:
  - Name: m
Lights:
  - Type: Point
    Position: [0, 2, 2]
    Intensity: [3, 3, 3]
Instances:
  - Mesh: tri.obj
    Material: m
    Transforms:
      - Translation: [1, 1, 1]
        Scale: [2, -1, 1]
      - Rotation: [0, 90, 0]
        Scale: 2
      - Matrix: [0, 0, 2, 10,  0, 2, 0, 0,  -2, 0, 0, 0]
";

#[test]
fn yaml_instances_place_one_copy_per_transform() {
    let loaded = load(&yaml_scene("yaml_instances", INSTANCES_YAML));
    assert!(loaded.stats.warnings.is_empty(), "{:?}", loaded.stats.warnings);
    // One mesh and three placements, placed here to look at the copies.
    assert_eq!((loaded.triangles.len(), loaded.instances.len(), loaded.instances[0].placements.len()), (0, 1, 3));
    let s = loaded.expanded().unwrap();
    assert_eq!(s.triangles.len(), 3);
    // Scale and translation place exactly as Models' Scale and Translation (GOOD_YAML's test):
    // the mirror's winding flipped back.
    let models = load(&yaml_scene("yaml_instances_models", GOOD_YAML));
    assert_eq!(s.triangles[0].p, models.triangles[0].p);
    assert!(s.triangles[0].cross().dot(s.triangles[0].n.unwrap()[0]) > 0.0);
    // Scale 2, then 90 degrees about y: x -> -z, and the normal +z -> +x.
    let t = &s.triangles[1];
    assert!(close(t.p[1], Vec3::new(0.0, 0.0, -2.0)) && close(t.p[2], Vec3::new(0.0, 2.0, 0.0)), "{:?}", t.p);
    assert!(close(t.n.unwrap()[0], Vec3::X), "{:?}", t.n);
    // The same by rows, then 10 along x.
    let m = &s.triangles[2];
    for k in 0..3 {
        assert!(close(m.p[k], t.p[k] + Vec3::new(10.0, 0.0, 0.0)), "{:?} vs {:?}", m.p, t.p);
    }
    assert!(s.triangles.iter().all(|t| t.material == 0));
}

#[test]
fn yaml_instances_without_a_material_take_the_mtl_s() {
    let yaml = "Instances:\n  - Mesh: box.obj\n    Transforms:\n      - Translation: [0, 0, 0]\n      - Translation: [3, 0, 0]\n";
    let obj = b"mtllib box.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let path = write_files("yaml_instances_mtl", &[("scene.yaml", yaml.as_bytes()), ("box.obj", obj), ("box.mtl", b"newmtl red\nKd 0.8 0.1 0.1\n")]);
    let loaded = load(&path);
    let s = loaded.expanded().unwrap();
    assert_eq!(s.triangles.len(), 2);
    // One copy of the MTL's materials for all the mesh's copies.
    assert_eq!(s.materials.iter().filter(|m| m.name == "red").count(), 1);
    assert_eq!(s.triangles[0].material, s.triangles[1].material);
    assert_eq!(s.triangles[1].p[1], Vec3::new(4.0, 0.0, 0.0));
}

#[test]
fn yaml_bad_instances_name_the_key() {
    let cases = [
        (
            "yaml_inst_matrix_len",
            "Matrix: [0, 0, 2, 10,  0, 2, 0, 0,  -2, 0, 0, 0]",
            "Matrix: [1, 0, 0, 0, 1, 0, 0, 0, 1]",
            "key Instances[0].Transforms[2].Matrix",
            "12 or 16",
        ),
        (
            "yaml_inst_projective",
            "Matrix: [0, 0, 2, 10,  0, 2, 0, 0,  -2, 0, 0, 0]",
            "Matrix: [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 1, 1]",
            "key Instances[0].Transforms[2].Matrix",
            "projective",
        ),
        ("yaml_inst_singular", "Scale: 2", "Scale: 0", "key Instances[0].Transforms[1]", "singular"),
        ("yaml_inst_both", "      - Matrix:", "      - Scale: 3\n        Matrix:", "key Instances[0].Transforms[2].Scale", "either Matrix"),
        ("yaml_inst_rotation", "Rotation: [0, 90, 0]", "Rotation: 90", "key Instances[0].Transforms[1].Rotation", "list of 3"),
        ("yaml_inst_no_transforms", "    Transforms:\n", "    Transform:\n", "key Instances[0].Transforms", "missing"),
        ("yaml_inst_material", "    Material: m\n", "    Material: wood\n", "key Instances[0].Material", "no material named 'wood'"),
        ("yaml_inst_mesh", "  - Mesh: tri.obj\n", "  - Mesh: tree.obj\n", "key Instances[0].Mesh", "not found"),
    ];
    assert_edits_fail(INSTANCES_YAML, &cases);
}

#[test]
fn yaml_instances_past_the_bound_are_refused_with_the_count() {
    // 65,000 copies of a 66,248-triangle grid (182 x 182 quads) make 4.3 G triangles, more
    // than a 32-bit primitive id names: refused from the count. (The copies are not made, so
    // fewer load.)
    let n = 182;
    let mut obj = String::new();
    for y in 0..=n {
        for x in 0..=n {
            obj += &format!("v {x} {y} 0\n");
        }
    }
    for y in 0..n {
        for x in 0..n {
            let v = y * (n + 1) + x + 1;
            obj += &format!("f {v} {} {}\nf {} {} {}\n", v + 1, v + n + 2, v, v + n + 2, v + n + 1);
        }
    }
    let copies = 65_000;
    let yaml = format!("Materials:\n  - Name: m\nInstances:\n  - Mesh: grid.obj\n    Material: m\n    Transforms: [{}{{}}]\n", "{}, ".repeat(copies - 1));
    let path = write_files("yaml_inst_bound", &[("scene.yaml", yaml.as_bytes()), ("grid.obj", obj.as_bytes())]);
    let text = assert_located(&path, "key Instances[0].Transforms");
    let triangles = 2 * n * n;
    assert!(text.contains(&format!("{copies} copies of a {triangles}-triangle mesh")) && text.contains("at most 4294967295"), "{text}");
}
