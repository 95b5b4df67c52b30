//! Copies of a mesh placed by affine transforms ("instances"): the lab YAML's `Instances`
//! (scene/lab_yaml.rs) and glTF meshes that nodes place more than once. A loader keeps one
//! copy of the mesh, in object space, and the copies' placements ([`InstanceGroup`]): the
//! scene holds the mesh once however many copies there are, and the prepare stage builds a
//! two-level BVH over it (`accel::two_level`). What needs the copies in the world (another
//! layout's one-level tree, `Scene::expanded`) places them from the group.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::assemble::{kept, normalised_normals};
use super::{Scene, Triangle};
use crate::geom::Aabb;

/// Copies of one mesh. Copy `c`'s triangle `i` has primitive id `first + c * mesh.len() + i`:
/// groups number their copies after the scene's own triangles, in the order the loader made
/// the groups (`Scene::number_instances`).
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceGroup {
    /// The mesh's triangles in object space, with their shading normals, texture coordinates
    /// and materials (degenerate ones dropped, as every loader drops them).
    pub mesh: Vec<Triangle>,
    /// Tangents by mesh triangle, in object space (as `Scene::tangents`): empty unless some
    /// material has a normal map.
    pub tangents: Vec<[Vec4; 3]>,
    /// Each copy's object-to-world placement.
    pub placements: Vec<Placement>,
    /// The primitive id of the first copy's first triangle.
    pub first: u32,
}

impl InstanceGroup {
    /// A group of `mesh` (object space, triangles as a loader keeps them) placed by
    /// `placements`, numbered later.
    pub fn new(mesh: Vec<Triangle>, tangents: Vec<[Vec4; 3]>, placements: Vec<Placement>) -> Self {
        Self { mesh, tangents, placements, first: 0 }
    }

    /// Triangles the copies place in the scene.
    pub fn placed_triangles(&self) -> u64 {
        self.mesh.len() as u64 * self.placements.len() as u64
    }

    /// Each copy's first primitive id and placement.
    pub fn copies(&self) -> impl Iterator<Item = (u32, Placement)> + '_ {
        let n = self.mesh.len() as u32;
        self.placements.iter().enumerate().map(move |(c, &p)| (self.first + c as u32 * n, p))
    }

    /// Copy `copy`'s triangle `i` in the world, its shading normals normalised as a loader's.
    pub fn placed(&self, copy: usize, i: usize) -> Triangle {
        let mut t = self.placements[copy].place(&self.mesh[i]);
        t.n = t.n.and_then(normalised_normals);
        t
    }

    /// Copy `copy`'s tangents of triangle `i` in the world (zero where the group has none).
    pub fn placed_tangents(&self, copy: usize, i: usize) -> [Vec4; 3] {
        let t = self.tangents.get(i).copied().unwrap_or([Vec4::ZERO; 3]);
        self.placements[copy].place_tangents(t)
    }

    /// The mesh's object-space bounds.
    pub fn object_bounds(&self) -> Aabb {
        self.mesh.iter().fold(Aabb::EMPTY, |b, t| b.union(&t.bounds()))
    }
}

/// Adds `mesh` (object space) placed by each of `placements` to the scene as one
/// [`InstanceGroup`], its degenerate triangles dropped (and counted once per copy, as the
/// copies' would be), numbered after what the scene holds so far (`Scene::number_instances`
/// numbers them again once the scene is whole).
pub fn add_group(scene: &mut Scene, mesh: &[Triangle], placements: Vec<Placement>) {
    let kept: Vec<Triangle> = mesh.iter().filter_map(|&t| kept(t)).collect();
    scene.stats.dropped_degenerate += (mesh.len() - kept.len()) * placements.len();
    if !kept.is_empty() && !placements.is_empty() {
        let first = u32::try_from(scene.placed_triangles()).unwrap_or(u32::MAX);
        scene.instances.push(InstanceGroup { first, ..InstanceGroup::new(kept, Vec::new(), placements) });
    }
}

/// The world box of an object box placed by `world`: its eight corners transformed (exact for
/// translations and scales, a little loose around a turned mesh).
pub fn placed_box(world: &Mat4, b: &Aabb) -> Aabb {
    if b.is_empty() {
        return *b;
    }
    let corners: [Vec3; 8] = std::array::from_fn(|k| {
        let pick = |bit: usize, lo: f32, hi: f32| if k & bit == 0 { lo } else { hi };
        world.transform_point3(Vec3::new(pick(1, b.min.x, b.max.x), pick(2, b.min.y, b.max.y), pick(4, b.min.z, b.max.z)))
    });
    Aabb::from_points(&corners)
}

/// An object-to-world transform and what placing a triangle by it needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    world: Mat4,
    /// Inverse transpose of the linear part: normals stay perpendicular to the surface under
    /// non-uniform scale.
    normal_matrix: Mat3,
    /// A negative determinant mirrors the mesh, which would turn its triangles inside out; the
    /// winding is flipped back, as glTF 2.0 section 3.7.4 asks of mirroring nodes.
    mirrored: bool,
}

impl Placement {
    /// glTF's order: scale, then rotate, then translate (p' = T R S p). `rotation_deg` turns
    /// about the fixed x axis, then y, then z (R = Rz Ry Rx), in degrees.
    pub fn from_trs(translation: Vec3, rotation_deg: Vec3, scale: Vec3) -> Result<Self, String> {
        let r = rotation_deg * (std::f32::consts::PI / 180.0);
        let rotation = Mat3::from_rotation_z(r.z) * Mat3::from_rotation_y(r.y) * Mat3::from_rotation_x(r.x);
        let linear = rotation * Mat3::from_diagonal(scale);
        Self::new(Mat4::from_cols(linear.x_axis.extend(0.0), linear.y_axis.extend(0.0), linear.z_axis.extend(0.0), translation.extend(1.0)))
    }

    /// A matrix given by rows: 12 numbers (3x4) or 16 (4x4, whose last row must be 0 0 0 1:
    /// vkrt places meshes by affine transforms only).
    pub fn from_rows(rows: &[f32]) -> Result<Self, String> {
        if rows.len() == 16 && rows[12..] != [0.0, 0.0, 0.0, 1.0] {
            return Err(format!("the last row is {:?}, not [0, 0, 0, 1]: a projective matrix cannot place a mesh", &rows[12..]));
        }
        if rows.len() != 12 && rows.len() != 16 {
            return Err(format!("{} numbers; a matrix is 12 (3x4, by rows) or 16 (4x4)", rows.len()));
        }
        let row = |i: usize| Vec4::new(rows[4 * i], rows[4 * i + 1], rows[4 * i + 2], rows[4 * i + 3]);
        Self::new(Mat4::from_cols_array_2d(&[row(0).into(), row(1).into(), row(2).into(), [0.0, 0.0, 0.0, 1.0]]).transpose())
    }

    /// Fails on a transform that is not finite or that flattens the mesh (determinant 0, or so
    /// small that the normals' inverse overflows).
    pub fn new(world: Mat4) -> Result<Self, String> {
        if !world.is_finite() {
            return Err("the transform is not finite".into());
        }
        let linear = Mat3::from_mat4(world);
        let det = linear.determinant();
        let normal_matrix = linear.inverse().transpose();
        if det == 0.0 || !normal_matrix.is_finite() {
            return Err(format!("the transform is singular (determinant {det}): it would flatten the mesh"));
        }
        Ok(Self { world, normal_matrix, mirrored: det < 0.0 })
    }

    /// The object-to-world transform (affine: its last row is 0 0 0 1).
    pub fn world(&self) -> Mat4 {
        self.world
    }

    /// Whether the transform mirrors (negative determinant): the placed triangles' second and
    /// third vertices are swapped.
    pub fn mirrored(&self) -> bool {
        self.mirrored
    }

    /// `t` in the world: positions by the transform, shading normals by its inverse transpose
    /// (normalised when the triangle joins the scene, `assemble::push_triangle`, as every
    /// loader's), the winding flipped back under a mirror.
    pub fn place(&self, t: &Triangle) -> Triangle {
        let mut placed =
            Triangle { p: t.p.map(|p| self.world.transform_point3(p)), n: t.n.map(|n| n.map(|v| self.normal_matrix * v)), uv: t.uv, material: t.material };
        if self.mirrored {
            placed.p.swap(1, 2);
            if let Some(n) = placed.n.as_mut() {
                n.swap(1, 2);
            }
            if let Some(uv) = placed.uv.as_mut() {
                uv.swap(1, 2);
            }
        }
        placed
    }

    /// A triangle's tangents (xyz along increasing u, w the bitangent's handedness) placed as
    /// [`Placement::place`] places its vertices: xyz by the linear part, and under a mirror the
    /// second and third swapped and the handedness flipped (the placed frame's bitangent
    /// w * cross(n, t) must still point along increasing v).
    pub fn place_tangents(&self, t: [Vec4; 3]) -> [Vec4; 3] {
        let sign = if self.mirrored { -1.0 } else { 1.0 };
        let mut placed =
            t.map(|t| if t.truncate() == Vec3::ZERO { t } else { self.world.transform_vector3(t.truncate()).normalize_or_zero().extend(t.w * sign) });
        if self.mirrored {
            placed.swap(1, 2);
        }
        placed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triangle() -> Triangle {
        Triangle { p: [Vec3::ZERO, Vec3::X, Vec3::Y], n: Some([Vec3::Z; 3]), uv: None, material: 3 }
    }

    #[test]
    fn scale_then_rotate_then_translate() {
        let p = Placement::from_trs(Vec3::new(10.0, 0.0, 0.0), Vec3::new(0.0, 90.0, 0.0), Vec3::splat(2.0)).unwrap();
        let t = p.place(&triangle());
        // x scaled to 2, turned 90 degrees about y (x -> -z), then moved by 10 along x.
        assert!((t.p[1] - Vec3::new(10.0, 0.0, -2.0)).length() < 1e-5, "{:?}", t.p);
        assert!((t.n.unwrap()[0].normalize() - Vec3::X).length() < 1e-6, "{:?}", t.n);
        assert_eq!(t.material, 3);
        // The same transform by rows.
        let m = Placement::from_rows(&[0.0, 0.0, 2.0, 10.0, 0.0, 2.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0]).unwrap();
        let u = m.place(&triangle());
        for k in 0..3 {
            assert!((u.p[k] - t.p[k]).length() < 1e-5);
        }
    }

    #[test]
    fn a_scale_and_shift_place_exactly_as_models_do() {
        // `Models`' Scale and Translation compute p * scale + shift; a diagonal transform gives
        // the same floats (its zero products add exactly).
        let (scale, shift) = (Vec3::new(1.5, 3.0, 0.25), Vec3::new(-7.0, 0.1, 12.5));
        let p = Placement::from_trs(shift, Vec3::ZERO, scale).unwrap();
        let t = Triangle { p: [Vec3::new(0.3, -1.7, 2.9), Vec3::new(5.1, 0.2, -3.3), Vec3::new(-0.6, 4.4, 0.7)], n: None, uv: None, material: 0 };
        assert_eq!(p.place(&t).p, t.p.map(|v| v * scale + shift));
    }

    #[test]
    fn a_mirror_keeps_the_front_face_outward() {
        let t = triangle();
        let mirrored = Placement::from_trs(Vec3::ZERO, Vec3::ZERO, Vec3::new(-1.0, 1.0, 1.0)).unwrap().place(&t);
        // The geometric normal (winding) and the shading normal still agree after the flip.
        assert!(mirrored.cross().dot(mirrored.n.unwrap()[0]) > 0.0, "{:?}", mirrored);
        assert_eq!(mirrored.p, [Vec3::ZERO, Vec3::Y, -Vec3::X]);
    }

    #[test]
    fn flattening_and_projective_transforms_are_refused() {
        let e = Placement::from_trs(Vec3::ZERO, Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0)).unwrap_err();
        assert!(e.contains("singular"), "{e}");
        let e = Placement::from_rows(&[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0]).unwrap_err();
        assert!(e.contains("projective"), "{e}");
        assert!(Placement::from_rows(&[1.0; 9]).unwrap_err().contains("12"));
        assert!(Placement::from_trs(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ZERO, Vec3::ONE).unwrap_err().contains("finite"));
    }
}
