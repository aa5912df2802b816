//! The pinhole camera: primary rays through jittered pixel positions.
//!
//! Pixel `(x, y)` covers `[x, x + 1) x [y, y + 1)` in raster space, `x` to
//! the right and `y` downwards (row 0 is the top of the image). The image
//! plane at distance 1 spans `±tan(fov_y / 2) * width / height`
//! horizontally and `±tan(fov_y / 2)` vertically.

use crate::abi::TraceParams;
use crate::intersect::Ray;
use glam::{Vec2, Vec3};

/// Primary ray through raster position `(x + jitter.x, y + jitter.y)`.
///
/// `jitter` in `[0, 1)^2` picks the point inside the pixel. The direction is
/// unit length; the origin is the camera position. Pixels outside the frame
/// give valid rays outside the field of view.
#[inline]
pub fn primary_ray(params: &TraceParams, x: u32, y: u32, jitter: Vec2) -> Ray {
    let width = params.width.max(1) as f32;
    let height = params.height.max(1) as f32;
    let aspect = width / height;
    // Normalised device coordinates in [-1, 1], y up.
    let ndc_x = 2.0 * (x as f32 + jitter.x) / width - 1.0;
    let ndc_y = 1.0 - 2.0 * (y as f32 + jitter.y) / height;
    let forward = params.camera_forward.truncate();
    let right = params.camera_right.truncate();
    let up = params.camera_up.truncate();
    let t = params.tan_half_fov_y;
    let dir = forward + right * (ndc_x * t * aspect) + up * (ndc_y * t);
    Ray::new(params.camera_origin.truncate(), dir.normalize())
}

/// A pinhole camera's basis, as the current or the previous frame's fields
/// of [`TraceParams`] hold it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// Eye position, world units.
    pub origin: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit vector to the image's right.
    pub right: Vec3,
    /// Unit vector to the image's top.
    pub up: Vec3,
    /// `tan(fov_y / 2)`, `> 0`.
    pub tan_half_fov_y: f32,
}

impl CameraView {
    /// This frame's camera of `params`.
    #[inline]
    pub fn current(params: &TraceParams) -> Self {
        CameraView {
            origin: params.camera_origin.truncate(),
            forward: params.camera_forward.truncate(),
            right: params.camera_right.truncate(),
            up: params.camera_up.truncate(),
            tan_half_fov_y: params.tan_half_fov_y,
        }
    }

    /// The previous frame's camera of `params`.
    #[inline]
    pub fn previous(params: &TraceParams) -> Self {
        CameraView {
            origin: params.prev_camera_origin.truncate(),
            forward: params.prev_camera_forward.truncate(),
            right: params.prev_camera_right.truncate(),
            up: params.prev_camera_up.truncate(),
            tan_half_fov_y: params.prev_tan_half_fov_y,
        }
    }

    /// Raster position (in a `width x height` frame) and linear depth `z`
    /// (distance along `forward`) of the direction `d` from the eye, or
    /// `None` when `z <= 0` (behind the camera).
    #[inline]
    pub fn project_offset(&self, width: u32, height: u32, d: Vec3) -> Option<(Vec2, f32)> {
        let z = d.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let t = self.tan_half_fov_y;
        let aspect = width.max(1) as f32 / height.max(1) as f32;
        let ndc_x = d.dot(self.right) / (z * t * aspect);
        let ndc_y = d.dot(self.up) / (z * t);
        Some((
            Vec2::new(
                (ndc_x + 1.0) * 0.5 * width as f32,
                (1.0 - ndc_y) * 0.5 * height as f32,
            ),
            z,
        ))
    }

    /// Raster position and linear depth of world point `p` (see
    /// [`Self::project_offset`]).
    #[inline]
    pub fn project(&self, width: u32, height: u32, p: Vec3) -> Option<(Vec2, f32)> {
        self.project_offset(width, height, p - self.origin)
    }
}

/// Raster position of world point `p` seen by the camera (inverse of
/// [`primary_ray`]'s mapping), or `None` when `p` is not in front of it.
/// Used by tests and the host to locate scene features in images.
#[inline]
pub fn project_point(params: &TraceParams, p: Vec3) -> Option<Vec2> {
    CameraView::current(params)
        .project(params.width, params.height, p)
        .map(|(raster, _)| raster)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn params() -> TraceParams {
        TraceParams {
            width: 200,
            height: 100,
            tan_half_fov_y: 1.0, // 90 degrees vertically
            camera_origin: Vec4::new(1.0, 2.0, 3.0, 0.0),
            camera_forward: Vec4::new(0.0, 0.0, -1.0, 0.0),
            camera_right: Vec4::new(1.0, 0.0, 0.0, 0.0),
            camera_up: Vec4::new(0.0, 1.0, 0.0, 0.0),
            ..Default::default()
        }
    }

    #[test]
    fn centre_and_corners() {
        let p = params();
        let centre = primary_ray(&p, 100, 50, Vec2::ZERO);
        assert!((centre.dir - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert_eq!(centre.origin, Vec3::new(1.0, 2.0, 3.0));
        // Top-left corner of the raster: left (-x) and up (+y), 45 degrees vertically.
        let tl = primary_ray(&p, 0, 0, Vec2::ZERO);
        let expect = Vec3::new(-2.0, 1.0, -1.0).normalize();
        assert!((tl.dir - expect).length() < 1e-6, "{}", tl.dir);
    }

    #[test]
    fn projection_inverts_the_ray() {
        let p = params();
        for (x, y, j) in [
            (0, 0, Vec2::new(0.5, 0.5)),
            (137, 12, Vec2::new(0.1, 0.9)),
            (199, 99, Vec2::ZERO),
        ] {
            let ray = primary_ray(&p, x, y, j);
            let raster = project_point(&p, ray.at(7.0)).expect("in front");
            let want = Vec2::new(x as f32, y as f32) + j;
            assert!((raster - want).length() < 1e-3, "{raster} vs {want}");
        }
        assert_eq!(project_point(&p, Vec3::new(1.0, 2.0, 4.0)), None);
    }
}
