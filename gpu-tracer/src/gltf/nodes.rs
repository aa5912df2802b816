//! The node hierarchy of the loaded scene: its nodes depth first, and each
//! node's rest transform as a [`Trs`].

use super::loader::{label, Loader};
use crate::animation::Trs;
use crate::error::Result;
use glam::{Mat4, Quat, Vec3, Vec4};

impl<'p> Loader<'p> {
    /// The scene's nodes depth first (children in file order) with their
    /// parent's position in that order.
    pub(super) fn traverse<'d>(
        &self,
        scene: &gltf::Scene<'d>,
    ) -> Result<Vec<(gltf::Node<'d>, Option<usize>)>> {
        let mut seen = vec![false; self.document.nodes().len()];
        let mut order = Vec::new();
        let mut stack: Vec<(gltf::Node<'d>, Option<usize>)> = scene.nodes().map(|n| (n, None)).collect();
        stack.reverse();
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut seen[node.index()], true) {
                return Err(self.content(
                    label("node", node.index(), node.name()),
                    "appears more than once in the scene's hierarchy (a cycle, or two parents)",
                ));
            }
            let me = order.len();
            let first_child = stack.len();
            stack.extend(node.children().map(|c| (c, Some(me))));
            stack[first_child..].reverse();
            order.push((node, parent));
        }
        Ok(order)
    }

    /// A node's file transform as a [`Trs`].
    pub(super) fn rest_transform(&mut self, node: &gltf::Node) -> Result<Trs> {
        let element = || label("node", node.index(), node.name());
        match node.transform() {
            gltf::scene::Transform::Decomposed {
                translation,
                rotation,
                scale,
            } => {
                let (t, r, s) = (Vec3::from(translation), Vec4::from(rotation), Vec3::from(scale));
                if !(t.is_finite() && r.is_finite() && s.is_finite()) {
                    return Err(self.content(element(), "translation, rotation or scale is NaN or infinite"));
                }
                if r.length() < 1e-6 {
                    return Err(self.content(element(), "rotation is a zero quaternion"));
                }
                Ok(Trs {
                    translation: t,
                    rotation: Quat::from_vec4(r.normalize()),
                    scale: s,
                })
            }
            gltf::scene::Transform::Matrix { matrix } => {
                let m = Mat4::from_cols_array_2d(&matrix);
                if !m.is_finite() {
                    return Err(self.content(element(), "matrix is NaN or infinite"));
                }
                let (scale, rotation, translation) = m.to_scale_rotation_translation();
                let rotation = if rotation.is_finite() && rotation.length() > 1e-6 {
                    rotation.normalize()
                } else {
                    Quat::IDENTITY
                };
                let trs = Trs {
                    translation,
                    rotation,
                    scale: if scale.is_finite() { scale } else { Vec3::ZERO },
                };
                let tolerance = 1e-4 * m.to_cols_array().iter().fold(1.0f32, |a, v| a.max(v.abs()));
                if !trs.matrix().abs_diff_eq(m, tolerance) {
                    self.notices.push(format!(
                        "{}: its matrix has shear, approximated by translation, rotation and scale",
                        element()
                    ));
                }
                Ok(trs)
            }
        }
    }
}
