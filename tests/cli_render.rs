//! `vkrt render` as a user runs it (issue 16): flags that apply or are an error, checks before
//! any work, the camera from the command line, exposure and display transforms, outputs written
//! exactly as named, progress where nobody watches a terminal, resuming in one word, and
//! consistent names and help. Every test runs the binary.

mod common;

use clap::CommandFactory;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn vkrt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vkrt")).args(args).output().expect("run vkrt")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "vkrt failed: {}", stderr(o));
    stderr(o)
}

/// Fails with status 1 (not an abort, not clap's 2), one error message, no panic.
fn fails(o: &Output, must_mention: &str) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(1), "expected exit 1: {err}");
    assert!(err.contains("error:") && err.contains(must_mention), "error does not mention {must_mention:?}: {err}");
    assert!(!err.contains("panicked") && !err.contains("For more information"), "{err}");
    err
}

fn repo(rel: &str) -> String {
    common::repo_path(rel).display().to_string()
}

const LAB_CORNELL: &str = "scenes/lab/cornell_box/cornell_box.yaml";
const MEASURED: &str = "scenes/cornell-measured/cornell.yaml";
const BOX_VER_PATH: &str = "scenes/lab/Box_ver_path/Box_ver_path.yaml";

fn file(dir: &Path, name: &str) -> String {
    dir.join(name).display().to_string()
}

#[test]
fn path_tracer_flags_select_it_or_are_an_error_under_whitted() {
    let dir = common::scratch_dir("cli16-flags");
    let out = file(&dir, "a.exr");
    let scene = repo(LAB_CORNELL);
    // Under an explicit --integrator whitted every path-tracer flag is refused by name.
    for flags in [
        &["--resume", "x.ckpt"][..],
        &["--time", "1"],
        &["--checkpoint", "c.ckpt"],
        &["--target-relmse", "0.1"],
        &["--sampler", "independent"],
        &["--adaptive"],
        &["--no-nee"],
        &["--connections", "on"],
    ] {
        let mut args = vec!["render", scene.as_str(), "-o", out.as_str(), "--integrator", "whitted"];
        args.extend_from_slice(flags);
        fails(&vkrt(&args), &format!("{} needs --integrator path", flags[0]));
    }
    // Without --integrator they select the path tracer: a progressive run that reports spp.
    let err = ok(&vkrt(&["render", &repo(LAB_CORNELL), "-o", &out, "--width", "16", "--height", "16", "--time", "0.2"]));
    assert!(err.contains("--time selects the path tracer") && err.contains("spp"), "{err}");
    // Connections asked for where there is no emissive triangle to start from: said, not silent.
    let err = ok(&vkrt(&["render", &scene, "-o", &out, "--width", "8", "--height", "8", "--spp", "1", "--connections", "on"]));
    assert!(err.contains("--connections on: no light-vertex connections here: the scene has no emissive triangles"), "{err}");
}

#[test]
fn bad_numbers_and_sizes_are_one_line_errors_before_any_work() {
    let dir = common::scratch_dir("cli16-numbers");
    let out = file(&dir, "a.png");
    let scene = repo(LAB_CORNELL);
    fails(&vkrt(&["render", &scene, "-o", &out, "--spp", "0"]), "at least 1, not 0");
    fails(&vkrt(&["render", &scene, "-o", &out, "--spp", "-5"]), "at least 1, not -5");
    fails(&vkrt(&["render", &scene, "-o", &out, "--width", "0"]), "--width");
    fails(&vkrt(&["render", &scene, "-o", &out, "--max-depth", "0"]), "--max-depth");
    fails(&vkrt(&["render", &scene, "-o", &out, "--integrator", "path", "--spp", "0"]), "at least 1");
    let err = fails(&vkrt(&["render", &scene, "-o", &out, "--max-depth", "16"]), "1 to 15");
    assert!(!err.contains("rendered"), "{err}");
    // A size no device and no machine holds: the limit, at once, no abort.
    for size in ["100000", "20000"] {
        let err = fails(&vkrt(&["render", &scene, "-o", &out, "--width", size, "--height", size]), "pixels");
        assert!(err.contains("at most") || err.contains("available"), "{err}");
    }
    assert!(!Path::new(&out).exists());
    // --help states the true limits.
    let help = String::from_utf8_lossy(&vkrt(&["render", "--help"]).stdout).into_owned();
    assert!(help.contains("1 to 15") && help.contains("at least 1"), "{help}");
}

/// The camera line of `--verbose`, in the flags' own syntax.
fn camera_line(err: &str) -> Vec<String> {
    let line = err.lines().find_map(|l| l.strip_prefix("camera: ")).unwrap_or_else(|| panic!("no camera line: {err}"));
    line.split_whitespace().map(str::to_string).collect()
}

#[test]
fn the_camera_comes_from_the_command_line_and_verbose_prints_it_as_flags() {
    let dir = common::scratch_dir("cli16-camera");
    let scene = repo(LAB_CORNELL);
    let (a, b, c) = (file(&dir, "a.pfm"), file(&dir, "b.pfm"), file(&dir, "c.pfm"));
    let err = ok(&vkrt(&["render", &scene, "-o", &a, "--width", "24", "--height", "24", "--verbose"]));
    let flags = camera_line(&err);
    assert_eq!(flags[0], "--eye");
    // The printed flags reproduce the image, bit for bit.
    let mut args: Vec<String> = ["render", &scene, "-o", &b, "--width", "24", "--height", "24"].iter().map(|s| s.to_string()).collect();
    args.extend(flags);
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&vkrt(&refs));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap(), "the printed camera renders another image");
    // Another eye, another image; and it is reported.
    let err = ok(&vkrt(&["render", &scene, "-o", &c, "--width", "24", "--height", "24", "--eye", "278,273,-400", "--fov", "60", "--verbose"]));
    assert!(camera_line(&err).join(" ").contains("--eye 278,273,-400"), "{err}");
    assert!(camera_line(&err).join(" ").contains("--fov 60"), "{err}");
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap());
    // --camera N picks among the file's cameras.
    let yaml = std::fs::read_to_string(common::repo_path(LAB_CORNELL))
        .unwrap()
        .replace("\r\n", "\n")
        .replace("Cameras:\n", "Cameras:\n  - Eye: [278, 400, -600]\n    Target: [278, 273, 0]\n    Up: [0, 1, 0]\n    Fovy: 50\n");
    let two = dir.join("two.yaml");
    std::fs::write(&two, yaml).unwrap();
    for f in ["left.obj", "right.obj", "wall.obj", "light.obj", "short_block.obj", "tall_block.obj"] {
        std::fs::copy(common::repo_path(&format!("scenes/lab/cornell_box/{f}")), dir.join(f)).unwrap();
    }
    let two = two.display().to_string();
    let err = ok(&vkrt(&["render", &two, "-o", &b, "--width", "24", "--height", "24", "--camera", "1", "--verbose"]));
    assert!(camera_line(&err).join(" ").starts_with("--eye 278,273,-800"), "{err}");
    let err = ok(&vkrt(&["render", &two, "-o", &b, "--width", "24", "--height", "24", "--verbose"]));
    assert!(camera_line(&err).join(" ").starts_with("--eye 278,400,-600"), "{err}");
    fails(&vkrt(&["render", &two, "-o", &b, "--camera", "2"]), "numbered 0 to 1");
    fails(&vkrt(&["render", &scene, "-o", &b, "--eye", "278,273,0"]), "cannot render");
}

/// A room: a closed box whose faces point inward, with a small block on its floor; and the same
/// box turned inside out (a closed object).
fn box_obj(inward: bool) -> String {
    let mut s = String::from("v -4 0 -2\nv 4 0 -2\nv 4 3 -2\nv -4 3 -2\nv -4 0 2\nv 4 0 2\nv 4 3 2\nv -4 3 2\n");
    // Quads counter-clockwise seen from inside.
    let faces = [[1, 2, 3, 4], [6, 5, 8, 7], [5, 1, 4, 8], [2, 6, 7, 3], [5, 6, 2, 1], [4, 3, 7, 8]];
    for f in faces {
        let f = if inward { f } else { [f[3], f[2], f[1], f[0]] };
        s.push_str(&format!("f {} {} {} {}\n", f[0], f[1], f[2], f[3]));
    }
    s
}

#[test]
fn a_bare_room_gets_a_camera_and_light_inside_a_closed_object_the_outside_view() {
    let dir = common::scratch_dir("cli16-room");
    for (name, inward) in [("room.obj", true), ("object.obj", false)] {
        std::fs::write(dir.join(name), box_obj(inward)).unwrap();
        let err = ok(&vkrt(&["render", &file(&dir, name), "-o", &file(&dir, "r.pfm"), "--width", "32", "--height", "16", "--verbose"]));
        let cam = camera_line(&err);
        let eye: Vec<f32> = cam[1].split(',').map(|v| v.parse().unwrap()).collect();
        let target: Vec<f32> = cam[3].split(',').map(|v| v.parse().unwrap()).collect();
        if inward {
            // At the centre, looking along the longer axis (x).
            assert!(eye[0].abs() < 1e-3 && (eye[1] - 1.5).abs() < 1e-3 && eye[2].abs() < 1e-3, "{err}");
            assert!(target[0] > 1.0 && (target[2] - eye[2]).abs() < 1e-3, "{err}");
            // And lit from inside: the far wall is not black.
            let img = vkrt::output::read_image(&dir.join("r.pfm")).unwrap();
            assert!(img.get(16, 8)[0] > 0.1, "the room is dark: {:?}", img.get(16, 8));
        } else {
            assert!(eye[2] > 2.0, "a closed object should be seen from outside: {err}");
        }
    }
}

#[test]
fn exposure_and_tonemap_shape_png_but_not_float_outputs() {
    let dir = common::scratch_dir("cli16-display");
    let scene = repo(BOX_VER_PATH);
    let run = |name: &str, extra: &[&str]| {
        let out = file(&dir, name);
        let mut args = vec!["render", scene.as_str(), "-o", out.as_str(), "--width", "48", "--height", "48"];
        args.extend_from_slice(extra);
        ok(&vkrt(&args));
        image::open(&out).map(|i| i.to_rgb8())
    };
    let white = |img: &image::RgbImage| img.pixels().filter(|p| p.0 == [255, 255, 255]).count();
    let clamp = run("clamp.png", &["--exposure", "0", "--tonemap", "clamp"]).unwrap();
    let default = run("default.png", &[]).unwrap();
    // The old clip blows this scene out; the defaults (auto exposure, PBR Neutral) do not.
    assert!(white(&clamp) > 48 * 48 / 5, "{} white pixels with clamp", white(&clamp));
    assert!(white(&default) * 10 < white(&clamp), "{} white pixels by default vs {} with clamp", white(&default), white(&clamp));
    let mean = |img: &image::RgbImage| img.pixels().map(|p| p.0.iter().map(|&c| c as f64).sum::<f64>()).sum::<f64>() / img.len() as f64;
    let dark = run("dark.png", &["--exposure", "-3"]).unwrap();
    let bright = run("bright.png", &["--exposure", "1"]).unwrap();
    assert!(mean(&dark) < mean(&bright), "exposure -3 is not darker than +1");
    // Float outputs are the radiance, whatever the display flags say.
    let exr = |name: &str, extra: &[&str]| {
        let out = file(&dir, name);
        let mut args = vec!["render", scene.as_str(), "-o", out.as_str(), "--width", "48", "--height", "48"];
        args.extend_from_slice(extra);
        ok(&vkrt(&args));
        std::fs::read(&out).unwrap()
    };
    assert_eq!(exr("a.exr", &[]), exr("b.exr", &["--exposure", "3", "--tonemap", "aces"]));
    fails(&vkrt(&["render", &scene, "-o", &file(&dir, "x.png"), "--exposure", "bright"]), "auto");
}

#[test]
fn outputs_are_exactly_the_files_named() {
    let dir = common::scratch_dir("cli16-outputs");
    let scene = repo(MEASURED);
    for ext in ["exr", "pfm"] {
        let _ = std::fs::remove_file(dir.join("a.png"));
        ok(&vkrt(&["render", &scene, "-o", &file(&dir, &format!("a.{ext}")), "--integrator", "path", "--spp", "2", "--width", "16", "--height", "16"]));
        assert!(!dir.join("a.png").exists(), "-o a.{ext} also wrote a.png");
    }
    ok(&vkrt(&["render", &scene, "-o", &file(&dir, "b.exr"), "--width", "16", "--height", "16", "--preview", &file(&dir, "b-preview.png")]));
    assert!(dir.join("b.exr").exists() && dir.join("b-preview.png").exists());
    fails(&vkrt(&["render", &scene, "-o", &file(&dir, "c.exr"), "--preview", &file(&dir, "c.exr2")]), ".png");
}

#[test]
fn progress_lines_when_not_on_a_terminal_and_silence_with_quiet() {
    let dir = common::scratch_dir("cli16-progress");
    let scene = repo(MEASURED);
    // stderr is a pipe here: plain lines every 5 s, with the running error estimate.
    let err = ok(&vkrt(&["render", &scene, "-o", &file(&dir, "a.exr"), "--integrator", "path", "--width", "64", "--height", "64", "--time", "11"]));
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("rendering: ")).collect();
    assert!(lines.len() >= 2, "progress lines: {err}");
    assert!(lines.iter().all(|l| l.contains('%') && l.contains("spp") && l.contains("rays/s") && l.contains("est. relMSE")), "{err}");
    let quiet = vkrt(&["render", &scene, "-o", &file(&dir, "b.exr"), "--integrator", "path", "--width", "16", "--height", "16", "--time", "6", "--quiet"]);
    assert!(quiet.status.success() && quiet.stderr.is_empty(), "--quiet printed: {}", stderr(&quiet));
}

#[test]
fn preview_every_rewrites_the_output_while_the_render_runs() {
    let dir = common::scratch_dir("cli16-preview-every");
    let out = dir.join("live.png");
    let _ = std::fs::remove_file(&out);
    let mut child = Command::new(env!("CARGO_BIN_EXE_vkrt"))
        .args(["render", &repo(MEASURED), "-o", out.to_str().unwrap(), "--integrator", "path", "--width", "32", "--height", "32"])
        .args(["--time", "30", "--preview-every", "0.2", "--quiet"])
        .spawn()
        .unwrap();
    // The image appears long before the 30 s render ends.
    let mut seen_while_running = false;
    for _ in 0..200 {
        if out.exists() {
            seen_while_running = child.try_wait().unwrap().is_none();
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let _ = child.kill();
    let _ = child.wait();
    assert!(seen_while_running, "the output was not written during the run");
    assert!(image::open(&out).is_ok(), "the preview is not a whole image");
}

#[test]
fn resume_continues_a_run_from_its_checkpoint_alone() {
    let dir = common::scratch_dir("cli16-resume");
    let scene = repo(MEASURED);
    let (ckpt, out, straight) = (file(&dir, "run.ckpt"), file(&dir, "run.exr"), file(&dir, "straight.exr"));
    // Sobol: a run extended past its --spp continues the very samples one longer run draws. (The
    // default zsobol's sets are the run's spp rounded up: extended, it draws new sets.)
    let settings = [
        "--integrator",
        "path",
        "--width",
        "24",
        "--height",
        "16",
        "--seed",
        "3",
        "--sky",
        "0.1,0.1,0.1",
        "--eye",
        "278,273,-700",
        "--target",
        "278,260,0",
        "--sampler",
        "sobol",
    ];
    let mut first = vec!["render", &scene, "-o", &out, "--spp", "4", "--checkpoint", &ckpt];
    first.extend_from_slice(&settings);
    ok(&vkrt(&first));
    // One word: the scene, size, seed, sky, camera and output come from the checkpoint.
    let said = ok(&vkrt(&["render", "--resume", &ckpt, "--spp", "8"]));
    assert!(said.contains(&format!("resuming {ckpt}: 4 spp done, going on to 8")), "no word of the resume: {said}");
    let mut whole = vec!["render", &scene, "-o", &straight, "--spp", "8"];
    whole.extend_from_slice(&settings);
    ok(&vkrt(&whole));
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&straight).unwrap(), "4 + 4 resumed spp differ from 8 in one run");
    let c = vkrt::integrator::path::checkpoint::Checkpoint::read(Path::new(&ckpt)).unwrap();
    assert_eq!(c.accum.samples, 8, "the resumed run did not keep saving into its checkpoint");
    // Flags that would change the image are errors naming the difference.
    let err = fails(&vkrt(&["render", "--resume", &ckpt, "--width", "32"]), "size differs");
    assert!(err.contains("24x16"), "{err}");
    fails(&vkrt(&["render", "--resume", &ckpt, "--fov", "20"]), "camera differs");
    fails(&vkrt(&["render", "--resume", &ckpt, "--sampler", "independent"]), "sampler differs: sobol");
    fails(&vkrt(&["render", "--resume", &ckpt, "--sampler", "zsobol"]), "sampler differs: sobol");
    // The Lambertian box lit by its lamp made light-vertex connections (the default, auto):
    // recorded, and a resumed run may not change the estimator.
    assert_eq!(c.settings.nee, vkrt::gpu_abi::constants::NEE_WITH_CONNECTIONS);
    let err = fails(&vkrt(&["render", "--resume", &ckpt, "--connections", "off"]), "light sampling differs");
    assert!(err.contains("with light-vertex connections"), "{err}");
    // One checkpoint becomes its image; an unknown output kind is an error.
    let merged = file(&dir, "merged.exr");
    ok(&vkrt(&["merge", &ckpt, "-o", &merged]));
    assert_eq!(std::fs::read(&merged).unwrap(), std::fs::read(&straight).unwrap());
    fails(&vkrt(&["merge", &ckpt, "-o", &file(&dir, "merged.txt")]), ".ckpt");
}

#[test]
fn names_and_help_are_consistent() {
    // Every flag of every command has a help line.
    let cli = vkrt::cli::Cli::command();
    for sub in cli.get_subcommands() {
        for arg in sub.get_arguments() {
            if arg.get_id() == "help" || arg.get_id() == "version" {
                continue;
            }
            assert!(arg.get_help().is_some(), "vkrt {} {}: no help", sub.get_name(), arg.get_id());
        }
        // -o/--output on every command that writes a file.
        if ["render", "trace", "merge"].contains(&sub.get_name()) {
            let out = sub.get_arguments().find(|a| a.get_id() == "output").unwrap_or_else(|| panic!("{} has no --output", sub.get_name()));
            assert_eq!(out.get_short(), Some('o'), "{} -o", sub.get_name());
        }
    }
    // Tables name builders as the flags do.
    let dir = common::scratch_dir("cli16-names");
    let o = vkrt(&[
        "bvh",
        &repo(MEASURED),
        "--format",
        "csv",
        "--width",
        "8",
        "--height",
        "8",
        "--repeat",
        "1",
        "--builders",
        "sah,sweep-sah",
        "--layouts",
        "threaded",
    ]);
    let csv = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success() && csv.contains(",sah,") && csv.contains(",sweep-sah,") && !csv.contains("SweepSah"), "{csv}");
    // compare: a difference picture and JSON.
    let (a, b) = (file(&dir, "a.exr"), file(&dir, "b.exr"));
    ok(&vkrt(&["render", &repo(MEASURED), "-o", &a, "--integrator", "path", "--spp", "2", "--width", "16", "--height", "16", "--seed", "1"]));
    ok(&vkrt(&["render", &repo(MEASURED), "-o", &b, "--integrator", "path", "--spp", "2", "--width", "16", "--height", "16", "--seed", "2"]));
    let diff = file(&dir, "diff.png");
    let o = vkrt(&["compare", &a, &b, "--diff", &diff, "--json"]);
    let json = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(o.status.success() && json.trim_start().starts_with('{') && json.contains("\"relmse\": ") && json.contains("\"mean_diff\": ["), "{json}");
    assert!(image::open(&diff).is_ok(), "no difference picture");
    // trace takes -o like every other command.
    let rays = dir.join("rays.npy");
    vkrt::output::npy::write_rays(
        &rays,
        &[vkrt::gpu_abi::GpuRay { origin: [278.0, 273.0, -500.0], tmin: 0.0, direction: [0.0, 0.0, 1.0], tmax: f32::INFINITY }],
    )
    .unwrap();
    ok(&vkrt(&["trace", &repo(MEASURED), "--rays", rays.to_str().unwrap(), "-o", &file(&dir, "hits.npy")]));
    assert!(dir.join("hits.npy").exists());
}

/// Writes an OBJ and MTL whose material name is Latin-1 ("Terraindæk"), with a red Kd.
fn latin1_scene(dir: &Path) -> PathBuf {
    let name: &[u8] = b"Terraind\xe6k";
    let mut mtl = b"newmtl ".to_vec();
    mtl.extend_from_slice(name);
    mtl.extend_from_slice(b"\nKd 0.9 0.1 0.1\n");
    std::fs::write(dir.join("latin.mtl"), mtl).unwrap();
    let mut obj = b"# made by an old exporter \xa9\nmtllib latin.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl ".to_vec();
    obj.extend_from_slice(name);
    obj.extend_from_slice(b"\nf 1 2 3 4\n");
    std::fs::write(dir.join("latin.obj"), obj).unwrap();
    dir.join("latin.obj")
}

#[test]
fn latin1_names_from_old_exporters_still_match() {
    let dir = common::scratch_dir("cli16-latin1");
    let obj = latin1_scene(&dir).display().to_string();
    let out = file(&dir, "latin.pfm");
    let err = ok(&vkrt(&["render", &obj, "-o", &out, "--width", "8", "--height", "8"]));
    assert!(err.contains("Latin-1"), "no encoding warning: {err}");
    assert!(!err.contains("no such material"), "usemtl did not match newmtl: {err}");
    // The material was found: the centre is red, not the default grey.
    let c = vkrt::output::read_image(Path::new(&out)).unwrap().get(4, 4);
    assert!(c[0] > 4.0 * c[1], "not the material's red: {c:?}");
    // --quiet silences the warning.
    let quiet = vkrt(&["render", &obj, "-o", &out, "--width", "8", "--height", "8", "--quiet"]);
    assert!(quiet.status.success() && quiet.stderr.is_empty(), "{}", stderr(&quiet));
}

/// `vkrt compare` says its verdict when asked to gate (issue 45): a pass line, a FAIL line
/// with exit 1, `"pass"` in JSON; it warns when a display picture meets linear radiance, and a
/// size mismatch that --downsample would fix names the flag.
#[test]
fn compare_says_its_verdict_warns_of_mixed_encodings_and_names_downsample() {
    let dir = common::scratch_dir("cli-compare-verdict");
    let render = |out: &str, size: &str, seed: &str| {
        ok(&vkrt(&["render", &repo(MEASURED), "-o", out, "--integrator", "path", "--spp", "2", "--width", size, "--height", size, "--seed", seed]));
    };
    let (a, b, big, png) = (file(&dir, "a.exr"), file(&dir, "b.exr"), file(&dir, "big.exr"), file(&dir, "a.png"));
    render(&a, "16", "1");
    render(&b, "16", "2");
    render(&big, "32", "1");
    render(&png, "16", "1");
    let same = vkrt(&["compare", &a, &a, "--max-relmse", "0"]);
    let text = String::from_utf8_lossy(&same.stdout).into_owned();
    assert!(same.status.success() && text.contains("verdict   pass: relMSE 0.000000e0 <= --max-relmse 0e0"), "{text}");
    let far = vkrt(&["compare", &a, &b, "--max-relmse", "1e-9"]);
    let text = String::from_utf8_lossy(&far.stdout).into_owned();
    assert!(text.contains("verdict   FAIL: relMSE"), "{text}");
    fails(&far, "exceeds --max-relmse");
    let json = vkrt(&["compare", &a, &a, "--max-relmse", "0", "--json"]);
    assert!(String::from_utf8_lossy(&json.stdout).contains("\"pass\": true"), "{}", String::from_utf8_lossy(&json.stdout));
    let without = vkrt(&["compare", &a, &b]);
    assert!(!String::from_utf8_lossy(&without.stdout).contains("verdict"), "a verdict nobody asked for");
    let mixed = vkrt(&["compare", &png, &a]);
    assert!(stderr(&mixed).contains("warning:") && stderr(&mixed).contains("8-bit picture"), "{}", stderr(&mixed));
    assert!(!stderr(&vkrt(&["compare", &a, &b])).contains("warning"), "a warning for two linear images");
    fails(&vkrt(&["compare", &big, &a]), "--downsample");
    ok(&vkrt(&["compare", &big, &a, "--downsample"]));
}

/// The lab Cornell box with its blocks as `Instances` renders the same bytes as with them as
/// `Models`: an identity and a translation place exactly as Models' Translation does.
#[test]
fn instances_render_as_the_models_they_stand_for() {
    let dir = common::scratch_dir("cli-instances");
    let lab = common::repo_path("scenes/lab/cornell_box");
    for mesh in ["wall.obj", "left.obj", "right.obj", "tall_block.obj", "short_block.obj"] {
        std::fs::copy(lab.join(mesh), dir.join(mesh)).unwrap();
    }
    // The lab's files have CRLF line ends.
    let original = std::fs::read_to_string(lab.join("cornell_box.yaml")).unwrap().replace("\r\n", "\n");
    let models =
        original.replace("  - Mesh: short_block.obj\n    Material: box\n", "  - Mesh: short_block.obj\n    Material: box\n    Translation: [10, 0, -20]\n");
    assert_ne!(models, original, "the short block's entry was not found");
    let blocks = "  - Mesh: tall_block.obj\n    Material: box\n  - Mesh: short_block.obj\n    Material: box\n    Translation: [10, 0, -20]\n";
    let instanced = models.replace(blocks, "")
        + "Instances:\n  - Mesh: tall_block.obj\n    Material: box\n    Transforms: [{}]\n  - Mesh: short_block.obj\n    Material: box\n    Transforms:\n      - Translation: [10, 0, -20]\n";
    assert!(!instanced.contains("Mesh: tall_block.obj\n    Material: box\n  - Mesh"), "the blocks are still Models");
    std::fs::write(dir.join("models.yaml"), models).unwrap();
    std::fs::write(dir.join("instanced.yaml"), instanced).unwrap();
    let render = |scene: &str, out: &str| {
        ok(&vkrt(&["render", &file(&dir, scene), "-o", &file(&dir, out), "--width", "48", "--height", "48"]));
        std::fs::read(dir.join(out)).unwrap()
    };
    assert_eq!(render("models.yaml", "m.pfm"), render("instanced.yaml", "i.pfm"));
}
