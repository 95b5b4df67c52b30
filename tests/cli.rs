//! The `vkrt` binary as a user runs it: help, device listing, renders to each image format,
//! and bad input (clear error naming the file, non-zero exit, no panic, outputs untouched).

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn vkrt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vkrt")).args(args).output().expect("run vkrt")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_fails_cleanly(o: &Output, must_mention: &str) {
    let err = stderr(o);
    assert!(!o.status.success(), "expected failure, got success; stderr: {err}");
    assert!(err.contains("error:"), "no error line: {err}");
    assert!(err.contains(must_mention), "error does not mention {must_mention:?}: {err}");
    assert!(!err.contains("panicked"), "vkrt panicked: {err}");
}

const CORNELL: &str = "scenes/lab/cornell_box/cornell_box.yaml";

fn cornell() -> String {
    common::repo_path(CORNELL).display().to_string()
}

#[test]
fn help_lists_every_render_option() {
    let o = vkrt(&["render", "--help"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for flag in ["--output", "--width", "--height", "--integrator", "--max-depth", "--spp", "--device", "--time", "--shard"] {
        assert!(text.contains(flag), "render --help lacks {flag}");
    }
    assert!(vkrt(&["--help"]).status.success());
    assert!(vkrt(&["info", "--help"]).status.success());
}

#[test]
fn info_lists_the_device_it_would_use() {
    let o = vkrt(&["info"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("<- vkrt uses this one"), "{text}");
    assert!(text.contains("max storage buffer range"), "{text}");
    assert!(text.contains("subgroup size"), "{text}");
}

#[test]
fn output_into_a_closed_pipe_ends_quietly() {
    // As in `vkrt info | head -1`: the reader is gone before vkrt prints (it needs ~0.1 s to
    // open Vulkan first). vkrt must not panic; it ends by SIGPIPE like other Unix tools.
    let mut child = Command::new(env!("CARGO_BIN_EXE_vkrt"))
        .arg("info")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run vkrt");
    drop(child.stdout.take());
    let o = child.wait_with_output().expect("wait for vkrt");
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "vkrt panicked: {err}");
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(o.status.signal(), Some(libc::SIGPIPE), "status {:?}, stderr: {err}", o.status);
    }
}

#[test]
fn renders_png_exr_and_pfm_of_the_same_image() {
    let dir = common::scratch_dir("cli-formats");
    let mut images = Vec::new();
    for ext in ["png", "exr", "pfm"] {
        let out = dir.join(format!("cornell.{ext}"));
        let _ = std::fs::remove_file(&out);
        let o = vkrt(&["render", &cornell(), "-o", out.to_str().unwrap(), "--width", "40", "--height", "30"]);
        assert!(o.status.success(), "{ext}: {}", stderr(&o));
        let img = vkrt::output::read_image(&out).unwrap();
        assert_eq!((img.width, img.height), (40, 30), "{ext} size");
        images.push(img);
    }
    // EXR and PFM hold the same linear floats, in the same row order (row 0 at the top).
    assert_eq!(images[1].pixels, images[2].pixels, "exr and pfm differ");
    // The PNG is the same image after the default display transform (PBR Neutral), sRGB-encoded
    // and quantised to 8 bits: within 1/255 after decoding.
    let shown = vkrt::output::display::Display::default().apply(&images[1]);
    for (p, f) in images[0].pixels.iter().zip(&shown.pixels) {
        for k in 0..3 {
            let want = vkrt::output::image::srgb_to_linear(vkrt::output::image::linear_to_srgb(f[k]));
            assert!((p[k] - want).abs() < 0.01, "png {} vs displayed exr {}", p[k], f[k]);
        }
    }
    // Row 0 is the top: the ceiling right by the point light is far brighter than the floor.
    let row = |y: u32| (0..40).map(|x| images[1].get(x, y)[0]).sum::<f32>();
    assert!(row(5) > 2.0 * row(25), "ceiling row {} vs floor row {}", row(5), row(25));
}

#[test]
fn missing_scene_is_a_clear_error_and_leaves_the_output_alone() {
    let dir = common::scratch_dir("cli-missing");
    let out = dir.join("keep.png");
    std::fs::write(&out, b"previous output").unwrap();
    let o = vkrt(&["render", "/nonexistent/scene.obj", "-o", out.to_str().unwrap()]);
    assert_fails_cleanly(&o, "/nonexistent/scene.obj");
    assert_eq!(std::fs::read(&out).unwrap(), b"previous output");
}

#[test]
fn unwritable_output_fails_before_rendering() {
    let o = vkrt(&["render", &cornell(), "-o", "/nonexistent-dir/out.png"]);
    assert_fails_cleanly(&o, "/nonexistent-dir/out.png");
    assert!(!stderr(&o).contains("rendered"), "it rendered before failing: {}", stderr(&o));
}

#[test]
fn unknown_output_format_is_an_error() {
    let o = vkrt(&["render", &cornell(), "-o", "out.bmp"]);
    assert_fails_cleanly(&o, "out.bmp");
}

#[test]
fn unknown_device_is_an_error_listing_the_devices() {
    let dir = common::scratch_dir("cli-device");
    let out = dir.join("x.png");
    let o = vkrt(&["render", &cornell(), "-o", out.to_str().unwrap(), "--device", "no-such-gpu"]);
    assert_fails_cleanly(&o, "no-such-gpu");
    assert!(stderr(&o).contains("devices:"), "{}", stderr(&o));
    assert!(!Path::new(&out).exists());
}

#[test]
fn bad_scene_file_names_the_file_and_line() {
    let dir = common::scratch_dir("cli-bad-obj");
    let obj = dir.join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n").unwrap();
    let o = vkrt(&["render", obj.to_str().unwrap(), "-o", dir.join("x.png").to_str().unwrap()]);
    assert_fails_cleanly(&o, "bad.obj");
    assert!(stderr(&o).contains("line 3"), "{}", stderr(&o));
}

#[test]
fn corrupt_or_mismatched_checkpoints_are_clear_errors() {
    let dir = common::scratch_dir("cli-bad-checkpoint");
    let scene = common::repo_path("scenes/cornell-measured/cornell.yaml").display().to_string();
    let ckpt = dir.join("good.ckpt");
    let out = dir.join("out.exr");
    let render = |extra: &[&str], ck: &Path, size: &str| {
        let mut args = vec!["render", scene.as_str(), "--integrator", "path", "--width", size, "--height", size, "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.push("--resume");
        args.push(ck.to_str().unwrap());
        vkrt(&args)
    };
    let o = vkrt(&[
        "render",
        &scene,
        "--integrator",
        "path",
        "--width",
        "8",
        "--height",
        "8",
        "--spp",
        "2",
        "--checkpoint",
        ckpt.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let good = std::fs::read(&ckpt).unwrap();
    std::fs::write(&out, b"previous output").unwrap();
    // Truncated, garbage and empty checkpoints: an error naming the file; the output stays.
    for (name, bytes) in [("truncated.ckpt", good[..good.len() / 2].to_vec()), ("garbage.ckpt", vec![0x5a; 300]), ("empty.ckpt", vec![])] {
        let bad = dir.join(name);
        std::fs::write(&bad, &bytes).unwrap();
        let o = render(&["--spp", "4"], &bad, "8");
        assert_fails_cleanly(&o, name);
        assert_eq!(std::fs::read(&out).unwrap(), b"previous output", "{name}: output overwritten");
    }
    // A checkpoint of another image size cannot be resumed.
    let o = render(&["--spp", "4"], &ckpt, "16");
    assert_fails_cleanly(&o, "good.ckpt");
    assert!(stderr(&o).contains("width") || stderr(&o).contains("size"), "{}", stderr(&o));
    // Nor one whose pixels drew their numbers differently (--coherence), and 0 is no block.
    let o = render(&["--spp", "4", "--coherence", "4"], &ckpt, "8");
    assert_fails_cleanly(&o, "coherence");
    let o = render(&["--spp", "4", "--coherence-block", "0"], &ckpt, "8");
    assert_fails_cleanly(&o, "coherence block");
    let o = vkrt(&["render", &scene, "--integrator", "path", "--width", "8", "--height", "8", "--coherence", "0", "-o", out.to_str().unwrap()]);
    assert_fails_cleanly(&o, "coherence");
}

/// Coherence flags the path tracer refuses fail before any work, naming the flag: a block that
/// is not a power of two. --adaptive renders with the default scattered groups (its blocks
/// are their squares) and with groups in rows.
#[test]
fn bad_coherence_flags_are_refused_before_any_work() {
    let dir = common::scratch_dir("cli-coherence");
    let scene = common::repo_path("scenes/cornell-measured/cornell.yaml").display().to_string();
    let out = dir.join("out.exr");
    let _ = std::fs::remove_file(&out);
    let render = |extra: &[&str]| {
        let mut args = vec!["render", scene.as_str(), "--integrator", "path", "--width", "16", "--height", "16", "--spp", "8", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        vkrt(&args)
    };
    assert_fails_cleanly(&render(&["--coherence-block", "24"]), "--coherence-block 24");
    assert!(!out.exists(), "a refused render wrote its output");
    for extra in [&["--adaptive"][..], &["--adaptive", "--coherence", "8", "--coherence-block", "0"]] {
        let o = render(extra);
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
        assert!(out.exists(), "{extra:?} wrote no image");
        std::fs::remove_file(&out).unwrap();
    }
}

/// `--envmap` replaces the default light that a file without lights gets, whichever loader read
/// it (issue 45, bugs 2 and 3): a glTF file (whose loader did not record its default light, so
/// the map lit the scene beside it) and a bare OBJ room (whose default point light the upload
/// dropped while the shader variant kept its code). `-v` lists the variant's features and why.
#[test]
fn envmap_replaces_the_default_light_of_every_loader() {
    let dir = common::scratch_dir("cli_envmap_default_light");
    // One triangle, no lights, no materials.
    let tri: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(dir.join("unlit.bin"), &tri).unwrap();
    let gltf = r#"{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"uri": "unlit.bin", "byteLength": 36}], "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]}"#;
    std::fs::write(dir.join("unlit.gltf"), gltf).unwrap();
    // A closed box whose faces turn inward (by their normals): the loader sees a room and
    // gives it a point light under the ceiling.
    let mut room = String::new();
    for v in [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]] {
        room += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    room += "vn 0 0 1\nvn 0 0 -1\nvn 1 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\n";
    for (face, n) in [([1, 2, 3, 4], 1), ([5, 8, 7, 6], 2), ([1, 4, 8, 5], 3), ([2, 6, 7, 3], 4), ([1, 5, 6, 2], 5), ([4, 3, 7, 8], 6)] {
        room += &format!("f {}//{n} {}//{n} {}//{n} {}//{n}\n", face[0], face[1], face[2], face[3]);
    }
    std::fs::write(dir.join("room.obj"), room).unwrap();
    let map = common::repo_path("tests/refs/envmap-sun.exr").display().to_string();
    for (scene, light) in [("unlit.gltf", "directional lights"), ("room.obj", "point lights")] {
        let path = dir.join(scene).display().to_string();
        let out = dir.join(format!("{scene}.png")).display().to_string();
        let plain = vkrt(&["render", &path, "-v", "--no-cache", "--width", "8", "--height", "8", "-o", &out]);
        let text = stderr(&plain);
        assert!(plain.status.success(), "{scene}: {text}");
        let line = |text: &str| text.lines().find(|l| l.trim_start().starts_with(light)).map(str::to_string);
        let on = line(&text).unwrap_or_else(|| panic!("{scene}: no {light} line in -v:\n{text}"));
        assert!(on.contains(" on "), "{scene} without a map is lit by its default light: {on}");
        let lit = vkrt(&["render", &path, "-v", "--cache", "off", "--envmap", &map, "--width", "8", "--height", "8", "-o", &out]);
        let text = stderr(&lit);
        assert!(lit.status.success(), "{scene}: {text}");
        assert!(text.contains("prepared-scene cache: off"), "--cache off kept a cache: {text}");
        let off = line(&text).unwrap_or_else(|| panic!("{scene}: no {light} line in -v:\n{text}"));
        assert!(off.contains(" off ") && off.contains("replaces the default light"), "{scene} under a map: {off}");
    }
}

/// `vkrt render --help` fits on a screen (issue 45): at most 25 options, each under a heading
/// (output, image, camera, lights, progressive runs, clusters, device); each of them is run by
/// a test that runs the binary (found as a quoted argument in those test files); the flags it
/// leaves out still work and `--help-expert` lists them all.
#[test]
fn render_help_shows_at_most_25_grouped_options_each_run_by_a_test() {
    use clap::CommandFactory;
    let mut cli = vkrt::cli::Cli::command();
    cli.build();
    let render = cli.find_subcommand("render").expect("a render command");
    let options: Vec<&clap::Arg> = render.get_arguments().filter(|a| !a.is_positional() && a.get_long() != Some("help")).collect();
    let visible: Vec<&clap::Arg> = options.iter().copied().filter(|a| !a.is_hide_set()).collect();
    let names = |args: &[&clap::Arg]| args.iter().filter_map(|a| a.get_long()).map(|l| format!("--{l}")).collect::<Vec<_>>();
    assert!(visible.len() <= 25, "{} options in render --help: {:?}", visible.len(), names(&visible));
    for a in &visible {
        assert!(a.get_help_heading().is_some(), "--{} has no heading", a.get_long().unwrap_or("?"));
    }
    let tests = common::repo_path("tests");
    let mut sources = String::new();
    for entry in std::fs::read_dir(&tests).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if path.extension().is_some_and(|e| e == "rs") && (text.contains("vkrt_bin()") || text.contains("CARGO_BIN_EXE_vkrt")) {
            sources += &text;
        }
    }
    for a in &visible {
        let long = format!("\"--{}\"", a.get_long().unwrap_or_default());
        let short = a.get_short().map(|c| format!("\"-{c}\""));
        assert!(sources.contains(&long) || short.is_some_and(|s| sources.contains(&s)), "no test runs the binary with {long}");
    }
    let help = String::from_utf8_lossy(&vkrt(&["render", "--help"]).stdout).into_owned();
    assert!(help.contains("--help-expert"), "render --help does not say where the other flags are");
    let expert = vkrt(&["render", "--help-expert"]);
    assert!(expert.status.success());
    let expert = String::from_utf8_lossy(&expert.stdout).into_owned();
    for name in names(&options) {
        assert!(expert.contains(&name), "--help-expert lacks {name}");
    }
    let hidden: Vec<&clap::Arg> = options.iter().copied().filter(|a| a.is_hide_set()).collect();
    // An option's line starts with its flags (`  -o, --output <FILE>`); descriptions may name others.
    let listed =
        |text: &str, name: &str| text.lines().map(str::trim_start).any(|l| l.split_whitespace().any(|w| w.trim_end_matches(',') == name) && l.starts_with('-'));
    for name in names(&hidden) {
        assert!(!listed(&help, &name), "--help lists {name}");
        assert!(listed(&expert, &name), "--help-expert does not list {name}");
    }
}
