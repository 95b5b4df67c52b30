//! Fuzzes the glTF 2.0 loader (host/scene/gltf/). An input that starts with the binary magic
//! `glTF` is a `.glb`; anything else is a `.gltf` (JSON), optionally followed by a 0xFF byte
//! (never in UTF-8 text) and the bytes of `f.bin`, the external buffer it may name. The loader
//! must return a scene or an error, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("vkrt-fuzz-gltf-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let (name, file, bin) = if data.starts_with(b"glTF") {
        ("f.glb", data, &[][..])
    } else {
        match data.iter().position(|&b| b == 0xFF) {
            Some(i) => ("f.gltf", &data[..i], &data[i + 1..]),
            None => ("f.gltf", data, &[][..]),
        }
    };
    let path = dir.join(name);
    if std::fs::write(&path, file).is_ok() && std::fs::write(dir.join("f.bin"), bin).is_ok() {
        let _ = vkrt::scene::load_scene(&path);
    }
});
