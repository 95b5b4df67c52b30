//! Compiles the GLSL compute shaders to SPIR-V with glslang, and writes the generated GLSL
//! headers: the shared constants (`host/gpu_abi/constants.rs`) as `#define`s, and the BVH
//! layout a variant walks (`host/accel/kinds.rs`), so both sides name each number and each
//! layout once.
//!
//! Every variant of `host/pipeline/variants.rs` is compiled (in parallel): product shaders are
//! embedded through the generated `shaders.rs`, bench baselines only with the `bench` feature,
//! and test probes are left in `$OUT_DIR/probes/` for the tests. A shader error fails the build
//! with glslang's own `file:line` message.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "gpu_abi/constants.rs"]
#[allow(dead_code)]
mod constants;

#[path = "accel/kinds.rs"]
#[allow(dead_code)]
mod kinds;

#[path = "pipeline/variants.rs"]
#[allow(dead_code)]
mod variants;

use variants::Role;

fn main() {
    if let Err(message) = run() {
        eprintln!("{message}");
        std::process::exit(1);
    }
}

/// One SPIR-V to build.
struct Variant {
    name: String,
    shader: &'static variants::Shader,
    layout: &'static kinds::LayoutInfo,
    /// The build over a two-level BVH of instanced meshes (`TWO_LEVEL`), whose levels are in
    /// `layout` or a layout its walk covers (`kinds::LayoutInfo::two_level`).
    two_level: bool,
    spv: PathBuf,
}

fn run() -> Result<(), String> {
    let out = PathBuf::from(std::env::var("OUT_DIR").map_err(|e| format!("OUT_DIR: {e}"))?);
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").map_err(|e| format!("CARGO_MANIFEST_DIR: {e}"))?);
    let bench = std::env::var_os("CARGO_FEATURE_BENCH").is_some();
    let shaders = root.join("shaders");
    // The build's identity for the prepared-scene cache (host/prepare/cache.rs keys its entries
    // with it): a hash of every source of the host code and its dependencies' versions. An
    // entry's arrays are whatever the code that wrote them made, so no other build may read
    // them; a format number bumped by hand missed changes (an experiment's binary once left an
    // entry with another BVH that main's binary then rendered wrongly, 2026-12-07).
    for watched in ["host", "shaders", "Cargo.toml", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={watched}");
    }
    println!("cargo:rerun-if-env-changed=GLSLANG_VALIDATOR");
    println!("cargo:rustc-env=VKRT_SOURCE_HASH={:016x}", tree_hash(&root, &["host", "Cargo.toml", "Cargo.lock"])?);

    // So the script now runs after any change to the host code, but glslang only when the
    // shaders' own inputs (or glslang itself) changed: their hash is stamped beside the SPIR-V.
    let glslang = std::env::var("GLSLANG_VALIDATOR").unwrap_or_else(|_| "glslangValidator".into());
    let glslang_version = Command::new(&glslang).arg("--version").output().map(|o| String::from_utf8_lossy(&o.stdout).into_owned()).unwrap_or_default();
    let inputs = tree_hash(&root, &["shaders", "host/build.rs", "host/gpu_abi/constants.rs", "host/pipeline/variants.rs", "host/accel/kinds.rs"])?;
    let stamp = format!("inputs {inputs:016x}; bench {bench}; glslang {glslang}: {glslang_version}");
    let generated = out.join("glsl");
    let probes = out.join("probes");
    let mut list = Vec::new();
    for shader in variants::SHADERS {
        if shader.role == Role::Bench && !bench {
            continue;
        }
        let layouts: &[kinds::LayoutInfo] = if shader.per_layout { &kinds::LAYOUTS } else { &kinds::LAYOUTS[..1] };
        for layout in layouts {
            let name = if shader.per_layout { format!("{}_{}", shader.name, layout.id) } else { shader.name.to_string() };
            let dir = if shader.role == Role::Probe { &probes } else { &out };
            list.push(Variant { spv: dir.join(format!("{name}.spv")), name, shader, layout, two_level: false });
        }
        // Every product shader that walks a layout also walks the two-level BVH of a scene with
        // instances (accel::two_level): one build per two-level walk, with the define of the
        // layout that owns it (the threaded build walks multi-order levels too, their orders
        // being data).
        if shader.per_layout && shader.role == Role::Product {
            for layout in kinds::LAYOUTS.iter().filter(|l| l.two_level == Some(l.kind)) {
                let name = format!("{}_two_level_{}", shader.name, layout.id);
                list.push(Variant { spv: out.join(format!("{name}.spv")), name, shader, layout, two_level: true });
            }
        }
    }
    // Up to date: the same inputs, and every file the table includes still there (a SPIR-V
    // file deleted by hand would otherwise fail the build at its `include_bytes!`).
    let stamp_path = out.join("shaders.stamp");
    let all_there = out.join("shaders.rs").exists() && list.iter().all(|v| v.spv.exists());
    if all_there && std::fs::read_to_string(&stamp_path).is_ok_and(|s| s == stamp) {
        return Ok(());
    }
    for dir in [&generated, &probes] {
        std::fs::create_dir_all(dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
    }
    write_constants(&generated.join("constants.glsl"))?;
    write_layout_headers(&generated)?;
    compile_all(&glslang, &list, &shaders, &generated)?;
    write_table(&out.join("shaders.rs"), &list)?;
    std::fs::write(&stamp_path, stamp).map_err(|e| format!("writing {}: {e}", stamp_path.display()))
}

/// FNV-1a (64-bit) over the files under `paths` (files or folders, relative to `root`; missing
/// ones skipped): each file's relative path, length and bytes, in path order.
fn tree_hash(root: &Path, paths: &[&str]) -> Result<u64, String> {
    fn collect(dir: &Path, files: &mut Vec<PathBuf>) -> Result<(), String> {
        let entries = std::fs::read_dir(dir).map_err(|e| format!("reading {}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry.map_err(|e| format!("reading {}: {e}", dir.display()))?.path();
            if path.is_dir() {
                collect(&path, files)?;
            } else {
                files.push(path);
            }
        }
        Ok(())
    }
    let mut files = Vec::new();
    for p in paths {
        let path = root.join(p);
        if path.is_dir() {
            collect(&path, &mut files)?;
        } else if path.exists() {
            files.push(path);
        }
    }
    files.sort();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for b in bytes {
            h = (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in files {
        let bytes = std::fs::read(&f).map_err(|e| format!("reading {}: {e}", f.display()))?;
        eat(f.strip_prefix(root).unwrap_or(&f).to_string_lossy().as_bytes());
        eat(&(bytes.len() as u64).to_le_bytes());
        eat(&bytes);
    }
    Ok(h)
}

/// Compiles every variant, as many at a time as the machine has cores.
fn compile_all(glslang: &str, list: &[Variant], shaders: &Path, generated: &Path) -> Result<(), String> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(list.len().max(1));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let errors: Vec<String> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut errors = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(v) = list.get(i) else { break };
                        if let Err(e) = compile(glslang, v, shaders, generated) {
                            errors.push(e);
                        }
                    }
                    errors
                })
            })
            .collect();
        workers.into_iter().flat_map(|w| w.join().unwrap_or_else(|_| vec!["a shader compile thread panicked".into()])).collect()
    });
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("\n"))
    }
}

fn compile(glslang: &str, v: &Variant, shaders: &Path, generated: &Path) -> Result<(), String> {
    let mut cmd = Command::new(glslang);
    cmd.args(["-V", "--target-env", "vulkan1.2", "-Os"])
        .arg(format!("-I{}", shaders.join("include").display()))
        .arg(format!("-I{}", generated.display()))
        .arg(format!("-D{}", v.layout.define));
    for d in v.shader.defines {
        cmd.arg(format!("-D{d}"));
    }
    if v.two_level {
        cmd.arg("-DTWO_LEVEL");
    }
    cmd.arg("-o").arg(&v.spv).arg(shaders.join(v.shader.source));
    let output = cmd.output().map_err(|e| {
        format!(
            "could not run `{glslang}` to compile shaders ({e}).\n\
             Install glslang (Debian: glslang-tools), or run `tools/ensure-deps.sh` as root."
        )
    })?;
    if !output.status.success() {
        return Err(format!(
            "glslang failed on shaders/{} (variant {}):\n{}{}",
            v.shader.source,
            v.name,
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    Ok(())
}

/// `shaders.rs`: the embedded variants. A per-layout shader is an array in `LayoutKind` order,
/// and so are its two-level builds: each layout's entry is the build that walks two-level BVHs
/// laid out in it (`kinds::LayoutInfo::two_level`), None where there is none.
fn write_table(path: &Path, list: &[Variant]) -> Result<(), String> {
    let mut t = String::from("// Generated by host/build.rs: the SPIR-V of every embedded shader variant.\n");
    let embedded: Vec<&Variant> = list.iter().filter(|v| v.shader.role != Role::Probe).collect();
    let bytes = |v: &Variant| format!("include_bytes!({:?})", v.spv.display().to_string());
    for shader in variants::SHADERS {
        let of: Vec<&&Variant> = embedded.iter().filter(|v| std::ptr::eq(v.shader, shader)).collect();
        if of.is_empty() {
            continue;
        }
        let upper = shader.name.to_uppercase();
        if shader.per_layout {
            let _ = writeln!(t, "/// `{}` for each BVH layout, in `LayoutKind` order.", shader.name);
            let items: Vec<String> = of.iter().filter(|v| !v.two_level).map(|v| bytes(v)).collect();
            let _ = writeln!(t, "pub const {upper}: [&[u8]; {}] = [{}];", items.len(), items.join(", "));
            let two_level: Vec<String> = kinds::LAYOUTS
                .iter()
                .map(|l| match of.iter().find(|v| v.two_level && Some(v.layout.kind) == l.two_level) {
                    Some(v) => format!("Some({})", bytes(v)),
                    None => "None".to_string(),
                })
                .collect();
            if two_level.iter().any(|b| b != "None") {
                let _ = writeln!(
                    t,
                    "/// `{}` over a two-level BVH (`accel::two_level`) in each layout, in `LayoutKind` order.\npub const {upper}_TWO_LEVEL: [Option<&[u8]>; {}] = [{}];",
                    shader.name,
                    two_level.len(),
                    two_level.join(", ")
                );
            }
        } else {
            let _ = writeln!(t, "/// `{}`.\npub const {upper}: &[u8] = {};", shader.name, bytes(of[0]));
        }
    }
    t.push_str("/// Every embedded variant's name and SPIR-V.\npub const ALL: &[(&str, &[u8])] = &[\n");
    for v in &embedded {
        let _ = writeln!(t, "    ({:?}, {}),", v.name, bytes(v));
    }
    t.push_str("];\n");
    std::fs::write(path, t).map_err(|e| format!("writing {}: {e}", path.display()))
}

fn write_constants(path: &Path) -> Result<(), String> {
    let mut s = String::from("// Generated by host/build.rs from host/gpu_abi/constants.rs: do not edit.\n");
    s.push_str("#ifndef VKRT_CONSTANTS_GLSL\n#define VKRT_CONSTANTS_GLSL\n");
    for (name, value) in constants::ALL {
        // Small values stay int literals so they work in layout qualifiers; GLSL converts them
        // to uint where needed. Values past i32::MAX need the `u` suffix.
        let suffix = if *value > i32::MAX as u32 { "u" } else { "" };
        let _ = writeln!(s, "#define {name} {value}{suffix}");
    }
    // `{:?}` writes the shortest decimal that reads back as the same f32.
    for (name, [x, y, z]) in constants::ALL_VEC3 {
        let _ = writeln!(s, "const vec3 {name} = vec3({x:?}, {y:?}, {z:?});");
    }
    s.push_str("#endif\n");
    std::fs::write(path, s).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// `bvh_node.glsl` (BVH_NODE: the node struct of the variant's layout, for the probes) and
/// `bvh_walk.glsl` (the layout's traverse_<id>.glsl, for traverse.glsl), from `LAYOUTS`.
fn write_layout_headers(dir: &Path) -> Result<(), String> {
    let chain = |guard: &str, body: &dyn Fn(&kinds::LayoutInfo) -> String| {
        let mut s = String::from("// Generated by host/build.rs from host/accel/kinds.rs: do not edit.\n");
        let _ = writeln!(s, "#ifndef {guard}\n#define {guard}");
        for (i, l) in kinds::LAYOUTS.iter().enumerate() {
            let _ = writeln!(s, "#{} defined({})\n{}", if i == 0 { "if" } else { "elif" }, l.define, body(l));
        }
        let defines: Vec<&str> = kinds::LAYOUTS.iter().map(|l| l.define).collect();
        let _ = writeln!(s, "#else\n#error \"no BVH layout selected: define one of {}\"\n#endif\n#endif", defines.join(", "));
        s
    };
    let node = chain("VKRT_BVH_NODE_GLSL", &|l| format!("#define BVH_NODE {}", l.node_struct));
    let walk = chain("VKRT_BVH_WALK_GLSL", &|l| format!("#include \"traverse_{}.glsl\"", l.id));
    for (name, text) in [("bvh_node.glsl", node), ("bvh_walk.glsl", walk)] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("writing {}: {e}", path.display()))?;
    }
    Ok(())
}
