//! Simple camera paths, so motion can be studied on every scene (the
//! built-in Cornell box and OBJ files have no animation of their own).
//!
//! A path moves a base [`Camera`] as a function of the frame index `t`
//! (frames since the start of the sequence, `t >= 0`), at a constant speed
//! whose unit depends on the path:
//!
//! | path | speed unit | positive speed |
//! |---|---|---|
//! | [`CameraPathKind::Orbit`] | degrees per frame | the eye turns about the world-up axis through the target, towards its right (right-hand rule about `up`); the picture moves left |
//! | [`CameraPathKind::Dolly`] | scene units per frame | eye and target move forward along the view direction |
//! | [`CameraPathKind::Pan`] | pixels per frame | eye and target move right so that points at the target's depth move `speed` pixels left per frame |
//!
//! The pan is the path to use when a screen-space speed matters (a motion
//! study at "0.5 px/frame"): it is exact for the plane through the target
//! facing the camera, and nearer points move faster.

use crate::error::{Error, Result};
use crate::scene::Camera;
use glam::{Quat, Vec3};

/// Which way a [`CameraPath`] moves the camera (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraPathKind {
    /// Rotation about the target, `speed` in degrees per frame.
    Orbit,
    /// Translation along the view direction, `speed` in scene units per frame.
    Dolly,
    /// Translation along the image's right axis, `speed` in pixels per frame
    /// at the target's depth.
    Pan,
}

/// A camera path: a kind and a constant speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraPath {
    /// The motion.
    pub kind: CameraPathKind,
    /// Speed in the kind's unit per frame (module docs); finite, any sign.
    pub speed: f32,
}

impl CameraPath {
    /// The camera at frame `t` (frames since the sequence started, may be
    /// fractional) for an image `height` pixels high (used by
    /// [`CameraPathKind::Pan`] to turn pixels into scene units).
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] when `base` is degenerate, the speed is not
    /// finite or the moved camera is degenerate.
    pub fn camera_at(&self, base: &Camera, t: f32, height: u32) -> Result<Camera> {
        let basis = base.basis()?;
        if !self.speed.is_finite() || !t.is_finite() {
            return Err(Error::InvalidCamera);
        }
        let amount = self.speed * t;
        let camera = match self.kind {
            CameraPathKind::Orbit => {
                let axis = base.up.normalize();
                let rotation = Quat::from_axis_angle(axis, amount.to_radians());
                Camera {
                    origin: base.target + rotation * (base.origin - base.target),
                    ..*base
                }
            }
            CameraPathKind::Dolly => {
                let shift = basis.forward * amount;
                Camera {
                    origin: base.origin + shift,
                    target: base.target + shift,
                    ..*base
                }
            }
            CameraPathKind::Pan => {
                let distance = (base.target - base.origin).dot(basis.forward);
                let metres_per_pixel = 2.0 * distance * basis.tan_half_fov_y / height.max(1) as f32;
                let shift: Vec3 = basis.right * (amount * metres_per_pixel);
                Camera {
                    origin: base.origin + shift,
                    target: base.target + shift,
                    ..*base
                }
            }
        };
        camera.basis()?;
        Ok(camera)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use kernels::camera::CameraView;

    fn base() -> Camera {
        Camera {
            origin: Vec3::new(0.0, 1.0, 10.0),
            target: Vec3::new(0.0, 1.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 60.0,
        }
    }

    fn view(c: &Camera) -> CameraView {
        let b = c.basis().unwrap();
        CameraView {
            origin: b.origin,
            forward: b.forward,
            right: b.right,
            up: b.up,
            tan_half_fov_y: b.tan_half_fov_y,
        }
    }

    #[test]
    fn pan_moves_the_target_plane_by_the_given_pixels() {
        let path = CameraPath {
            kind: CameraPathKind::Pan,
            speed: 2.0,
        };
        let p = Vec3::new(1.5, 0.3, 0.0); // on the plane through the target
        let (a, _) = view(&base()).project(200, 100, p).unwrap();
        for t in [1.0f32, 3.0, 7.5] {
            let moved = path.camera_at(&base(), t, 100).unwrap();
            let (b, _) = view(&moved).project(200, 100, p).unwrap();
            assert!((b.x - (a.x - 2.0 * t)).abs() < 1e-3, "t {t}: {a} -> {b}");
            assert!((b.y - a.y).abs() < 1e-4);
        }
    }

    #[test]
    fn orbit_keeps_the_distance_and_the_target() {
        let path = CameraPath {
            kind: CameraPathKind::Orbit,
            speed: 90.0,
        };
        let c = path.camera_at(&base(), 1.0, 100).unwrap();
        assert_eq!(c.target, base().target);
        // A quarter turn about +y takes the eye from +z to +x: to its right.
        assert!(
            (c.origin - Vec3::new(10.0, 1.0, 0.0)).length() < 1e-4,
            "{}",
            c.origin
        );
        assert_eq!(path.camera_at(&base(), 0.0, 100).unwrap(), base());
    }

    #[test]
    fn dolly_moves_forward_and_bad_speeds_are_errors() {
        let path = CameraPath {
            kind: CameraPathKind::Dolly,
            speed: 0.5,
        };
        let c = path.camera_at(&base(), 4.0, 100).unwrap();
        assert!((c.origin - Vec3::new(0.0, 1.0, 8.0)).length() < 1e-5);
        let bad = CameraPath {
            speed: f32::NAN,
            ..path
        };
        assert!(matches!(
            bad.camera_at(&base(), 1.0, 100),
            Err(Error::InvalidCamera)
        ));
    }
}
