//! The node hierarchy of a scene ([`Rig`]): nodes with rest transforms,
//! the channels animating them, mesh instances and the camera node, posed
//! at any time.

use super::channel::{Channel, Property};
use crate::scene::Camera;
use glam::{Mat3, Mat4, Quat, Vec3};

/// A node's local transform: scale, then rotation, then translation
/// (glTF's TRS order). [`Trs::default`] is the identity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation in world units (of the parent's space).
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Scale factors along the local axes (negative values mirror).
    pub scale: Vec3,
}

impl Default for Trs {
    fn default() -> Self {
        Trs {
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
        }
    }
}

impl Trs {
    /// The matrix `T * R * S` taking local coordinates to the parent's.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A node of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Name for messages (the glTF node name, or `node <index>`).
    pub name: String,
    /// Index of the parent in [`Rig::nodes`], `None` for a root. An index
    /// out of range or a parent cycle is treated as a root by
    /// [`Rig::world_transforms`].
    pub parent: Option<usize>,
    /// The transform without animation (the file's node transform).
    pub rest: Trs,
}

/// The triangles of one mesh placed by one node: a contiguous run of
/// [`crate::scene::Scene::triangles`] (and of [`Rig::local`]) sharing one
/// object id.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshInstance {
    /// Index into [`Rig::nodes`] of the node placing the mesh.
    pub node: usize,
    /// Index of the instance's first triangle.
    pub first_triangle: usize,
    /// Number of triangles of the instance.
    pub triangle_count: usize,
}

/// The camera node: the camera looks along the node's local `-Z` with `+Y`
/// up (the glTF convention).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigCamera {
    /// Index into [`Rig::nodes`].
    pub node: usize,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

/// A scene's hierarchy and animation: everything needed to pose its
/// triangles and camera at any time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rig {
    /// The nodes, in any order (parents need not come first).
    pub nodes: Vec<Node>,
    /// Animation channels; a channel failing [`Channel::problem`] or naming
    /// a node out of range is ignored. When several channels animate the
    /// same property of the same node, the last one wins.
    pub channels: Vec<Channel>,
    /// Mesh instances, in the order of their triangles.
    pub instances: Vec<MeshInstance>,
    /// `local[i]` = the vertices of triangle `i` of
    /// [`crate::scene::Scene::triangles`] in the local space of its
    /// instance's node, in the same vertex order (so the rest pose maps them
    /// exactly onto the scene's triangles).
    pub local: Vec<[Vec3; 3]>,
    /// `local_normals[i]` = the vertex normals of triangle `i` in the same
    /// local space and vertex order as [`Rig::local`] (unit), or three
    /// zeros for a flat triangle; a missing entry (a shorter list) is flat
    /// too.
    pub local_normals: Vec<[Vec3; 3]>,
    /// The camera node, `None` when the scene frames itself automatically.
    pub camera: Option<RigCamera>,
}

/// A [`Rig`] evaluated at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct RigPose {
    /// World-space vertices, parallel to [`Rig::local`] (so to
    /// [`crate::scene::Scene::triangles`]).
    pub triangles: Vec<[Vec3; 3]>,
    /// World-space vertex normals, parallel to `triangles`: each
    /// [`Rig::local_normals`] entry through its node's [`normal_matrix`]
    /// (not normalised), swapped with the vertices; zeros for flat
    /// triangles (what `SceneGpu::set_normals` takes).
    pub normals: Vec<[Vec3; 3]>,
    /// The camera, `None` without a camera node.
    pub camera: Option<Camera>,
}

impl Rig {
    /// The channels that can be applied.
    fn valid_channels(&self) -> impl Iterator<Item = &Channel> {
        self.channels
            .iter()
            .filter(|c| c.node < self.nodes.len() && c.problem().is_none())
    }

    /// Length of the animation in seconds: the last key time over all
    /// channels (clamped to `>= 0`), 0 without channels.
    pub fn duration(&self) -> f32 {
        self.valid_channels()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0, f32::max)
    }

    /// `animated[node]`: a valid channel targets the node.
    fn animated_nodes(&self) -> Vec<bool> {
        let mut animated = vec![false; self.nodes.len()];
        for c in self.valid_channels() {
            animated[c.node] = true;
        }
        animated
    }

    /// Whether `node` or one of its ancestors is animated.
    fn animated_from_above(&self, animated: &[bool], node: usize) -> bool {
        let mut current = Some(node);
        // At most `nodes.len()` steps: a parent cycle ends the walk.
        for _ in 0..=self.nodes.len() {
            match current {
                Some(n) if n < self.nodes.len() => {
                    if animated[n] {
                        return true;
                    }
                    current = self.nodes[n].parent;
                }
                _ => return false,
            }
        }
        false
    }

    /// Whether a channel moves some triangle: it targets the node of a mesh
    /// instance or one of its ancestors.
    pub fn animates_geometry(&self) -> bool {
        let animated = self.animated_nodes();
        self.instances
            .iter()
            .any(|i| self.animated_from_above(&animated, i.node))
    }

    /// Whether a channel moves the camera: it targets the camera node or
    /// one of its ancestors.
    pub fn animates_camera(&self) -> bool {
        let animated = self.animated_nodes();
        self.camera
            .is_some_and(|c| self.animated_from_above(&animated, c.node))
    }

    /// Local transforms at `time` seconds: rest transforms with the
    /// channels applied.
    fn locals_at(&self, time: f32) -> Vec<Trs> {
        let mut locals: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        for c in self.valid_channels() {
            let v = c.sample(time);
            let trs = &mut locals[c.node];
            match c.property {
                Property::Translation => trs.translation = v.truncate(),
                Property::Rotation => trs.rotation = Quat::from_vec4(v),
                Property::Scale => trs.scale = v.truncate(),
            }
        }
        locals
    }

    /// World matrices from local transforms, parents first, iteratively.
    fn world_from_locals(&self, locals: &[Trs]) -> Vec<Mat4> {
        let n = self.nodes.len();
        let mut world: Vec<Option<Mat4>> = vec![None; n];
        let mut chain = Vec::new();
        for start in 0..n {
            if world[start].is_some() {
                continue;
            }
            // Walk up to a computed ancestor, a root, or a cycle.
            chain.clear();
            let mut current = start;
            let base = loop {
                chain.push(current);
                match self.nodes[current].parent {
                    Some(p) if p < n && chain.len() <= n => {
                        if let Some(m) = world[p] {
                            break m;
                        }
                        if chain.contains(&p) {
                            break Mat4::IDENTITY; // cycle: `current` acts as a root
                        }
                        current = p;
                    }
                    _ => break Mat4::IDENTITY,
                }
            };
            let mut m = base;
            for &node in chain.iter().rev() {
                m *= locals[node].matrix();
                world[node] = Some(m);
            }
        }
        world.into_iter().map(|m| m.unwrap_or(Mat4::IDENTITY)).collect()
    }

    /// World matrix of every node at `time` seconds (parallel to
    /// [`Rig::nodes`]): `world(parent) * local`, where `local` is the rest
    /// transform with the channels sampled at `time` applied. Works for
    /// nodes in any order; a parent out of range or on a cycle is treated as
    /// absent.
    pub fn world_transforms(&self, time: f32) -> Vec<Mat4> {
        self.world_from_locals(&self.locals_at(time))
    }

    /// World matrices of the rest pose (no channel applied).
    pub fn rest_transforms(&self) -> Vec<Mat4> {
        let locals: Vec<Trs> = self.nodes.iter().map(|n| n.rest).collect();
        self.world_from_locals(&locals)
    }

    /// Triangles and camera at `time` seconds.
    ///
    /// Each instance's [`Rig::local`] triangles are transformed by its
    /// node's world matrix. A mirroring transform (negative determinant)
    /// flips the winding, so when the mirroring at `time` differs from the
    /// rest pose's, vertices 1 and 2 are swapped: the right-hand normal
    /// keeps pointing to the authored front side, and the vertex order stays
    /// that of [`crate::scene::Scene::triangles`] otherwise. Triangles not
    /// covered by an instance are returned untransformed.
    ///
    /// The camera sits at the camera node's world origin, looks along its
    /// world `-Z` axis (normalised) with its world `+Y` axis,
    /// re-orthogonalised against the view direction, as up: scale and shear
    /// do not distort it. A degenerate matrix falls back to `-Z` forward and
    /// some perpendicular up.
    pub fn pose(&self, time: f32) -> RigPose {
        let world = self.world_transforms(time);
        let rest = self.rest_transforms();
        let mut triangles = self.local.clone();
        let mut normals: Vec<[Vec3; 3]> = (0..triangles.len())
            .map(|i| self.local_normals.get(i).copied().unwrap_or([Vec3::ZERO; 3]))
            .collect();
        for inst in &self.instances {
            let (Some(m), Some(r)) = (world.get(inst.node), rest.get(inst.node)) else {
                continue;
            };
            let flip = (m.determinant() < 0.0) != (r.determinant() < 0.0);
            let end = inst
                .first_triangle
                .saturating_add(inst.triangle_count)
                .min(triangles.len());
            let start = inst.first_triangle.min(end);
            for t in &mut triangles[start..end] {
                let [a, b, c] = t.map(|v| m.transform_point3(v));
                *t = if flip { [a, c, b] } else { [a, b, c] };
            }
            let nm = normal_matrix(m);
            for n in &mut normals[start..end] {
                let [a, b, c] = n.map(|v| nm * v);
                *n = if flip { [a, c, b] } else { [a, b, c] };
            }
        }
        let camera = self.camera_in(&world);
        RigPose {
            triangles,
            normals,
            camera,
        }
    }

    /// The camera at `time` seconds alone (as [`Rig::pose`] places it),
    /// without transforming any triangle; `None` without a camera node.
    pub fn camera_at(&self, time: f32) -> Option<Camera> {
        self.camera_in(&self.world_transforms(time))
    }

    /// The camera node's camera under the world matrices `world`.
    fn camera_in(&self, world: &[Mat4]) -> Option<Camera> {
        self.camera
            .and_then(|c| world.get(c.node).map(|m| camera_from_matrix(m, c.fov_y_degrees)))
    }
}

/// The matrix that carries normals under the affine map `m`: the
/// inverse transpose of its linear part, up to a positive factor (the
/// cofactor matrix times the sign of the determinant, so it stays finite
/// for singular maps and keeps a mirrored normal on the mirrored outside).
/// Normalise what it gives.
pub fn normal_matrix(m: &Mat4) -> Mat3 {
    let (c0, c1, c2) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
    let cofactor = Mat3::from_cols(c1.cross(c2), c2.cross(c0), c0.cross(c1));
    if m.determinant() < 0.0 {
        -cofactor
    } else {
        cofactor
    }
}

/// The camera of a node with world matrix `m` (looking along local `-Z`,
/// `+Y` up).
pub fn camera_from_matrix(m: &Mat4, fov_y_degrees: f32) -> Camera {
    let origin = m.w_axis.truncate();
    let mut forward = m.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    if forward == Vec3::ZERO {
        forward = Vec3::NEG_Z;
    }
    let up = m.transform_vector3(Vec3::Y);
    let mut up = (up - forward * up.dot(forward)).normalize_or_zero();
    if up == Vec3::ZERO {
        up = forward.any_orthonormal_vector();
    }
    Camera {
        origin,
        target: origin + forward,
        up,
        fov_y_degrees,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animation::Interpolation;
    use glam::Vec4;
    use std::f32::consts::FRAC_PI_2;

    /// Parent: translated, rotated 90 degrees about +Y, scaled by 2; child:
    /// translated by +X in the parent's space, holding one triangle.
    fn two_level_rig(child_first: bool) -> Rig {
        let parent = Node {
            name: "parent".into(),
            parent: None,
            rest: Trs {
                translation: Vec3::new(1.0, 2.0, 3.0),
                rotation: Quat::from_rotation_y(FRAC_PI_2),
                scale: Vec3::splat(2.0),
            },
        };
        let child = |p| Node {
            name: "child".into(),
            parent: Some(p),
            rest: Trs {
                translation: Vec3::X,
                ..Trs::default()
            },
        };
        let (nodes, child_index) = if child_first {
            (vec![child(1), parent], 0)
        } else {
            (vec![parent, child(0)], 1)
        };
        Rig {
            nodes,
            channels: Vec::new(),
            instances: vec![MeshInstance {
                node: child_index,
                first_triangle: 0,
                triangle_count: 1,
            }],
            local: vec![[Vec3::ZERO, Vec3::X, Vec3::Y]],
            local_normals: Vec::new(),
            camera: None,
        }
    }

    /// Vertex normals follow the inverse transpose: under a non-uniform
    /// scale they stay perpendicular to the scaled surface, under an
    /// animated mirror they swap with their vertices and keep pointing to
    /// the mirrored outside; a rig without normals poses zeros.
    #[test]
    fn normals_follow_the_inverse_transpose() {
        let mut rig = two_level_rig(false);
        assert_eq!(rig.pose(0.0).normals, vec![[Vec3::ZERO; 3]]);
        rig.nodes[0].rest = Trs::default();
        rig.nodes[1].rest = Trs {
            scale: Vec3::new(1.0, 4.0, 1.0),
            ..Trs::default()
        };
        // The plane x + y = 1 (its normal (1, 1, 0) / sqrt 2) scaled by 4
        // along y becomes x + y / 4 = 1: normal (4, 1, 0) / sqrt 17.
        let tilted = Vec3::new(1.0, 1.0, 0.0).normalize();
        rig.local_normals = vec![[tilted, Vec3::Z, Vec3::X]];
        let n = rig.pose(0.0).normals[0].map(Vec3::normalize);
        assert!(
            n[0].abs_diff_eq(Vec3::new(4.0, 1.0, 0.0).normalize(), 1e-6),
            "{}",
            n[0]
        );
        assert!(n[1].abs_diff_eq(Vec3::Z, 1e-6) && n[2].abs_diff_eq(Vec3::X, 1e-6));
        // Mirror x from t = 1: vertices 1 and 2 swap, so do their normals,
        // and the +x normal becomes -x (the mirrored outside).
        rig.channels.push(mirror_x_from_one(1));
        let n = rig.pose(1.0).normals[0].map(Vec3::normalize);
        assert!(n[1].abs_diff_eq(Vec3::NEG_X, 1e-6), "{n:?}");
        assert!(n[2].abs_diff_eq(Vec3::Z, 1e-6), "{n:?}");
        assert!(
            n[0].abs_diff_eq(Vec3::new(-1.0, 1.0, 0.0).normalize(), 1e-6),
            "{n:?}"
        );
        // A singular map gives finite normals.
        assert!(normal_matrix(&Mat4::ZERO).is_finite());
    }

    #[test]
    fn hierarchy_places_a_child_vertex() {
        for child_first in [false, true] {
            let rig = two_level_rig(child_first);
            let pose = rig.pose(0.0);
            // Child origin: parent * (1, 0, 0) = (1,2,3) + R_y(90)(2, 0, 0) = (1,2,3) + (0,0,-2).
            let [a, b, c] = pose.triangles[0];
            assert!(a.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5), "{a}");
            // Local (1,0,0) of the child = parent-space (2,0,0) -> (0,0,-4) + (1,2,3).
            assert!(b.abs_diff_eq(Vec3::new(1.0, 2.0, -1.0), 1e-5), "{b}");
            // Local (0,1,0) -> parent-space (1,1,0) -> scaled (2,2,0) -> rotated (0,2,-2).
            assert!(c.abs_diff_eq(Vec3::new(1.0, 4.0, 1.0), 1e-5), "{c}");
            assert!(!rig.animates_geometry());
            assert_eq!(rig.duration(), 0.0);
        }
    }

    #[test]
    fn animated_parent_moves_the_child() {
        let mut rig = two_level_rig(true);
        rig.channels.push(Channel {
            node: 1, // the parent
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times: vec![1.0, 3.0],
            values: vec![Vec4::ZERO, Vec4::new(0.0, 10.0, 0.0, 0.0)],
        });
        assert!(rig.animates_geometry());
        assert!(!rig.animates_camera());
        assert_eq!(rig.duration(), 3.0);
        // Before the first key the first key applies (not the rest translation).
        let a = rig.pose(0.0).triangles[0][0];
        assert!(a.abs_diff_eq(Vec3::new(0.0, 0.0, -2.0), 1e-5), "{a}");
        let a = rig.pose(2.0).triangles[0][0];
        assert!(a.abs_diff_eq(Vec3::new(0.0, 5.0, -2.0), 1e-5), "{a}");
        let w = rig.world_transforms(2.0);
        assert!(w[1].w_axis.truncate().abs_diff_eq(Vec3::new(0.0, 5.0, 0.0), 1e-5));
    }

    #[test]
    fn cycles_and_bad_parents_do_not_hang() {
        let mut rig = two_level_rig(false);
        rig.nodes[0].parent = Some(1); // 0 <-> 1
        rig.nodes.push(Node {
            name: "orphan".into(),
            parent: Some(77),
            rest: Trs::default(),
        });
        let w = rig.world_transforms(0.0);
        assert_eq!(w.len(), 3);
        assert!(w.iter().all(|m| m.is_finite()));
        assert!(!rig.animates_geometry());
    }

    /// A step channel that scales `node` by (-1, 1, 1) from t = 1: a mirror.
    fn mirror_x_from_one(node: usize) -> Channel {
        Channel {
            node,
            property: Property::Scale,
            interpolation: Interpolation::Step,
            times: vec![0.0, 1.0],
            values: vec![Vec4::ONE, Vec4::new(-1.0, 1.0, 1.0, 0.0)],
        }
    }

    #[test]
    fn mirroring_keeps_the_authored_front() {
        let mut rig = two_level_rig(false);
        rig.nodes[1].rest.translation = Vec3::ZERO;
        rig.nodes[0].rest = Trs::default();
        // Scale x from +1 (rest) to -1 at t = 1: the mirror flips the winding.
        rig.channels.push(mirror_x_from_one(1));
        let normal = |t: [Vec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        assert!(normal(rig.pose(0.0).triangles[0]).abs_diff_eq(Vec3::Z, 1e-6));
        // Mirrored in x, the authored front (+Z) still faces +Z.
        let t = rig.pose(1.0).triangles[0];
        assert!(normal(t).abs_diff_eq(Vec3::Z, 1e-6), "{t:?}");
        assert!(t.contains(&Vec3::NEG_X));
    }

    #[test]
    fn camera_follows_its_node_and_ignores_scale() {
        let mut rig = two_level_rig(false);
        rig.nodes[1].rest.scale = Vec3::new(1.0, 3.0, 0.5); // non-uniform, under a rotated parent
        rig.camera = Some(RigCamera {
            node: 1,
            fov_y_degrees: 45.0,
        });
        let cam = rig.pose(0.0).camera.expect("camera");
        assert!(cam.origin.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5));
        // Local -Z under R_y(90) is -X.
        assert!((cam.target - cam.origin).abs_diff_eq(Vec3::NEG_X, 1e-5));
        assert!(cam.up.abs_diff_eq(Vec3::Y, 1e-5));
        assert_eq!(cam.fov_y_degrees, 45.0);
        assert!(cam.basis().is_ok());
        assert!(!rig.animates_camera());
        rig.channels.push(Channel {
            node: 0,
            property: Property::Rotation,
            interpolation: Interpolation::Linear,
            times: vec![0.0],
            values: vec![Vec4::from(Quat::IDENTITY)],
        });
        assert!(rig.animates_camera());
        // Parent rotation now the identity: the camera looks along -Z.
        let cam = rig.pose(0.0).camera.expect("camera");
        assert!((cam.target - cam.origin).abs_diff_eq(Vec3::NEG_Z, 1e-5));
        // A degenerate (zero-scale) matrix still gives a usable camera.
        let cam = camera_from_matrix(&Mat4::ZERO, 30.0);
        assert!(cam.basis().is_ok());
    }
}
