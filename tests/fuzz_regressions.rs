//! Every input in fuzz/regressions/ (crashers found by fuzzing, and seeds written by hand for
//! the crashes tobj had) loads without a panic: it gives a scene or an error naming the file.

use std::path::Path;

const MESH: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// Sets up the input as the fuzz target does and loads it; returns the load result's text.
fn load(kind: &str, data: &[u8], dir: &Path) -> Result<String, String> {
    std::fs::create_dir_all(dir).unwrap();
    // The bytes after the first 0xFF (never in UTF-8 text) are the file the first part may name.
    let split = |data: &'_ [u8]| match data.iter().position(|&b| b == 0xFF) {
        Some(i) => (data[..i].to_vec(), data[i + 1..].to_vec()),
        None => (data.to_vec(), Vec::new()),
    };
    let path = if kind == "obj" {
        let (obj, mtl) = split(data);
        std::fs::write(dir.join("f.mtl"), mtl).unwrap();
        std::fs::write(dir.join("f.obj"), obj).unwrap();
        dir.join("f.obj")
    } else if kind == "gltf" && data.starts_with(b"glTF") {
        std::fs::write(dir.join("f.glb"), data).unwrap();
        dir.join("f.glb")
    } else if kind == "gltf" {
        let (gltf, bin) = split(data);
        std::fs::write(dir.join("f.bin"), bin).unwrap();
        std::fs::write(dir.join("f.gltf"), gltf).unwrap();
        dir.join("f.gltf")
    } else {
        std::fs::write(dir.join("m.obj"), MESH).unwrap();
        std::fs::write(dir.join("f.yaml"), data).unwrap();
        dir.join("f.yaml")
    };
    match vkrt::scene::load_scene(&path) {
        Ok(scene) => Ok(format!("{} triangles", scene.triangles.len())),
        Err(e) => Err(format!("{e:#}")),
    }
}

#[test]
fn fuzz_regressions_load_without_panicking() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions");
    let scratch = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-output/fuzz-regressions");
    let mut count = 0;
    for kind in ["obj", "yaml", "gltf"] {
        let mut files: Vec<_> = std::fs::read_dir(root.join(kind)).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
        for file in files {
            let data = std::fs::read(&file).unwrap();
            let dir = scratch.join(kind);
            let result = std::panic::catch_unwind(|| load(kind, &data, &dir));
            let outcome = result.unwrap_or_else(|_| panic!("{} panicked the {kind} loader", file.display()));
            // An error must name the file it is about.
            if let Err(message) = &outcome {
                let named = ["f.obj", "f.yaml", "f.mtl", "f.gltf", "f.glb"].iter().any(|f| message.contains(f));
                assert!(named, "{}: error names no file: {message}", file.display());
            }
            println!("{}: {outcome:?}", file.display());
            count += 1;
        }
    }
    assert!(count >= 6, "only {count} regression inputs found");
}
