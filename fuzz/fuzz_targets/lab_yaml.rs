//! Fuzzes the course-lab YAML loader. A small valid mesh `m.obj` sits beside the scene so that
//! `Models: [{Mesh: m.obj}]` resolves. The loader must return a scene or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

const MESH: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("vkrt-fuzz-yaml-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let path = dir.join("f.yaml");
    if std::fs::write(dir.join("m.obj"), MESH).is_ok() && std::fs::write(&path, data).is_ok() {
        let _ = vkrt::scene::load_scene(&path);
    }
});
