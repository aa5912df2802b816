//! The camera: the chosen camera node of the scene and its vertical field
//! of view.

use super::loader::{label, Loader};
use crate::animation::RigCamera;
use crate::error::Result;

impl<'p> Loader<'p> {
    /// The chosen camera node, if any.
    pub(super) fn camera(
        &self,
        order: &[(gltf::Node, Option<usize>)],
        camera_index: Option<usize>,
    ) -> Result<Option<RigCamera>> {
        let cameras: Vec<(usize, gltf::Camera)> = order
            .iter()
            .enumerate()
            .filter_map(|(i, (n, _))| n.camera().map(|c| (i, c)))
            .collect();
        let wanted = camera_index.unwrap_or(0);
        let Some((node, camera)) = cameras.get(wanted) else {
            if camera_index.is_none() {
                return Ok(None);
            }
            return Err(self.content(
                format!("camera index {wanted}"),
                format!("out of range: the scene has {} camera node(s)", cameras.len()),
            ));
        };
        let element = label("camera", camera.index(), camera.name());
        match camera.projection() {
            gltf::camera::Projection::Orthographic(_) => {
                Err(self.content(element, "orthographic cameras are not supported"))
            }
            gltf::camera::Projection::Perspective(p) => {
                let yfov = p.yfov();
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(self.content(element, format!("yfov {yfov} rad is outside (0, pi)")));
                }
                Ok(Some(RigCamera {
                    node: *node,
                    fov_y_degrees: yfov.to_degrees(),
                }))
            }
        }
    }
}
