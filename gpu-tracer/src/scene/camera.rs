//! The pinhole [`Camera`] and its orthonormal [`CameraBasis`].

use crate::error::{Error, Result};
use glam::Vec3;

/// A pinhole camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position, world units.
    pub origin: Vec3,
    /// Point looked at (the image centre), `!= origin`.
    pub target: Vec3,
    /// Approximate up direction, not parallel to `target - origin`.
    pub up: Vec3,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov_y_degrees: f32,
}

/// The orthonormal basis of a [`Camera`]: the camera part of
/// [`TraceParams`](kernels::abi::TraceParams).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// Eye position.
    pub origin: Vec3,
    /// Unit viewing direction.
    pub forward: Vec3,
    /// Unit vector to the image's right: `forward x up`, normalised.
    pub right: Vec3,
    /// Unit vector to the image's top: `right x forward`.
    pub up: Vec3,
    /// `tan(fov_y / 2)`.
    pub tan_half_fov_y: f32,
}

impl Camera {
    /// The camera's orthonormal basis.
    ///
    /// # Errors
    /// [`Error::InvalidCamera`] when a vector is non-finite, `target ==
    /// origin`, `up` is (nearly) parallel to the view direction, or the field
    /// of view is outside `(0, 180)` degrees.
    pub fn basis(&self) -> Result<CameraBasis> {
        let finite = self.origin.is_finite() && self.target.is_finite() && self.up.is_finite();
        let fov_ok = self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0;
        let forward = (self.target - self.origin).normalize_or_zero();
        let right = forward.cross(self.up.normalize_or_zero());
        if !finite || !fov_ok || forward == Vec3::ZERO || right.length() < 1e-6 {
            return Err(Error::InvalidCamera);
        }
        let right = right.normalize();
        Ok(CameraBasis {
            origin: self.origin,
            forward,
            right,
            up: right.cross(forward),
            tan_half_fov_y: (self.fov_y_degrees.to_radians() * 0.5).tan(),
        })
    }

    /// A camera framing the box `[min, max]` from its `+z` side, looking
    /// along `-z` with `+y` up and a 40-degree vertical field of view, far
    /// enough that the box's bounding sphere fits the vertical field of view.
    /// Used for OBJ files, which carry no camera.
    pub fn framing(min: Vec3, max: Vec3) -> Camera {
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-3);
        let fov_y_degrees = 40.0f32;
        let distance = radius / (fov_y_degrees.to_radians() * 0.5).sin();
        Camera {
            origin: centre + Vec3::Z * distance,
            target: centre,
            up: Vec3::Y,
            fov_y_degrees,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_basis_and_framing() {
        let b = Camera {
            origin: Vec3::new(278.0, 273.0, -800.0),
            target: Vec3::new(278.0, 273.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 90.0,
        }
        .basis()
        .expect("valid");
        assert_eq!(b.forward, Vec3::Z);
        assert_eq!(b.right, -Vec3::X);
        assert_eq!(b.up, Vec3::Y);
        assert!((b.tan_half_fov_y - 1.0).abs() < 1e-6);
        let cam = Camera::framing(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert!(cam.basis().is_ok());
        assert!(cam.origin.z > 1.0 && cam.target == Vec3::ZERO);
        let bad = Camera {
            fov_y_degrees: 180.0,
            ..cam
        };
        assert!(bad.basis().is_err());
    }
}
