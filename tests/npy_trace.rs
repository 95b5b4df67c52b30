//! `.npy` ray and hit files: round trips, malformed files rejected with the file named and no
//! panic, and `vkrt trace` / `vkrt bvh` end to end on a small scene for every layout.

mod common;

use vkrt::accel::{leaf, LayoutKind};
use vkrt::bvh::BuilderKind;
use vkrt::cli::bvh::{format_rows, BvhArgs, Format};
use vkrt::cli::trace::run;
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::GpuRay;
use vkrt::output::npy::{parse_header, read_hits, write_rays, RayReader};

fn rays(n: usize) -> Vec<GpuRay> {
    (0..n).map(|i| GpuRay { origin: [i as f32, 1.0, 2.0], tmin: 0.0, direction: [0.0, 0.0, -1.0], tmax: f32::INFINITY }).collect()
}

#[test]
fn rays_round_trip_in_batches() {
    let dir = common::scratch_dir("npy-round-trip");
    let path = dir.join("rays.npy");
    let original = rays(1000);
    write_rays(&path, &original).unwrap();
    // The header pads the data to a 64-byte boundary, as numpy does.
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!((bytes.len() - 1000 * 32) % 64, 0);
    let mut reader = RayReader::open(&path).unwrap();
    assert_eq!(reader.count(), 1000);
    let mut back = Vec::new();
    loop {
        let batch = reader.next_batch(300).unwrap();
        if batch.is_empty() {
            break;
        }
        assert!(batch.len() <= 300);
        back.extend(batch);
    }
    assert_eq!(back, original);
}

#[test]
fn header_parser_reads_what_numpy_writes() {
    let h = parse_header("{'descr': '<f4', 'fortran_order': False, 'shape': (12, 8), }        \n").unwrap();
    assert_eq!((h.descr.as_str(), h.fortran_order, h.shape.as_slice()), ("<f4", false, &[12u64, 8][..]));
    let h = parse_header("{'descr': [('t', '<f4'), ('prim', '<u4'), ('u', '<f4'), ('v', '<f4')], 'fortran_order': False, 'shape': (3,), }").unwrap();
    assert_eq!(h.descr, vkrt::output::npy::HIT_DESCR);
    assert_eq!(h.shape, vec![3]);
}

/// Every kind of broken file is an error that names the file, never a panic.
#[test]
fn malformed_ray_files_are_rejected_with_the_file_named() {
    let dir = common::scratch_dir("npy-malformed");
    let good = dir.join("good.npy");
    write_rays(&good, &rays(4)).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    let header = |dict: &str| {
        let text = format!("{dict:<118}\n");
        let mut b = b"\x93NUMPY\x01\x00".to_vec();
        b.extend_from_slice(&(text.len() as u16).to_le_bytes());
        b.extend_from_slice(text.as_bytes());
        b
    };
    let with_data = |mut h: Vec<u8>, n: usize| {
        h.extend(std::iter::repeat(0u8).take(n));
        h
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "too short"),
        ("magic", b"PK\x03\x04 not numpy at all".to_vec(), "bad magic"),
        ("version", b"\x93NUMPY\x09\x00\x10\x00".to_vec(), "version"),
        ("truncated-header", bytes[..20].to_vec(), "truncated header"),
        ("truncated-data", bytes[..bytes.len() - 5].to_vec(), "bytes of data"),
        ("extra-data", [bytes.clone(), vec![0; 32]].concat(), "bytes of data"),
        ("f8", with_data(header("{'descr': '<f8', 'fortran_order': False, 'shape': (1, 8), }"), 64), "float32"),
        ("big-endian", with_data(header("{'descr': '>f4', 'fortran_order': False, 'shape': (1, 8), }"), 32), "float32"),
        ("shape", with_data(header("{'descr': '<f4', 'fortran_order': False, 'shape': (4, 6), }"), 96), "(N, 8)"),
        ("1d", with_data(header("{'descr': '<f4', 'fortran_order': False, 'shape': (8,), }"), 32), "(N, 8)"),
        ("fortran", with_data(header("{'descr': '<f4', 'fortran_order': True, 'shape': (1, 8), }"), 32), "C order"),
        ("no-shape", with_data(header("{'descr': '<f4', 'fortran_order': False, }"), 32), "no 'shape'"),
        ("bad-shape", with_data(header("{'descr': '<f4', 'fortran_order': False, 'shape': (x, 8), }"), 32), "not a count"),
        ("huge-shape", with_data(header("{'descr': '<f4', 'fortran_order': False, 'shape': (18446744073709551615, 8), }"), 32), "bytes of data"),
        ("not-dict", with_data(header("['descr', '<f4']"), 32), "dict"),
    ];
    for (name, contents, expected) in cases {
        let path = dir.join(format!("{name}.npy"));
        std::fs::write(&path, &contents).unwrap();
        let err = match RayReader::open(&path) {
            Ok(_) => panic!("{name}: accepted a malformed file"),
            Err(e) => format!("{e:#}"),
        };
        assert!(err.contains(&path.display().to_string()), "{name}: error does not name the file: {err}");
        assert!(err.contains(expected), "{name}: expected '{expected}' in: {err}");
    }
    let missing = dir.join("missing.npy");
    let err = RayReader::open(&missing).err().map(|e| format!("{e:#}")).unwrap_or_default();
    assert!(err.contains("missing.npy"), "{err}");
}

/// `vkrt trace` on the Cornell box for every layout: hits equal brute force, misses are encoded
/// as documented, and the output is a valid hit file.
#[test]
fn trace_command_matches_brute_force_for_every_layout() {
    let scene_path = common::repo_path("scenes/cornell-measured/cornell.obj");
    let scene = vkrt::scene::load_scene(&scene_path).unwrap();
    let dir = common::scratch_dir("trace-command");
    let mut all = vkrt::query::rays::incoherent(&scene, 2000, 5);
    // One ray that certainly misses: from outside, pointing away.
    let b = scene.bounds();
    all.push(GpuRay { origin: (b.max + b.extent()).to_array(), tmin: 0.0, direction: [1.0, 1.0, 1.0], tmax: f32::INFINITY });
    let rays_path = dir.join("rays.npy");
    write_rays(&rays_path, &all).unwrap();
    // Every layout by name, and the default (None: multi-order for a scene this small).
    for layout in LayoutKind::ALL.into_iter().map(Some).chain([None]) {
        let name = layout.map_or("default", |l| l.name());
        let out = dir.join(format!("hits-{name}.npy"));
        let report = run(&common::trace_args(&scene_path, &rays_path, &out, layout)).unwrap();
        assert_eq!(report.rays, all.len() as u64);
        assert!(report.nodes_visited > 0);
        let hits = read_hits(&out).unwrap();
        assert_eq!(hits.len(), all.len());
        for (i, (r, h)) in all.iter().zip(&hits).enumerate() {
            let brute = leaf::brute_force(&scene.triangles, r);
            assert_eq!(h.prim, brute.prim, "{name} ray {i}");
            if brute.prim == PRIM_NONE {
                assert_eq!(h.t, f32::INFINITY);
            } else {
                assert!((h.t - brute.t).abs() <= 1e-5 * brute.t.abs(), "{name} ray {i}: t {} vs {}", h.t, brute.t);
            }
        }
        assert_eq!(hits.last().map(|h| h.prim), Some(PRIM_NONE));
    }
}

/// `vkrt bvh` on the Cornell box: one row per builder x layout with sane numbers, every format,
/// and a heat map file.
#[test]
fn bvh_table_covers_every_builder_and_layout() {
    let scene_path = common::repo_path("scenes/cornell-measured/cornell.obj");
    let scene = vkrt::scene::load_scene(&scene_path).unwrap();
    let dir = common::scratch_dir("bvh-table");
    let heat = dir.join("heat.png");
    let _ = std::fs::remove_file(&heat);
    let args = BvhArgs {
        scenes: vec![scene_path.clone()],
        format: Format::Table,
        width: 32,
        height: 32,
        repeat: 1,
        heatmap: Some(heat.clone()),
        heatmap_builder: BuilderKind::Sah,
        heatmap_layout: LayoutKind::ParentLink,
        builders: vec![],
        layouts: vec![],
        device: vkrt::cli::DeviceArgs { device: None },
    };
    let ctx = common::gpu_context();
    let rows = vkrt::cli::bvh::scene_rows(&ctx, &scene_path, &scene, &args).unwrap();
    assert_eq!(rows.len(), BuilderKind::ALL.len() * LayoutKind::ALL.len());
    for r in &rows {
        assert!(r.sah > 0.0 && r.nodes > 0 && r.bytes > 0, "{r:?}");
        assert!(r.primary.nodes_per_ray >= 1.0 && r.primary.rays_per_second > 0.0, "{r:?}");
    }
    let img = image::open(&heat).unwrap();
    assert_eq!((img.width(), img.height() > 32), (32, true));
    let csv = format_rows(&rows, Format::Csv, "dev");
    assert_eq!(csv.lines().count(), rows.len() + 1);
    let json = format_rows(&rows, Format::Json, "dev");
    assert_eq!(json.matches("\"builder\"").count(), rows.len());
    assert!(format_rows(&rows, Format::Table, "dev").contains("| cornell.obj |"));
    common::assert_no_validation_messages(&ctx);
}
