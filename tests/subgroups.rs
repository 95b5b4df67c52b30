//! Images and hits do not depend on the device's subgroup size. lavapipe runs 8-wide subgroups,
//! 4-wide ones with LP_NATIVE_VECTOR_WIDTH=128 (any x86 CPU) and 16-wide ones with
//! LP_NATIVE_VECTOR_WIDTH=512 (on a CPU with AVX-512): the same renders and ray queries under
//! each must give the same bytes, since nothing vkrt computes depends on how the device groups
//! lanes (gpu::Workgroups only groups them for execution; adaptive and coherence blocks are
//! fixed pixel blocks). tools/test also runs the GPU tests again with each other width.

mod common;

use std::path::Path;
use std::process::Command;

/// vkrt at lavapipe's vector width `width`, with a Mesa shader cache of that width's own:
/// llvmpipe's cache keys do not hold the width, and code compiled at one width was found under
/// another's key (shader objects against pipelines, docs/experiments/shader-binaries.md), which
/// would crash or hang the suite's other tests.
fn vkrt(width: &str, args: &[&str]) -> std::process::Output {
    let mesa_cache = common::scratch_dir("subgroups").join(format!("mesa-{width}"));
    Command::new(env!("CARGO_BIN_EXE_vkrt"))
        .env("LP_NATIVE_VECTOR_WIDTH", width)
        .env("MESA_SHADER_CACHE_DIR", mesa_cache)
        .args(args)
        .output()
        .expect("run vkrt")
}

/// The LP_NATIVE_VECTOR_WIDTH values to compare with lavapipe's 8-wide default, with the
/// subgroup size each gives: 4-wide on lavapipe, 16-wide too on a CPU with AVX-512; none on
/// another device (prints why).
fn other_widths() -> Vec<(&'static str, &'static str)> {
    use std::io::Write as _;
    let info = vkrt("256", &["info"]);
    let text = String::from_utf8_lossy(&info.stdout).into_owned();
    let lavapipe = text.lines().find(|l| l.contains("<- vkrt uses this one")).is_some_and(|l| l.contains("llvmpipe")) || text.contains("llvmpipe");
    if !lavapipe {
        let _ = writeln!(std::io::stderr(), "SKIPPED: other subgroup sizes need lavapipe");
        return Vec::new();
    }
    let mut widths = vec![("128", "subgroup size: 4")];
    if std::fs::read_to_string("/proc/cpuinfo").is_ok_and(|c| c.contains(" avx512f")) {
        widths.push(("512", "subgroup size: 16"));
    } else {
        let _ = writeln!(std::io::stderr(), "16-wide subgroups not compared: they need a CPU with AVX-512");
    }
    widths
}

#[test]
fn renders_and_hits_are_the_same_bytes_with_4_8_and_16_wide_subgroups() {
    let others = other_widths();
    if others.is_empty() {
        return;
    }
    let widths: Vec<&str> = std::iter::once("256").chain(others.iter().map(|w| w.0)).collect();
    // Each leg really changes the subgroup size.
    for (width, want) in std::iter::once(("256", "subgroup size: 8")).chain(others.iter().copied()) {
        let text = String::from_utf8_lossy(&vkrt(width, &["info"]).stdout).into_owned();
        assert!(text.contains(want), "LP_NATIVE_VECTOR_WIDTH={width}: {text}");
    }
    let dir = common::scratch_dir("subgroups");
    let lab = common::repo_path("scenes/lab/cornell_box/cornell_box.yaml").display().to_string();
    let measured = common::repo_path("scenes/cornell-measured/cornell.yaml").display().to_string();
    let small = ["--width", "40", "--height", "24", "--quiet"];
    let cases: Vec<(&str, Vec<&str>)> = vec![
        ("whitted.pfm", vec!["render", &lab, "--spp", "2"]),
        ("path.pfm", vec!["render", &measured, "--integrator", "path", "--spp", "8"]),
        ("adaptive.pfm", vec!["render", &measured, "--integrator", "path", "--spp", "16", "--adaptive", "--coherence", "4", "--coherence-block", "0"]),
        ("adaptive-squares.pfm", vec!["render", &measured, "--integrator", "path", "--spp", "16", "--adaptive"]),
        ("uncorrelated.pfm", vec!["render", &measured, "--integrator", "path", "--spp", "8", "--coherence", "1"]),
        ("wide-layout.pfm", vec!["render", &measured, "--integrator", "path", "--spp", "4", "--layout", "wide"]),
    ];
    for (name, args) in &cases {
        let mut outputs = Vec::new();
        for width in &widths {
            let out = dir.join(format!("{width}-{name}"));
            let mut all = args.clone();
            let out_s = out.display().to_string();
            all.extend(["-o", out_s.as_str()]);
            all.extend_from_slice(&small);
            let o = vkrt(width, &all);
            assert!(o.status.success(), "{name} at {width} bits: {}", String::from_utf8_lossy(&o.stderr));
            outputs.push(std::fs::read(&out).unwrap());
        }
        for (width, output) in widths.iter().zip(&outputs).skip(1) {
            assert!(*output == outputs[0], "{name}: LP_NATIVE_VECTOR_WIDTH={width} rendered another image than the 8-wide subgroups");
        }
    }
    // Batch queries: the same hits and the same traversal counters.
    let rays: Vec<vkrt::gpu_abi::GpuRay> = (0..4000)
        .map(|i| {
            let a = i as f32 * 0.37;
            vkrt::gpu_abi::GpuRay { origin: [278.0, 273.0, 200.0], tmin: 0.0, direction: [a.cos(), (a * 0.7).sin(), a.sin()], tmax: f32::INFINITY }
        })
        .collect();
    let ray_file = dir.join("rays.npy");
    vkrt::output::npy::write_rays(&ray_file, &rays).unwrap();
    let mut logs = Vec::new();
    let mut hits = Vec::new();
    for width in &widths {
        let out = dir.join(format!("{width}-hits.npy"));
        let o = vkrt(width, &["trace", &measured, "--rays", ray_file.to_str().unwrap(), "-o", out.to_str().unwrap(), "--layout", "multi-order"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let log = String::from_utf8_lossy(&o.stderr).into_owned();
        // The counters at the end of the report ("... nodes visited and ... per ray").
        logs.push(log.rsplit(": ").next().unwrap_or("").split(" M rays/s").last().unwrap_or("").to_string());
        hits.push(std::fs::read(Path::new(&out)).unwrap());
    }
    for (k, width) in widths.iter().enumerate().skip(1) {
        assert!(hits[k] == hits[0], "hits differ between 8-wide subgroups and LP_NATIVE_VECTOR_WIDTH={width}");
        assert_eq!(logs[k], logs[0], "traversal counters differ at LP_NATIVE_VECTOR_WIDTH={width}");
    }
}
