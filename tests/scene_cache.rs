//! The prepared-scene cache (`vkrt render --cache DIR`): a second run maps the entry the first
//! stored and renders the same bytes; a changed input file, a corrupt or a truncated entry is
//! never trusted (a warning, the scene prepared again, the entry rewritten); runs that store
//! the same entry at once leave a whole one; the default cache skips small scenes.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn vkrt(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(common::vkrt_bin());
    cmd.args(args).env_remove("VKRT_CACHE");
    cmd.envs(env.iter().copied());
    cmd.output().expect("run vkrt")
}

fn ok(out: Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{what}: {err}");
    assert!(!err.contains("panicked"), "{what} panicked: {err}");
    err
}

/// A copy of the cornell-measured scene in its own folder, so the test can change its files.
fn scene_copy(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    for f in ["cornell.yaml", "cornell.obj", "cornell.mtl"] {
        std::fs::copy(common::repo_path(&format!("scenes/cornell-measured/{f}")), dir.join(f)).unwrap();
    }
    dir.join("cornell.yaml")
}

/// What a cache folder holds besides its `shaders` folder (compiled shaders, tests/shader_cache.rs).
fn entries(cache: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(cache)
        .map(|d| d.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.file_name() != Some(std::ffi::OsStr::new("shaders"))).collect())
        .unwrap_or_default();
    v.sort();
    v
}

struct Case {
    dir: PathBuf,
    scene: String,
    cache: String,
}

impl Case {
    fn new(name: &str) -> Self {
        let dir = common::scratch_dir(&format!("scene-cache/{name}"));
        let _ = std::fs::remove_dir_all(&dir);
        let scene = scene_copy(&dir.join("scene")).display().to_string();
        Self { cache: dir.join("cache").display().to_string(), scene, dir }
    }

    /// Renders with `extra` flags into `name`; returns (image bytes, stderr).
    fn render(&self, name: &str, extra: &[&str], cache: bool) -> (Vec<u8>, String) {
        let out = self.dir.join(name).display().to_string();
        let mut args = vec!["render", self.scene.as_str(), "--width", "40", "--height", "32", "--verbose", "-o", out.as_str()];
        if cache {
            args.extend(["--cache", self.cache.as_str()]);
        } else {
            args.push("--no-cache");
        }
        args.extend(extra);
        let err = ok(vkrt(&args, &[]), name);
        (std::fs::read(&out).unwrap(), err)
    }
}

const HIT: &str = "from the prepared-scene cache";

#[test]
fn a_cached_scene_renders_the_same_bytes_in_both_integrators_and_any_view() {
    let case = Case::new("same-bytes");
    let path = ["--integrator", "path", "--spp", "4"];
    let views: [&[&str]; 3] = [&[], &path, &["--sky", "0.2,0.3,0.4", "--eye", "278,273,-700", "--fov", "50"]];
    for (i, view) in views.iter().enumerate() {
        let (fresh, _) = case.render(&format!("fresh-{i}.exr"), view, false);
        let (first, err) = case.render(&format!("first-{i}.exr"), view, true);
        if i == 0 {
            assert!(err.contains("prepared-scene cache: stored"), "the first run must store the scene:\n{err}");
        }
        let (second, err) = case.render(&format!("second-{i}.exr"), view, true);
        assert!(err.contains(HIT), "view {i}: the second run must map the entry:\n{err}");
        assert!(fresh == first && first == second, "view {i}: a cached render differs from an uncached one");
    }
    assert_eq!(entries(Path::new(&case.cache)).len(), 1, "one scene and one build setting make one entry");
    // A checkpoint made on a cache hit takes its input hashes from the cache's check: it must be
    // the checkpoint an uncached run writes, byte for byte (same output and checkpoint names).
    let ckpt = case.dir.join("run.ckpt").display().to_string();
    let with_ckpt = ["--integrator", "path", "--spp", "2", "--checkpoint", ckpt.as_str()];
    case.render("ckpt.exr", &with_ckpt, false);
    let uncached = std::fs::read(&ckpt).unwrap();
    let (_, err) = case.render("ckpt.exr", &with_ckpt, true);
    assert!(err.contains(HIT), "{err}");
    assert!(std::fs::read(&ckpt).unwrap() == uncached, "a checkpoint written from the cache differs");
    // Another layout is another entry, and the same image.
    let (fresh, _) = case.render("fresh-compact.exr", &["--layout", "compact"], false);
    let (_, err) = case.render("first-compact.exr", &["--layout", "compact"], true);
    assert!(!err.contains(HIT), "the threaded entry must not serve the compact layout:\n{err}");
    let (cached, err) = case.render("second-compact.exr", &["--layout", "compact"], true);
    assert!(err.contains(HIT), "{err}");
    assert!(cached == fresh);
    assert_eq!(entries(Path::new(&case.cache)).len(), 2);
}

#[test]
fn changed_inputs_and_damaged_entries_are_rebuilt_with_a_warning() {
    let case = Case::new("damaged");
    case.render("first.png", &[], true);
    let entry = entries(Path::new(&case.cache)).pop().expect("an entry");

    // A changed material library: the entry is stale, and the new colour shows.
    let mtl = Path::new(&case.scene).with_file_name("cornell.mtl");
    let text = std::fs::read_to_string(&mtl).unwrap();
    let changed = text.replacen("Kd ", "Kd 0.9 0.1 0.1 #", 1);
    assert_ne!(changed, text, "the test needs a Kd line to change");
    std::fs::write(&mtl, changed).unwrap();
    let (stale, err) = case.render("stale.png", &[], true);
    assert!(err.contains("stale") && err.contains("cornell.mtl"), "a changed input must be named:\n{err}");
    assert!(!err.contains(HIT));
    let (fresh, _) = case.render("fresh.png", &[], false);
    assert!(stale == fresh, "the render after a change must be of the changed scene");
    let (again, err) = case.render("again.png", &[], true);
    assert!(err.contains(HIT), "the rebuilt entry must be used next time:\n{err}");
    assert!(again == fresh);

    // One flipped byte in an array, then a cut: never trusted, always rebuilt.
    let mut bytes = std::fs::read(&entry).unwrap();
    let last = bytes.len() - 1;
    bytes[last - 100] ^= 0x40;
    std::fs::write(&entry, &bytes).unwrap();
    let (image, err) = case.render("corrupt.png", &[], true);
    assert!(err.contains("corrupt"), "{err}");
    assert!(image == fresh);
    let len = std::fs::metadata(&entry).unwrap().len();
    std::fs::File::options().write(true).open(&entry).unwrap().set_len(len / 2).unwrap();
    let (image, err) = case.render("truncated.png", &[], true);
    assert!(err.contains("truncated"), "{err}");
    assert!(image == fresh);
    std::fs::write(&entry, b"not a cache entry").unwrap();
    let (image, err) = case.render("foreign.png", &[], true);
    assert!(err.contains("not using") && !err.contains(HIT), "{err}");
    assert!(image == fresh);
    let (_, err) = case.render("after.png", &[], true);
    assert!(err.contains(HIT), "the entry must be whole again:\n{err}");
}

#[test]
fn runs_storing_the_same_entry_at_once_leave_a_whole_one() {
    let case = Case::new("concurrent");
    let out = |i: usize| case.dir.join(format!("c{i}.exr")).display().to_string();
    let children: Vec<_> = (0..4)
        .map(|i| {
            Command::new(common::vkrt_bin())
                .args(["render", &case.scene, "--width", "40", "--height", "32", "--quiet", "--cache", &case.cache, "-o", &out(i)])
                .env_remove("VKRT_CACHE")
                .spawn()
                .unwrap()
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    let files = entries(Path::new(&case.cache));
    assert_eq!(files.len(), 1, "one entry and no temporary files left: {files:?}");
    let (image, err) = case.render("after.exr", &[], true);
    assert!(err.contains(HIT), "{err}");
    for i in 0..4 {
        assert!(std::fs::read(out(i)).unwrap() == image);
    }
}

#[test]
fn the_default_cache_skips_small_scenes_and_no_cache_keeps_nothing() {
    let case = Case::new("default");
    let home = case.dir.join("xdg");
    let out = case.dir.join("a.png").display().to_string();
    let xdg = home.display().to_string();
    let err = ok(vkrt(&["render", &case.scene, "--width", "16", "--height", "16", "-v", "-o", &out], &[("XDG_CACHE_HOME", &xdg)]), "default cache");
    assert!(err.contains("not stored") && err.contains("under the 0.5 s"), "{err}");
    assert!(entries(&home.join("vkrt")).is_empty());
    let err = ok(vkrt(&["render", &case.scene, "--width", "16", "--height", "16", "-v", "--no-cache", "-o", &out], &[("XDG_CACHE_HOME", &xdg)]), "no cache");
    assert!(err.contains("prepared-scene cache: off"), "{err}");
    let both = vkrt(&["render", &case.scene, "--no-cache", "--cache", &xdg, "-o", &out], &[]);
    assert!(!both.status.success() && String::from_utf8_lossy(&both.stderr).contains("--no-cache"));
}

#[test]
fn a_normal_mapped_obj_renders_the_same_from_the_cache() {
    // An OBJ quad whose MTL names a tangent-space normal map with `norm`: the map is loaded
    // (the image differs from the same quad without it), MikkTSpace makes its tangents, and the
    // cache stores them (format 2): a cached render is the uncached one, byte for byte.
    let dir = common::scratch_dir("scene-cache/normal-map");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut img = image::RgbaImage::new(4, 4);
    for (x, _, p) in img.enumerate_pixels_mut() {
        *p = image::Rgba([if x < 2 { 200 } else { 60 }, 128, 220, 255]);
    }
    img.save(dir.join("normal.png")).unwrap();
    let obj = "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl bumpy\nf 1/1/1 2/2/1 3/3/1 4/4/1\n";
    std::fs::write(dir.join("quad.obj"), obj).unwrap();
    std::fs::write(dir.join("plain.obj"), obj.replace("quad.mtl", "plain.mtl")).unwrap();
    std::fs::write(dir.join("quad.mtl"), "newmtl bumpy\nKd 0.8 0.8 0.8\nnorm normal.png\n").unwrap();
    std::fs::write(dir.join("plain.mtl"), "newmtl bumpy\nKd 0.8 0.8 0.8\n").unwrap();
    let cache = dir.join("cache").display().to_string();
    let render = |scene: &str, name: &str, cached: bool| {
        let out = dir.join(name).display().to_string();
        let scene = dir.join(scene).display().to_string();
        let mut args = vec!["render", scene.as_str(), "--width", "24", "--height", "24", "--verbose", "-o", out.as_str()];
        if cached {
            args.extend(["--cache", cache.as_str()]);
        } else {
            args.push("--no-cache");
        }
        let err = ok(vkrt(&args, &[]), name);
        (std::fs::read(&out).unwrap(), err)
    };
    let (fresh, _) = render("quad.obj", "fresh.exr", false);
    let (plain, _) = render("plain.obj", "plain.exr", false);
    assert!(fresh != plain, "the normal map changes nothing: `norm` was not loaded");
    let (first, _) = render("quad.obj", "first.exr", true);
    let (second, err) = render("quad.obj", "second.exr", true);
    assert!(err.contains(HIT), "the second run must map the entry:\n{err}");
    assert!(fresh == first && first == second, "a cached normal-mapped render differs from an uncached one");
}
