//! The two-level BVH over instanced meshes (`accel::two_level`, issue 44), in each layout its
//! levels take (every layout: threaded, multi-order, parent-link, compact, wide): its walk on the GPU (the tracing shaders'
//! `_two_level_<id>` builds) against its CPU twin, hit for hit and counter for counter, and
//! both against the expanded scene the loaders make of the same copies.

mod common;

use common::closed_meshes::{icosphere, subdivided_cube};
use glam::Vec3;
use vkrt::accel::leaf::brute_force;
use vkrt::accel::two_level::LAYOUTS;
use vkrt::accel::LayoutKind;
use vkrt::gpu_abi::constants::PRIM_NONE;
use vkrt::gpu_abi::{GpuHit, GpuRay};
use vkrt::prepare::{build_two_level, GpuBvh, PrepareOptions};
use vkrt::query::ray_query::trace_rays;
use vkrt::rng::Pcg32;
use vkrt::scene::instance::{add_group, Placement};
use vkrt::scene::{Scene, Triangle};

/// A ground of two triangles (no instance's: the identity instance) and two groups of copies.
fn scene_with(groups: &[(Vec<Triangle>, Vec<Placement>)]) -> Scene {
    let mut scene = Scene::default();
    let g = [Vec3::new(-40.0, -2.0, -40.0), Vec3::new(40.0, -2.0, -40.0), Vec3::new(40.0, -2.0, 40.0), Vec3::new(-40.0, -2.0, 40.0)];
    scene.triangles.push(Triangle { p: [g[0], g[2], g[1]], n: None, uv: None, material: 0 });
    scene.triangles.push(Triangle { p: [g[0], g[3], g[2]], n: None, uv: None, material: 0 });
    for (mesh, placements) in groups {
        add_group(&mut scene, mesh, placements.clone());
    }
    scene
}

fn translation(x: f32, y: f32, z: f32) -> Placement {
    Placement::from_trs(Vec3::new(x, y, z), Vec3::ZERO, Vec3::ONE).unwrap()
}

/// Copies turned, scaled (unevenly too) and mirrored, of a sphere (with vertex normals) and a
/// cube.
fn turned_scene() -> Scene {
    let mut sphere = icosphere(2).to_triangles(1.0, Vec3::ZERO, 0);
    for t in &mut sphere {
        t.n = Some(t.p.map(|p| p.normalize()));
    }
    let cube = subdivided_cube(3).to_triangles(1.0, Vec3::ZERO, 0);
    let mut rng = Pcg32::new(7);
    let mut spheres = Vec::new();
    let mut cubes = Vec::new();
    for i in 0..6 {
        for j in 0..6 {
            let at = Vec3::new(i as f32 * 5.0 - 12.5, 0.0, j as f32 * 5.0 - 12.5);
            let turn = Vec3::new(rng.range(0.0, 360.0), rng.range(0.0, 360.0), rng.range(0.0, 360.0));
            let mirror = if (i + j) % 3 == 0 { -1.0 } else { 1.0 };
            let scale = Vec3::new(mirror * rng.range(0.5, 1.5), rng.range(0.5, 1.5), rng.range(0.5, 1.5));
            let p = Placement::from_trs(at, turn, scale).unwrap();
            if (i + j) % 2 == 0 {
                spheres.push(p)
            } else {
                cubes.push(p)
            }
        }
    }
    scene_with(&[(sphere, spheres), (cube, cubes)])
}

/// Cubes on a grid of 1/2 steps, moved by whole numbers: every coordinate and every difference
/// the walk takes is exact in both forms.
fn translated_scene() -> Scene {
    let cube = subdivided_cube(4).to_triangles(1.0, Vec3::ZERO, 0);
    let placements = (0..25).map(|k| translation((k % 5) as f32 * 3.0 - 6.0, (k % 2) as f32, (k / 5) as f32 * 3.0 - 6.0)).collect();
    scene_with(&[(cube, placements)])
}

/// Rays from around the scene to random points in it, and from inside it in random directions.
fn rays(n: usize, seed: u64, grid: bool) -> Vec<GpuRay> {
    let mut rng = Pcg32::new(seed);
    // On the grid scene origins are multiples of 1/8, so that their moves into object space are exact.
    let snap = |v: Vec3| if grid { (v * 8.0).round() / 8.0 } else { v };
    (0..n)
        .map(|i| {
            let (origin, dir) = if i % 2 == 0 {
                let o = snap(rng.unit_vector() * 40.0);
                let target = Vec3::new(rng.range(-15.0, 15.0), rng.range(-2.0, 2.0), rng.range(-15.0, 15.0));
                (o, target - o)
            } else {
                (snap(Vec3::new(rng.range(-15.0, 15.0), rng.range(-1.5, 3.0), rng.range(-15.0, 15.0))), rng.unit_vector())
            };
            GpuRay { origin: origin.to_array(), tmin: 0.0, direction: dir.to_array(), tmax: f32::INFINITY }
        })
        .collect()
}

/// The scene's two-level BVH with its levels in `layout`.
fn two_level_in(scene: &Scene, layout: LayoutKind) -> vkrt::accel::FlatBvh {
    let flat = build_two_level(scene, &PrepareOptions { layout, ..PrepareOptions::default() }).unwrap().0;
    assert_eq!(flat.layout(), layout);
    flat
}

#[test]
fn groups_keep_one_mesh_and_number_their_copies_after_the_scene_s_triangles() {
    let scene = turned_scene();
    assert_eq!(scene.instances.len(), 2);
    assert_eq!(scene.triangles.len(), 2, "only the ground is the scene's own");
    assert_eq!(scene.instances[0].first, 2);
    let expanded = scene.expanded().unwrap();
    assert!(expanded.instances.is_empty());
    assert_eq!(expanded.triangles.len() as u64, scene.placed_triangles());
    // Each copy is its placement of the mesh, from its first primitive on.
    let g = &scene.instances[1];
    let (first, placement) = g.copies().nth(3).unwrap();
    assert_eq!(u64::from(first), 2 + scene.instances[0].placed_triangles() + 3 * g.mesh.len() as u64);
    let copy = &expanded.triangles[first as usize..][..g.mesh.len()];
    for (i, (t, object)) in copy.iter().zip(&g.mesh).enumerate() {
        let mut p = object.p.map(|v| placement.world().transform_point3(v));
        if placement.mirrored() {
            p.swap(1, 2);
        }
        assert_eq!(t.p, p);
        assert_eq!(Some(*t), scene.triangle(first + i as u32), "Scene::triangle places the copy's triangle alike");
    }
}

#[test]
fn a_mesh_s_degenerate_triangles_are_dropped_once_per_copy() {
    let mesh = vec![
        Triangle { p: [Vec3::ZERO, Vec3::X, Vec3::Y], n: None, uv: None, material: 0 },
        Triangle { p: [Vec3::ZERO, Vec3::X, Vec3::X * 2.0], n: None, uv: None, material: 0 },
    ];
    let mut scene = Scene::default();
    add_group(&mut scene, &mesh, vec![translation(0.0, 0.0, 0.0), translation(3.0, 0.0, 0.0), translation(6.0, 0.0, 0.0)]);
    assert_eq!(scene.instances.len(), 1);
    assert_eq!(scene.instances[0].mesh.len(), 1);
    assert_eq!((scene.placed_triangles(), scene.stats.dropped_degenerate), (3, 3));
}

#[test]
fn exact_translations_hit_as_the_expanded_scene_bit_for_bit() {
    let scene = translated_scene();
    let expanded = scene.expanded().unwrap();
    for layout in LAYOUTS {
        let flat = two_level_in(&scene, layout);
        assert_eq!(flat.nodes.instances().len(), 26, "25 copies and the ground");
        // One copy of the cube in memory, not 25.
        assert_eq!(flat.triangles.len(), 192 + 2);
        for ray in rays(4000, 1, true) {
            let expected = brute_force(&expanded.triangles, &ray);
            let got = flat.trace(&ray, false);
            assert_eq!(
                (got.t.to_bits(), got.prim, got.u.to_bits(), got.v.to_bits()),
                (expected.t.to_bits(), expected.prim, expected.u.to_bits(), expected.v.to_bits()),
                "{}: {ray:?}",
                layout.name()
            );
        }
    }
}

/// The multi-order levels hold six orders of each tree (the instances say where a mesh's
/// start) and, walked near-first in the order of the ray's direction in each level's space,
/// visit fewer nodes than the threaded levels for the same hits.
#[test]
fn multi_order_levels_walk_each_copy_in_the_order_of_its_own_space() {
    let scene = turned_scene();
    let threaded = two_level_in(&scene, LayoutKind::Threaded);
    let multi = two_level_in(&scene, LayoutKind::MultiOrder);
    assert_eq!(multi.node_count(), 6 * threaded.node_count());
    // Six orders of the top level from index 0, then six of each mesh's tree from its root.
    assert_eq!(threaded.push().top_order_nodes, 0);
    let mut meshes: Vec<(u32, u32)> = multi.nodes.instances().iter().map(|i| (i.root, i.order_nodes)).collect();
    meshes.sort();
    meshes.dedup();
    assert_eq!(meshes.len(), 3, "two meshes and the ground");
    let top = multi.push().top_order_nodes;
    assert_eq!(meshes[0].0, 6 * top);
    assert_eq!(6 * (top + meshes.iter().map(|m| m.1).sum::<u32>()) as usize, multi.node_count());
    for (a, b) in threaded.nodes.instances().iter().zip(multi.nodes.instances()) {
        assert_eq!((a.order_nodes, a.prim_base, a.shading_base), (0, b.prim_base, b.shading_base));
        assert!(b.order_nodes > 0);
    }
    let (mut nodes_threaded, mut nodes_multi) = (0u64, 0u64);
    for ray in rays(4000, 12, false) {
        let (a, b) = (threaded.trace(&ray, false), multi.trace(&ray, false));
        assert_eq!((a.t.to_bits(), a.prim), (b.t.to_bits(), b.prim), "{ray:?}");
        nodes_threaded += u64::from(a.nodes_visited);
        nodes_multi += u64::from(b.nodes_visited);
    }
    assert!(nodes_multi < nodes_threaded, "multi-order {nodes_multi} nodes against threaded {nodes_threaded}");
}

/// Parent-link and wide levels, whose walks order a node's children by the ray's direction: a
/// turned, unevenly scaled copy is walked as the mesh's own one-level tree in that layout walks
/// the object-space ray, node for node (its children ordered by the object-space direction,
/// the walk ending where that tree is done). Parent-link trees start at even indices (siblings
/// are the pairs 2k, 2k + 1).
#[test]
fn parent_link_and_wide_levels_walk_a_copy_as_its_mesh_s_own_tree_walks_the_object_space_ray() {
    use vkrt::accel::two_level::object_ray;
    use vkrt::accel::{parent_link, wide, NodeArray};
    use vkrt::geom::Aabb;
    use vkrt::gpu_abi::GpuTriangle;

    let sphere = icosphere(3).to_triangles(1.0, Vec3::ZERO, 0);
    let mut scene = Scene::default();
    add_group(&mut scene, &sphere, vec![Placement::from_trs(Vec3::new(1.0, 2.0, 3.0), Vec3::new(30.0, 70.0, -20.0), Vec3::new(2.0, 0.5, 1.0)).unwrap()]);
    // (layout, where the mesh's tree starts, top-level visits of a ray that enters the copy):
    // the parent-link top level is a leaf and its filler, visited once; the wide one a node
    // with one slot, visited again when the mesh's tree is done.
    for (layout, root, top_visits) in [(LayoutKind::ParentLink, 2, 1), (LayoutKind::Wide, 1, 2)] {
        let options = PrepareOptions { layout, ..PrepareOptions::default() };
        let flat = build_two_level(&scene, &options).unwrap().0;
        let instance = flat.nodes.instances()[0];
        assert_eq!(instance.root, root, "{}: one top-level node, then the mesh's tree", layout.name());

        // The mesh's own tree, by the same builder, in the one-level layout.
        let positions: Vec<[Vec3; 3]> = scene.instances[0].mesh.iter().map(|t| t.p).collect();
        let boxes: Vec<Aabb> = positions.iter().map(|p| Aabb::from_points(p)).collect();
        let centroids: Vec<Vec3> = positions.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
        let tree = vkrt::bvh::build(options.builder, &boxes, &centroids, &options.build);
        let own: Box<dyn NodeArray> = match layout {
            LayoutKind::ParentLink => Box::new(parent_link::ParentLink(parent_link::flatten(&tree).unwrap())),
            _ => Box::new(wide::Wide(wide::flatten(&tree).unwrap())),
        };
        let tris: Vec<GpuTriangle> = tree
            .prim_indices
            .iter()
            .map(|&i| {
                let p = positions[i as usize];
                GpuTriangle { v0: p[0].to_array(), prim: i, v1: p[1].to_array(), shading: i, v2: p[2].to_array(), _pad1: 0 }
            })
            .collect();
        assert_eq!(flat.node_count(), root as usize + own.count());

        let mut rng = Pcg32::new(21);
        let (mut walked, mut reordered) = (0, 0);
        for _ in 0..3000 {
            let origin = Vec3::new(1.0, 2.0, 3.0) + rng.unit_vector() * 12.0;
            let target = Vec3::new(1.0, 2.0, 3.0) + rng.unit_vector() * rng.range(0.0, 2.5);
            let ray = GpuRay { origin: origin.to_array(), tmin: 0.0, direction: (target - origin).to_array(), tmax: f32::INFINITY };
            for any_hit in [false, true] {
                let got = flat.trace(&ray, any_hit);
                let object = object_ray(&instance, &ray);
                let expected = own.trace(&tris, &object, any_hit);
                assert_eq!(
                    (got.t.to_bits(), got.prim, got.u.to_bits(), got.v.to_bits()),
                    (expected.t.to_bits(), expected.prim, expected.u.to_bits(), expected.v.to_bits()),
                    "{}: {ray:?}",
                    layout.name()
                );
                // A ray that misses the copy's world box visits the top level's node alone; an
                // any-hit query that hits the copy stops in it, before coming back.
                if got.nodes_visited > 1 {
                    let top = if any_hit && got.prim != PRIM_NONE { 1 } else { top_visits };
                    assert_eq!((got.nodes_visited, got.tris_tested), (expected.nodes_visited + top, expected.tris_tested), "{}: {ray:?}", layout.name());
                    walked += 1;
                }
            }
            // Rays for which the world direction would order some nodes' children the other way
            // (a node's near child or first slot is the one on the direction's side of its axis).
            let (world, object) = (Vec3::from(ray.direction), Vec3::from(object_ray(&instance, &ray).direction));
            reordered += usize::from((0..3).any(|a| (world[a] >= 0.0) != (object[a] >= 0.0)));
        }
        assert!(walked > 4000, "{}: {walked} walks compared", layout.name());
        assert!(reordered > 1000, "{reordered} rays with a direction component whose sign the copy's turn changes");
    }
}

/// Compact levels: each mesh's boxes are cells of a grid over its own root box in object space
/// (the instance carries it, and where its tree ends), the top level's of one over the
/// instances' world boxes (the push constants); the decoded boxes hold the true ones, so the
/// walk finds threaded levels' hits to the bit, in half the node bytes, visiting a few more
/// nodes at most.
#[test]
fn compact_levels_hit_what_threaded_levels_hit_on_a_grid_per_mesh() {
    let scene = turned_scene();
    let threaded = two_level_in(&scene, LayoutKind::Threaded);
    let compact = two_level_in(&scene, LayoutKind::Compact);
    assert_eq!(compact.node_count(), threaded.node_count());
    assert_eq!(compact.nodes.bytes().len() * 2, threaded.nodes.bytes().len());
    let push = compact.push();
    let world = scene.bounds();
    // The top level's grid spans the instances' boxes, in the world.
    for a in 0..3 {
        assert!(push.grid_origin[a] <= world.min[a] && push.grid_origin[a] + 65535.0 * push.grid_scale[a] >= world.max[a], "axis {a}");
    }
    let instances = compact.nodes.instances();
    for (i, (c, t)) in instances.iter().zip(threaded.nodes.instances()).enumerate() {
        assert_eq!((c.root, c.prim_base, c.shading_base, c.order_nodes), (t.root, t.prim_base, t.shading_base, 0));
        // A mesh's tree ends where the next begins (or the array does).
        let next = instances.iter().map(|j| j.root).filter(|&r| r > c.root).min().unwrap_or(compact.node_count() as u32);
        assert_eq!(c.node_end, next, "instance {i}");
        // Its grid is in object space: a unit mesh's, not the world's (copies are 5 apart).
        let size = Vec3::from(c.grid_scale) * 65535.0;
        assert!(size.max_element() <= 2.01 && size.min_element() >= 1.99 || c.prim_base < 2, "instance {i}: grid {size}");
    }
    let (mut nodes_threaded, mut nodes_compact, mut hits) = (0u64, 0u64, 0);
    for ray in rays(4000, 13, false) {
        for any_hit in [false, true] {
            let (a, b) = (threaded.trace(&ray, any_hit), compact.trace(&ray, any_hit));
            assert_eq!(a.prim == PRIM_NONE, b.prim == PRIM_NONE, "{ray:?}");
            if !any_hit {
                assert_eq!((a.t.to_bits(), a.prim, a.u.to_bits(), a.v.to_bits()), (b.t.to_bits(), b.prim, b.u.to_bits(), b.v.to_bits()), "{ray:?}");
                hits += usize::from(a.prim != PRIM_NONE);
                nodes_threaded += u64::from(a.nodes_visited);
                nodes_compact += u64::from(b.nodes_visited);
            }
        }
    }
    assert!(hits > 1000, "{hits} hits");
    assert!(
        nodes_compact >= nodes_threaded && nodes_compact as f64 <= 1.1 * nodes_threaded as f64,
        "compact {nodes_compact} nodes against threaded {nodes_threaded}"
    );
}

#[test]
fn turned_scaled_and_mirrored_copies_hit_as_the_expanded_scene() {
    let scene = turned_scene();
    let expanded = scene.expanded().unwrap();
    for layout in LAYOUTS {
        turned_copies_hit_as_expanded(&two_level_in(&scene, layout), &expanded);
    }
}

fn turned_copies_hit_as_expanded(flat: &vkrt::accel::FlatBvh, expanded: &Scene) {
    let (mut hits, mut same) = (0, 0);
    for ray in rays(6000, 2, false) {
        let expected = brute_force(&expanded.triangles, &ray);
        let got = flat.trace(&ray, false);
        // A ray through an edge may take either triangle's side after the transform's rounding;
        // it never misses where the expanded scene is hit.
        assert_eq!(got.prim == PRIM_NONE, expected.prim == PRIM_NONE, "{ray:?}: {got:?} against {expected:?}");
        if expected.prim == PRIM_NONE {
            continue;
        }
        hits += 1;
        // The ray's move into object space rounds its origin by an ulp or so of the scene's
        // size (40), not of t.
        assert!((got.t - expected.t).abs() <= 1e-5 * (expected.t + 40.0), "{ray:?}: t {} against {}", got.t, expected.t);
        if got.prim == expected.prim {
            same += 1;
            // Barycentrics of the placed triangle's own vertices: a mirror's swap is undone.
            assert!((got.u - expected.u).abs() < 1e-3 && (got.v - expected.v).abs() < 1e-3, "{ray:?}: {got:?} against {expected:?}");
        }
    }
    assert!(hits > 2000, "{hits} hits");
    assert!(same as f64 >= 0.999 * hits as f64, "{same} of {hits} on the same triangle");
    // Any-hit queries agree on whether anything is in the way.
    for ray in rays(2000, 3, false) {
        assert_eq!(flat.trace(&ray, true).prim == PRIM_NONE, brute_force(&expanded.triangles, &ray).prim == PRIM_NONE, "{ray:?}");
    }
}

#[test]
fn the_gpu_walk_matches_its_cpu_twin_bit_for_bit() {
    let ctx = common::gpu_context();
    for (name, scene, grid) in [("translated", translated_scene(), true), ("turned", turned_scene(), false)] {
        for layout in LAYOUTS {
            let flat = two_level_in(&scene, layout);
            let gpu = GpuBvh::upload(&ctx, &flat).unwrap();
            assert_eq!((gpu.instance_count as usize, gpu.layout), (flat.nodes.instances().len(), layout));
            let rays = rays(4096, 4, grid);
            for any_hit in [false, true] {
                let hits = trace_rays(&ctx, &gpu, &rays, any_hit).unwrap();
                for (ray, got) in rays.iter().zip(&hits) {
                    let expected: GpuHit = flat.trace(ray, any_hit);
                    assert_eq!(*got, expected, "{name}, {}, any_hit {any_hit}: {ray:?}", layout.name());
                }
            }
        }
    }
    common::assert_no_validation_messages(&ctx);
}

/// A lab YAML scene: a ground `Model` and a cube and a sphere placed by `Instances` (turned,
/// scaled, one mirrored).
fn write_yaml_scene(dir: &std::path::Path) -> std::path::PathBuf {
    let obj = |mesh: &common::closed_meshes::IndexedMesh| {
        let mut s = String::new();
        for p in &mesh.positions {
            s += &format!("v {} {} {}\n", p.x, p.y, p.z);
        }
        for t in &mesh.triangles {
            s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        s
    };
    std::fs::write(dir.join("cube.obj"), obj(&subdivided_cube(3))).unwrap();
    std::fs::write(dir.join("ball.obj"), obj(&icosphere(2))).unwrap();
    std::fs::write(dir.join("ground.obj"), "v -20 -1 -20\nv 20 -1 -20\nv 20 -1 20\nv -20 -1 20\nf 1 3 2\nf 1 4 3\n").unwrap();
    let mut yaml = String::from("Materials:\n  - Name: m\nModels:\n  - Mesh: ground.obj\n    Material: m\nInstances:\n");
    for (mesh, x) in [("cube.obj", -6.0), ("ball.obj", 6.0)] {
        yaml += &format!("  - Mesh: {mesh}\n    Material: m\n    Transforms:\n");
        for k in 0..4 {
            let z = k as f32 * 4.0 - 6.0;
            yaml += &format!(
                "      - Translation: [{x}, 0, {z}]\n        Rotation: [0, {}, 10]\n        Scale: [{}, 1.5, 1]\n",
                30 * k,
                if k == 2 { -1.0 } else { 1.0 }
            );
        }
    }
    let path = dir.join("scene.yaml");
    std::fs::write(&path, yaml).unwrap();
    path
}

/// `vkrt trace` walks a scene's instances through the two-level BVH (wide levels by default,
/// any other layout when asked), and hits what the expanded scene's walk hits; `vkrt bvh` adds
/// a row for each two-level layout asked for.
#[test]
fn trace_and_bvh_commands_take_instanced_scenes() {
    use vkrt::bvh::BuilderKind;
    use vkrt::cli::trace::run;
    use vkrt::output::npy::{read_hits, write_rays};
    let dir = common::scratch_dir("instancing-commands");
    let scene_path = write_yaml_scene(&dir);
    let scene = vkrt::scene::load_scene(&scene_path).unwrap();
    assert_eq!(scene.instances.len(), 2, "the loader records both Instances entries");
    let rays = vkrt::query::rays::incoherent(&scene, 3000, 9);
    let rays_path = dir.join("rays.npy");
    write_rays(&rays_path, &rays).unwrap();
    let trace = |layout: Option<vkrt::accel::LayoutKind>, out: &str| {
        let output = dir.join(out);
        let report = run(&common::trace_args(&scene_path, &rays_path, &output, layout)).unwrap();
        (report, read_hits(&output).unwrap())
    };
    let (two, two_hits) = trace(None, "two-level.npy");
    // The expanded scene's one-level tree, walked on the CPU.
    let expanded = scene.expanded().unwrap();
    let one_level = vkrt::prepare::build_bvh(&expanded, &PrepareOptions::default()).unwrap().0;
    let one_hits: Vec<GpuHit> = rays.iter().map(|r| one_level.trace(r, false)).collect();
    assert_eq!(two.hits as usize, one_hits.iter().filter(|h| h.prim != PRIM_NONE).count());
    assert!(two.hits > 1000, "{two:?}");
    let same = two_hits.iter().zip(&one_hits).filter(|(a, b)| a.prim == b.prim).count();
    assert!(same as f64 >= 0.999 * rays.len() as f64, "{same} of {} on the same triangle", rays.len());
    // Same counters as the CPU twin of the wide two-level walk, so it was that walk.
    let flat = two_level_in(&scene, LayoutKind::Wide);
    let nodes: u64 = rays.iter().map(|r| u64::from(flat.trace(r, false).nodes_visited)).sum();
    assert_eq!(two.nodes_visited, nodes);
    // Another layout when asked: multi-order levels, the same hits.
    let (multi, multi_hits) = trace(Some(LayoutKind::MultiOrder), "multi-order.npy");
    let flat = two_level_in(&scene, LayoutKind::MultiOrder);
    let multi_nodes: u64 = rays.iter().map(|r| u64::from(flat.trace(r, false).nodes_visited)).sum();
    assert_eq!((multi.hits, multi.nodes_visited), (two.hits, multi_nodes));
    assert!(multi_hits.iter().zip(&two_hits).all(|(a, b)| a.t.to_bits() == b.t.to_bits()));

    let args = vkrt::cli::bvh::BvhArgs {
        scenes: vec![scene_path.clone()],
        format: vkrt::cli::bvh::Format::Table,
        width: 24,
        height: 24,
        repeat: 1,
        heatmap: None,
        heatmap_builder: BuilderKind::Sah,
        heatmap_layout: vkrt::accel::LayoutKind::Threaded,
        builders: vec![BuilderKind::Sah],
        layouts: vec![LayoutKind::Threaded, LayoutKind::MultiOrder, LayoutKind::ParentLink, LayoutKind::Wide],
        device: vkrt::cli::DeviceArgs { device: None },
    };
    let ctx = common::gpu_context();
    let rows = vkrt::cli::bvh::scene_rows(&ctx, &scene_path, &scene, &args).unwrap();
    let names = ["threaded", "multi-order", "parent-link", "wide", "two-level-threaded", "two-level-multi-order", "two-level-parent-link", "two-level-wide"];
    assert_eq!(rows.iter().map(|r| r.layout_name()).collect::<Vec<_>>(), names);
    for (two, one) in [(4, 0), (5, 1), (6, 2), (7, 3)] {
        let counts = rows[two].two_level.unwrap();
        assert_eq!((counts.instances, counts.meshes), (9, 3), "eight copies and the ground; two meshes and the ground");
        assert_eq!(counts.bottom_triangles, 108 + 320 + 2);
        assert!(rows[two].bytes < rows[one].bytes, "{} bytes against {}", rows[two].bytes, rows[one].bytes);
    }
    let table = vkrt::cli::bvh::format_rows(&rows, vkrt::cli::bvh::Format::Table, "dev");
    assert!(table.contains("two-level-threaded: 9 instances of 3 meshes; top level 17 nodes"), "{table}");
    assert!(table.contains("two-level-multi-order: 9 instances of 3 meshes; top level 102 nodes"), "{table}");
    // Parent-link levels: the same tree, sibling pairs and one filler node.
    assert!(table.contains("two-level-parent-link: 9 instances of 3 meshes; top level 18 nodes"), "{table}");
}

/// Whitted and path renders of a scene with instances: through the two-level BVH (the
/// prepared scene's default for it), and of its expanded copies (the same scene with its
/// instance groups forgotten, walked as one tree).
fn renders(scene: &Scene) -> [(vkrt::integrator::Image, vkrt::integrator::Image); 2] {
    let ctx = common::gpu_context();
    let expanded = scene.expanded().unwrap().into_owned();
    let settings = vkrt::integrator::RenderSettings { width: 64, height: 48, spp: 1, ..Default::default() };
    let path = common::path_settings(64, 48, 16);
    let mut out = Vec::new();
    for s in [scene, &expanded] {
        let gpu = common::upload(&ctx, s);
        assert_eq!(gpu.bvh.instances.is_some(), !s.instances.is_empty());
        let whitted = vkrt::integrator::whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap().0;
        let path = common::render_path_on(&ctx, &gpu, &path).image();
        out.push((whitted, path));
    }
    common::assert_no_validation_messages(&ctx);
    let expanded = out.pop().unwrap();
    let two_level = out.pop().unwrap();
    [(two_level.0, expanded.0), (two_level.1, expanded.1)]
}

/// A point light above the scene, a camera looking down on it.
fn lit(mut scene: Scene) -> Scene {
    scene.materials.push(vkrt::scene::Material::default());
    scene.lights.push(vkrt::scene::Light::Point { position: Vec3::new(4.0, 12.0, 6.0), intensity: Vec3::splat(150.0) });
    scene.camera = vkrt::scene::Camera { eye: Vec3::new(0.0, 14.0, 22.0), target: Vec3::ZERO, ..scene.camera };
    scene
}

/// Under whole-number moves the camera rays (from the camera's whole-number eye) hit the same
/// triangles at the same t, and shading sees the same world triangle: the Whitted image has
/// the expanded scene's bytes. A path's later rays start at surface points, whose move into
/// object space rounds, so a few of its pixels part.
#[test]
fn exact_translations_render_the_expanded_scene_s_bytes() {
    let [(w2, w1), (p2, p1)] = renders(&lit(translated_scene()));
    assert!(w1.pixels.iter().any(|p| p[0] > 0.0), "the Whitted image is black");
    assert!(w2.pixels == w1.pixels, "Whitted: the images differ");
    let same = p2.pixels.iter().zip(&p1.pixels).filter(|(a, b)| a == b).count();
    assert!(same as f64 >= 0.95 * p1.pixels.len() as f64, "path: {same} of {} pixels the same", p1.pixels.len());
}

/// The device holds one copy of each mesh's shading data, not one per copy.
#[test]
fn shading_data_is_per_mesh() {
    let scene = lit(turned_scene());
    let prepared = vkrt::prepare::PreparedScene::new(&scene, &PrepareOptions::default()).unwrap();
    let per_mesh: usize = scene.instances.iter().map(|g| g.mesh.len()).sum::<usize>() + 2;
    assert_eq!(prepared.buffers.shading.len(), per_mesh);
    assert!(per_mesh as u64 * 10 < scene.placed_triangles(), "{per_mesh} entries for {} triangles", scene.placed_triangles());
}

#[test]
fn turned_copies_render_the_expanded_scene_to_rounding() {
    let [(w2, w1), (p2, p1)] = renders(&lit(turned_scene()));
    for (name, a, b) in [("Whitted", &w2, &w1), ("path", &p2, &p1)] {
        let sum = |img: &vkrt::integrator::Image| img.pixels.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>();
        let (sa, sb) = (sum(a), sum(b));
        assert!(sb > 0.0 && (sa - sb).abs() <= 0.01 * sb, "{name}: {sa} against {sb}");
        // Paths part only where rounding sends a ray another way: most pixels are the same.
        let close = a.pixels.iter().zip(&b.pixels).filter(|(x, y)| (0..3).all(|k| (x[k] - y[k]).abs() <= 1e-3 * (1.0 + y[k].abs()))).count();
        assert!(close as f64 >= 0.9 * a.pixels.len() as f64, "{name}: {close} of {} pixels alike", a.pixels.len());
    }
}

/// Mirrors and caustic casters among the copies are found in the world, as in the expanded
/// scene: instanced flat mirrors (two copies, one turned) and glossy balls.
#[test]
fn instanced_mirrors_and_casters_are_found_as_in_the_expanded_scene() {
    let mut scene = lit(scene_with(&[]));
    let mirror = vkrt::scene::Material { name: "mirror".into(), diffuse: Vec3::ZERO, specular: Vec3::ONE, illum: 3, ..Default::default() };
    let glossy = vkrt::scene::Material {
        name: "glossy".into(),
        diffuse: Vec3::splat(0.1),
        specular: Vec3::splat(0.9),
        shininess: 1000.0,
        illum: 2,
        ..Default::default()
    };
    scene.materials.extend([mirror, glossy]);
    let quad = |m: u32| {
        let p = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(-1.0, 1.0, 0.0)];
        vec![Triangle { p: [p[0], p[1], p[2]], n: None, uv: None, material: m }, Triangle { p: [p[0], p[2], p[3]], n: None, uv: None, material: m }]
    };
    add_group(
        &mut scene,
        &quad(1),
        vec![translation(0.0, 1.0, -8.0), Placement::from_trs(Vec3::new(-8.0, 1.0, 0.0), Vec3::new(0.0, 90.0, 0.0), Vec3::ONE).unwrap()],
    );
    let ball = icosphere(3).to_triangles(1.0, Vec3::ZERO, 2);
    add_group(&mut scene, &ball, vec![translation(3.0, 0.0, 0.0), translation(-3.0, 0.0, 3.0)]);
    assert_eq!(scene.instances.len(), 2);
    let expanded = scene.expanded().unwrap().into_owned();
    let ctx = common::gpu_context();
    let (two, one) = (common::upload(&ctx, &scene), common::upload(&ctx, &expanded));
    assert!(two.bvh.instances.is_some() && one.bvh.instances.is_none());
    assert_eq!((two.mirror_plane_count, two.caster_count), (one.mirror_plane_count, one.caster_count));
    assert_eq!((two.mirror_plane_count, two.caster_count), (2, 2), "two mirror planes, two balls");
    let settings = common::path_settings(48, 36, 64);
    let (a, b) = (common::render_path_on(&ctx, &two, &settings).image(), common::render_path_on(&ctx, &one, &settings).image());
    let sum = |img: &vkrt::integrator::Image| img.pixels.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>();
    assert!((sum(&a) - sum(&b)).abs() <= 0.02 * sum(&b), "{} against {}", sum(&a), sum(&b));
}

/// The mirror and caster searches see copies placed in the world only while they could use
/// them: a glossy statue too rough to cast is never placed, and copies past what a search
/// takes (over 2048 mirror triangles, over 8 caster pieces) are not placed, the outcome being
/// the expanded scene's (no mirrors, no casters), so the host's memory does not grow with the
/// copies.
#[test]
fn copies_are_placed_for_the_mirror_and_caster_searches_only_while_they_can_be_used() {
    use vkrt::prepare::PreparedScene;
    let material = |name: &str, specular: f32, shininess: f32, illum: u32| vkrt::scene::Material {
        name: name.into(),
        diffuse: Vec3::splat(0.2),
        specular: Vec3::splat(specular),
        shininess,
        illum,
        ..Default::default()
    };
    let ball = |m: u32| icosphere(1).to_triangles(0.4, Vec3::ZERO, m);
    let grid = |n: usize, y: f32| (0..n).map(|k| translation((k % 40) as f32 * 2.0 - 40.0, y, (k / 40) as f32 * 2.0 - 40.0)).collect::<Vec<_>>();
    // 1000 statues; `mirrors` copies of a flat two-triangle mirror (each in its own plane);
    // `balls` copies of a sharp glossy ball.
    let scene_of = |mirrors: usize, balls: usize| {
        let mut scene = lit(scene_with(&[]));
        // The Happy Buddha's MTL: Ks 0.35, Ns 32, too rough and too dim to cast.
        scene.materials.extend([material("statue", 0.35, 32.0, 2), material("mirror", 1.0, 0.0, 3), material("ball", 0.9, 1000.0, 2)]);
        add_group(&mut scene, &ball(1), grid(1000, 0.0));
        let p = [Vec3::new(-0.5, 0.0, -0.5), Vec3::new(0.5, 0.0, -0.5), Vec3::new(0.5, 0.0, 0.5), Vec3::new(-0.5, 0.0, 0.5)];
        let quad = [[p[0], p[2], p[1]], [p[0], p[3], p[2]]].map(|p| Triangle { p, n: None, uv: None, material: 2 });
        let tilted = |k: usize| Placement::from_trs(Vec3::new(0.0, 1.0 + k as f32 * 0.01, 0.0), Vec3::new(k as f32 * 0.1, 0.0, 0.0), Vec3::ONE).unwrap();
        add_group(&mut scene, &quad, (0..mirrors).map(tilted).collect());
        add_group(&mut scene, &ball(3), grid(balls, 3.0));
        scene
    };
    let placed = |scene: &Scene| PreparedScene::new(scene, &PrepareOptions::default()).unwrap().specular_triangles.len();
    assert_eq!(placed(&scene_of(0, 0)), 0, "the statues are placed");

    // Past what the searches take: 2200 mirror triangles in 1100 planes, 9 balls.
    let ctx = common::gpu_context();
    let scene = scene_of(1100, 9);
    assert_eq!(placed(&scene), 0);
    let expanded = scene.expanded().unwrap().into_owned();
    let (two, one) = (common::upload(&ctx, &scene), common::upload(&ctx, &expanded));
    assert_eq!((two.mirror_plane_count, two.caster_count), (0, 0));
    assert_eq!((one.mirror_plane_count, one.caster_count), (0, 0), "the expanded scene's searches find too many to use");

    // Within: 16 mirror triangles, 7 balls (a curved mirror's copies count as casters too).
    let scene = scene_of(8, 7);
    assert_eq!(placed(&scene), 8 * 2 + 7 * ball(3).len());
    let expanded = scene.expanded().unwrap().into_owned();
    let (two, one) = (common::upload(&ctx, &scene), common::upload(&ctx, &expanded));
    assert_eq!((two.mirror_plane_count, two.caster_count), (one.mirror_plane_count, one.caster_count));
    assert_eq!((two.mirror_plane_count, two.caster_count), (8, 7));
    common::assert_no_validation_messages(&ctx);
}

/// Renders through multi-order and parent-link levels see what threaded levels see: the same
/// closest hits (but for which of two triangles an edge goes to), so the same images but for
/// such pixels.
#[test]
fn every_two_level_layout_renders_the_threaded_levels_images() {
    let scene = lit(turned_scene());
    let ctx = common::gpu_context();
    let settings = vkrt::integrator::RenderSettings { width: 64, height: 48, spp: 1, ..Default::default() };
    let path = common::path_settings(64, 48, 16);
    let images: Vec<_> = LAYOUTS
        .iter()
        .map(|&layout| {
            let gpu = common::upload_with(&ctx, &scene, &PrepareOptions { layout, ..PrepareOptions::default() });
            assert_eq!((gpu.bvh.layout, gpu.bvh.instance_count), (layout, 37));
            let whitted = vkrt::integrator::whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap().0;
            (whitted, common::render_path_on(&ctx, &gpu, &path).image())
        })
        .collect();
    common::assert_no_validation_messages(&ctx);
    assert_eq!(LAYOUTS[0], LayoutKind::Threaded);
    for (layout, other) in LAYOUTS.iter().zip(&images).skip(1) {
        for (name, a, b) in [("Whitted", &images[0].0, &other.0), ("path", &images[0].1, &other.1)] {
            assert!(a.pixels.iter().any(|p| p[0] > 0.0), "{name}: black");
            let same = a.pixels.iter().zip(&b.pixels).filter(|(x, y)| x == y).count();
            assert!(same as f64 >= 0.98 * a.pixels.len() as f64, "{}, {name}: {same} of {} pixels the same", layout.name(), a.pixels.len());
        }
    }
}

/// Two cubes moved by whole numbers so that they share a face: rays from inside either, aimed
/// exactly at the seam's outer edges and corners (x = 1 on the boundary of the square |y|,
/// |z| <= 1), hit a face at or before the seam; none slips out between the copies. (Under exact
/// moves each copy's triangles are the expanded ones to the bit, so the watertight test's
/// guarantee carries over; turned copies meet only to rounding, as in every renderer's
/// instancing.)
#[test]
fn rays_at_the_seam_of_abutting_copies_never_slip_through() {
    let cube = subdivided_cube(2).to_triangles(1.0, Vec3::ZERO, 0);
    let mut scene = Scene::default();
    add_group(&mut scene, &cube, vec![translation(0.0, 0.0, 0.0), translation(2.0, 0.0, 0.0)]);
    for layout in LAYOUTS {
        let flat = two_level_in(&scene, layout);
        assert_eq!(flat.nodes.instances().len(), 2);
        seam_rays_stay_in(&flat);
    }
}

fn seam_rays_stay_in(flat: &vkrt::accel::FlatBvh) {
    let mut rng = Pcg32::new(11);
    for k in 0..4000 {
        let r = [-1.0f32, -0.5, 0.0, 0.5, 1.0][k % 5];
        let side = if k % 2 == 0 { -1.0 } else { 1.0 };
        let target = if (k / 2) % 2 == 0 { Vec3::new(1.0, side, r) } else { Vec3::new(1.0, r, side) };
        let origin = Vec3::new(rng.range(-0.9, 2.9), rng.range(-0.9, 0.9), rng.range(-0.9, 0.9));
        let ray = GpuRay { origin: origin.to_array(), tmin: 0.0, direction: (target - origin).to_array(), tmax: f32::INFINITY };
        let hit = flat.trace(&ray, false);
        assert_ne!(hit.prim, PRIM_NONE, "{ray:?} slipped out through the seam");
        assert!(hit.t <= 1.0 + 1e-5, "{ray:?} left the cubes: hit at t {}", hit.t);
    }
}

/// Normal-mapped, textured copies (turned, one mirrored) shade as the expanded copies do: the
/// tangents and texture coordinates of each mesh entry are turned out by the hit instance.
#[test]
fn normal_mapped_copies_shade_as_the_expanded_ones() {
    use vkrt::scene::{Material, Texture};
    let mut scene = lit(scene_with(&[]));
    let normal = Texture::from_rgba("normal", 2, 2, &[[230, 128, 180, 255], [128, 230, 180, 255], [30, 128, 180, 255], [128, 30, 180, 255]]).unwrap();
    let colour = Texture::from_rgba("colour", 2, 2, &[[250, 40, 40, 255], [40, 250, 40, 255], [40, 40, 250, 255], [250, 250, 40, 255]]).unwrap();
    scene.textures.extend([normal, colour]);
    scene.materials.push(Material { name: "mapped".into(), diffuse_texture: Some(1), normal_texture: Some(0), normal_scale: 1.0, ..Material::default() });
    let mut ball = icosphere(3).to_triangles(4.0, Vec3::ZERO, 1);
    for t in &mut ball {
        t.n = Some(t.p.map(|p| p.normalize()));
        t.uv = Some(t.p.map(|p| glam::Vec2::new(0.5 + p.x.atan2(p.z) / std::f32::consts::TAU, 0.5 + p.y / 8.0)));
    }
    let placements = vec![
        Placement::from_trs(Vec3::new(-5.0, 2.0, 4.0), Vec3::new(0.0, 40.0, 20.0), Vec3::ONE).unwrap(),
        Placement::from_trs(Vec3::new(5.0, 2.0, 4.0), Vec3::new(10.0, -30.0, 0.0), Vec3::new(-1.0, 1.2, 1.0)).unwrap(),
    ];
    add_group(&mut scene, &ball, placements);
    vkrt::scene::tangents::fill_missing_tangents(&mut scene);
    assert_eq!(scene.instances[0].tangents.len(), ball.len(), "the mesh's tangents, in object space");
    let [(w2, w1), (p2, p1)] = renders(&scene);
    for (name, a, b) in [("Whitted", &w2, &w1), ("path", &p2, &p1)] {
        let sum = |img: &vkrt::integrator::Image| img.pixels.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>();
        assert!(sum(b) > 0.0 && (sum(a) - sum(b)).abs() <= 0.01 * sum(b), "{name}: {} against {}", sum(a), sum(b));
        let close = a.pixels.iter().zip(&b.pixels).filter(|(x, y)| (0..3).all(|k| (x[k] - y[k]).abs() <= 0.02 * (0.05 + y[k].abs()))).count();
        assert!(close as f64 >= 0.95 * a.pixels.len() as f64, "{name}: {close} of {} pixels alike", a.pixels.len());
    }
}

/// More triangles than a one-level tree takes (2^28): 900 copies of a 327,680-triangle sphere,
/// 295 M triangles, held as one mesh. The scene loads and renders through the two-level BVH in
/// every layout; placing its copies for a one-level tree is refused with the count.
#[test]
fn copies_past_the_one_level_bound_render_through_the_two_level_bvh_only() {
    let ball = icosphere(7).to_triangles(1.0, Vec3::ZERO, 0);
    assert_eq!(ball.len(), 327_680);
    let placements = (0..900).map(|k| translation((k % 30) as f32 * 2.5 - 36.0, 0.0, (k / 30) as f32 * 2.5 - 36.0)).collect();
    let scene = lit(scene_with(&[(ball, placements)]));
    assert_eq!(scene.placed_triangles(), 2 + 900 * 327_680);
    assert!(scene.placed_triangles() > vkrt::scene::assemble::MAX_PLACED_TRIANGLES);
    let e = scene.expanded().unwrap_err();
    assert!(e.contains("294912002") && e.contains("268435456"), "{e}");
    let e = format!("{:#}", vkrt::prepare::build_bvh(&scene, &PrepareOptions::default()).unwrap_err());
    assert!(e.contains("placing the scene's copies for a one-level BVH in the threaded layout") && e.contains("294912002"), "{e}");

    let ctx = common::gpu_context();
    let gpu = common::upload(&ctx, &scene);
    assert_eq!(gpu.bvh.instances.as_ref().map(|_| ()), Some(()));
    let settings = vkrt::integrator::RenderSettings { width: 48, height: 32, spp: 1, ..Default::default() };
    let image = vkrt::integrator::whitted::render(&ctx, &gpu, &settings, &mut |_, _| {}).unwrap().0;
    // The balls and the ground under the point light: most pixels see something lit.
    let lit_pixels = image.pixels.iter().filter(|p| p[0] > 0.0).count();
    assert!(lit_pixels * 2 > image.pixels.len(), "{lit_pixels} of {} pixels lit", image.pixels.len());
    common::assert_no_validation_messages(&ctx);
}
