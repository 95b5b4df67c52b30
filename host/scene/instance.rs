//! Copies of a mesh placed by affine transforms ("instances"): the lab YAML's `Instances`
//! (scene/lab_yaml.rs). Each copy is expanded into the scene's triangles at load, as glTF's
//! node placements are, so the triangles a scene would hold are counted against
//! [`super::assemble::MAX_PLACED_TRIANGLES`] before anything is copied. [`place_copies`] also
//! records how the copies were made ([`InstanceGroup`]), so that the prepare stage can build a
//! two-level BVH over one copy of the mesh (`accel::two_level`); shading still reads the
//! expanded copies' normals, texture coordinates and materials.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::assemble::push_triangle;
use super::{Scene, Triangle};

/// Copies of one mesh as a loader expanded them into [`Scene::triangles`]: each copy's
/// triangles are contiguous from its first primitive id, in the mesh's order, each
/// [`Placement::place`]d. What a two-level BVH needs to keep one copy.
#[derive(Debug, Clone, PartialEq)]
pub struct InstanceGroup {
    /// The mesh's vertex positions in object space, in the copies' triangle order (a
    /// mirrored copy has its second and third vertices swapped, [`Placement::place`]).
    pub mesh: Vec<[Vec3; 3]>,
    /// Each copy: the primitive id of its first triangle, and its placement.
    pub copies: Vec<(u32, Placement)>,
}

impl InstanceGroup {
    /// Triangles the copies hold in the scene.
    pub fn placed_triangles(&self) -> usize {
        self.mesh.len() * self.copies.len()
    }
}

/// Which of a mesh's triangles each copy kept (a transform can make a triangle degenerate in
/// one copy and not in another), gathered copy by copy while a loader expands them: an
/// [`InstanceGroup`] where every copy kept the same ones, none otherwise (the copies are then
/// only expanded).
#[derive(Debug, Clone, Default)]
pub struct CopiesMade {
    mesh: Vec<[Vec3; 3]>,
    kept: Option<Vec<bool>>,
    copies: Vec<(u32, Placement)>,
    added: usize,
    alike: bool,
}

impl CopiesMade {
    /// `mesh`: the object-space positions of every triangle a copy is made of, in order.
    pub fn new(mesh: Vec<[Vec3; 3]>) -> Self {
        Self { mesh, kept: None, copies: Vec::new(), added: 0, alike: true }
    }

    /// A copy placed by `world` from primitive `first` on, with `kept` telling which of the
    /// mesh's triangles it kept. A transform that [`Placement`] refuses (singular) leaves the
    /// copies expanded.
    pub fn add(&mut self, first: usize, world: Mat4, kept: Vec<bool>) {
        self.added += 1;
        match (u32::try_from(first), Placement::new(world)) {
            (Ok(first), Ok(p)) => self.copies.push((first, p)),
            _ => self.alike = false,
        }
        match &self.kept {
            None => self.kept = Some(kept),
            Some(first_copy) => self.alike &= *first_copy == kept,
        }
    }

    /// Copies added so far.
    pub fn count(&self) -> usize {
        self.added
    }

    /// The group, if the copies are alike and keep a triangle.
    pub fn group(self) -> Option<InstanceGroup> {
        let kept = self.kept.filter(|_| self.alike)?;
        let mesh: Vec<[Vec3; 3]> = self.mesh.iter().zip(&kept).filter(|(_, &keep)| keep).map(|(t, _)| *t).collect();
        (!mesh.is_empty()).then_some(InstanceGroup { mesh, copies: self.copies })
    }
}

/// Adds one copy of `mesh` per placement to the scene's triangles and, where every copy kept
/// the same triangles, records them as an [`InstanceGroup`] ([`CopiesMade`]).
pub fn place_copies(scene: &mut Scene, mesh: &[Triangle], placements: Vec<Placement>) {
    let mut made = CopiesMade::new(mesh.iter().map(|t| t.p).collect());
    for p in &placements {
        let first = scene.triangles.len();
        let kept = mesh.iter().map(|t| push_triangle(scene, p.place(t))).collect();
        made.add(first, p.world, kept);
    }
    scene.instances.extend(made.group());
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
