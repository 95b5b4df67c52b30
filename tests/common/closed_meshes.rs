//! Closed, watertight triangle meshes with shared vertices, for leak and self-intersection
//! tests: every edge is shared by exactly two triangles, and faces wind counter-clockwise seen
//! from outside. Each is centred on the origin with a size of about 2 (radius 1). Test support,
//! not part of the library: the tests include it as `common::closed_meshes`, the benchmark
//! tools by path.
#![allow(dead_code)]

use glam::Vec3;
use std::collections::HashMap;
use vkrt::scene::Triangle;

/// An indexed mesh: positions and counter-clockwise index triples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IndexedMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl IndexedMesh {
    /// The mesh scaled by `scale` and then moved by `offset`, as triangles of `material`.
    /// Shared vertices stay bit-identical between the triangles that share them.
    pub fn to_triangles(&self, scale: f32, offset: Vec3, material: u32) -> Vec<Triangle> {
        let p: Vec<Vec3> = self.positions.iter().map(|&v| v * scale + offset).collect();
        self.triangles.iter().map(|t| Triangle { p: t.map(|i| p[i as usize]), n: None, uv: None, material }).collect()
    }

    /// Midpoints of every edge, each once (for rays aimed exactly through edges).
    pub fn edges(&self) -> Vec<(u32, u32)> {
        let mut seen = std::collections::HashSet::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                seen.insert((a.min(b), a.max(b)));
            }
        }
        let mut edges: Vec<_> = seen.into_iter().collect();
        edges.sort_unstable();
        edges
    }
}

/// An icosahedron subdivided `levels` times, vertices pushed onto the unit sphere
/// (20 * 4^levels triangles).
pub fn icosphere(levels: u32) -> IndexedMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .iter()
    .map(|&p| Vec3::from(p).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push(((positions[a as usize] + positions[b as usize]) * 0.5).normalize());
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = mid(a, b, &mut positions);
            let bc = mid(b, c, &mut positions);
            let ca = mid(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    IndexedMesh { positions, triangles }
}

/// The cube [-1, 1]^3 with each face split into n x n quads (12 n^2 triangles), vertices shared
/// along face boundaries.
pub fn subdivided_cube(n: u32) -> IndexedMesh {
    let n = n.max(1);
    let mut index: HashMap<[i64; 3], u32> = HashMap::new();
    let mut mesh = IndexedMesh::default();
    // Grid coordinates in integer units of 2/n, so shared vertices are found exactly.
    let mut vertex = |g: [i64; 3], mesh: &mut IndexedMesh| -> u32 {
        *index.entry(g).or_insert_with(|| {
            mesh.positions.push(Vec3::new(g[0] as f32, g[1] as f32, g[2] as f32) * (2.0 / n as f32) - Vec3::ONE);
            mesh.positions.len() as u32 - 1
        })
    };
    let n = n as i64;
    for axis in 0..3usize {
        for side in [0i64, n] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: i64, dj: i64| {
                        let mut g = [0i64; 3];
                        g[axis] = side;
                        g[u] = i + di;
                        g[v] = j + dj;
                        g
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)].map(|g| vertex(g, &mut mesh));
                    // u x v points along +axis: keep that order on the far side, flip it on the near one.
                    if side == n {
                        mesh.triangles.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
                    } else {
                        mesh.triangles.extend([[q[0], q[2], q[1]], [q[0], q[3], q[2]]]);
                    }
                }
            }
        }
    }
    mesh
}

/// A torus around the y axis with major radius `major` and minor radius `minor`, `nu` segments
/// around the axis and `nv` around the tube (2 nu nv triangles).
pub fn torus(major: f32, minor: f32, nu: u32, nv: u32) -> IndexedMesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let mut mesh = IndexedMesh::default();
    for i in 0..nu {
        let a = i as f32 / nu as f32 * std::f32::consts::TAU;
        for j in 0..nv {
            let b = j as f32 / nv as f32 * std::f32::consts::TAU;
            let r = major + minor * b.cos();
            mesh.positions.push(Vec3::new(r * a.cos(), minor * b.sin(), r * a.sin()));
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            mesh.triangles.extend([[a, c, b], [a, d, c]]);
        }
    }
    mesh
}
