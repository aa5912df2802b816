//! Importance sampling of an equirectangular (latitude-longitude)
//! environment map, on top of the 2D piecewise-constant distribution of
//! [`piecewise`](super::piecewise).
//!
//! # Conventions
//!
//! - **+Y is up.** Texel rows run from the top of the image (`v = 0`, +Y)
//!   to the bottom (`v = 1`, -Y): the polar angle from +Y is `theta = pi v`.
//! - **`u = 0.5`, the image's centre column, looks down -Z** (where a camera
//!   with the usual right-handed, Y-up view looks), and **`u` increases to
//!   the viewer's right**: `u = 0.75` is +X, `u = 0` (and 1) is +Z,
//!   `u = 0.25` is -X. Seen from above, `u` increases clockwise: a step of
//!   `u` is a rotation by `-2 pi u` about +Y (right-hand rule). A panorama
//!   therefore looks unmirrored from inside the sphere.
//! - With `phi = 2 pi (u + rotation_turns)`:
//!   `direction = (-sin(theta) sin(phi), cos(theta), sin(theta) cos(phi))`
//!   ([`uv_to_direction`], inverse [`direction_to_uv`]).
//! - **The rotation about +Y is in turns** (1 turn = `2 pi` rad = the whole
//!   map width; only its fractional part matters, and small values keep the
//!   most precision). A positive rotation turns the map's content to the
//!   viewer's right (clockwise seen from above): the texel column at `u` is
//!   seen where column `u + rotation_turns` is without rotation.
//! - Texel `(x, y)` of a `width x height` map covers `u` in
//!   `[x / width, (x + 1) / width)` and `v` in `[y / height, (y + 1) / height)`,
//!   row-major from the top-left.
//!
//! # Weights and pdf
//!
//! The sampling weight of texel `(x, y)` is its **luminance** (linear RGB,
//! Rec. 709 weights [`luminance`]) times `sin(theta)` of its row's centre
//! ([`row_sin_theta`]): the texel's solid angle is proportional to it
//! ([`texel_solid_angle`]). Since `d omega = sin(theta) d theta d phi =
//! 2 pi^2 sin(theta) du dv`, the density per steradian of a direction is
//!
//! ```text
//! pdf(omega) = pdf_uv(u, v) / (2 pi^2 sin(theta))
//! ```
//!
//! with `sin(theta)` of the direction itself, so inside one texel the pdf
//! follows `L sin(theta_row) / sin(theta)`, nearly proportional to `L`
//! except in the rows at the poles.
//!
//! **Poles:** where `sin(theta) < `[`MIN_SIN_THETA`] (within `1e-9` rad of
//! +Y or -Y, a cap of about `3e-18` sr) both [`sample_environment`] and
//! [`pdf_environment`] give pdf 0, never NaN or infinity; a caller discards
//! a sample with pdf 0, as pbrt does (that loses the cap's energy and, for a
//! map bright in its first or last row, about `3e-10 * height` of that
//! row's samples). Elsewhere the pdf is finite, at most
//! `width * height / (2 pi^2 MIN_SIN_THETA)` (`5.4e16` for the largest
//! map), so even its square (power heuristic) is finite in `f32`.
//!
//! An all-zero map samples `(u, v)` uniformly (pdf `1 / (2 pi^2 sin(theta))`
//! per steradian) and has [`EnvironmentMap::luminance_integral`] 0.
//!
//! Sampling and pdf are written for shaders (`u32`/`f32`, only `libm`
//! functions that rust-gpu maps to GLSL.std.450: `sincosf`, `sinf`,
//! `atan2f`, `sqrtf`, `floorf`; no allocation, no panics; compiled to
//! SPIR-V when the tracer integrates them); the builders are host code. CPU and GPU agree to the precision of the device's
//! `sin`/`cos`/`atan2`, not bit for bit. Table layout and out-of-range
//! behaviour as in [`piecewise`](super::piecewise).

use super::piecewise::{check_len, check_size, pdf_2d, sample_2d, Distribution2d};
use crate::error::{Buffer, Error};
use core::f32::consts::{PI, TAU};
use glam::{UVec2, Vec2, Vec3};

/// Smallest `sin(theta)` with a non-zero pdf: within `1e-9` rad of a pole
/// the pdf per steradian is 0. Chosen so the pdf and its square stay finite
/// in `f32` for any map (see the [module doc](self)) while `sin(theta)`
/// recomputed from a direction's components (about `1e-9`, squares `1e-18`)
/// is still exact to `f32` precision.
pub const MIN_SIN_THETA: f32 = 1e-9;

/// `2 pi^2`: the Jacobian `d omega / (du dv)` divided by `sin(theta)`.
const TWO_PI_SQUARED: f32 = 2.0 * PI * PI;

/// An environment map's shape and orientation as plain scalars, the form
/// shaders receive (16 bytes, Vulkan block layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct EnvironmentParams {
    /// Texels per row, in `1..=MAX_DISTRIBUTION_SIDE`.
    pub width: u32,
    /// Rows, in `1..=MAX_DISTRIBUTION_SIDE`.
    pub height: u32,
    /// Rotation about +Y in turns (see the [module doc](self)); 0 for none.
    pub rotation_turns: f32,
    /// Unused; keeps the struct 16 bytes. Zero.
    pub reserved: u32,
}

const _: () = assert!(core::mem::size_of::<EnvironmentParams>() == 16);

/// A direction drawn from an environment map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentSample {
    /// Unit direction toward the environment (world space, +Y up).
    pub direction: Vec3,
    /// Density per steradian; 0 within [`MIN_SIN_THETA`] of a pole (discard
    /// the sample), else finite and `> 0`.
    pub pdf: f32,
    /// The map coordinates of `direction` (rotation undone), in `[0, 1)^2`:
    /// where to fetch its radiance.
    pub uv: Vec2,
    /// The texel (column, row) it was drawn from.
    pub texel: UVec2,
}

/// Rec. 709 luminance of linear RGB: `0.2126 r + 0.7152 g + 0.0722 b`.
/// Identical to [`luma`](crate::luma).
#[inline]
pub fn luminance(rgb: Vec3) -> f32 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

/// `(sin(pi v), cos(pi v))` for `v` in `[0, 1]`, accurate at both poles
/// (for `v > 1/2` it is computed from the exact `1 - v`).
#[inline]
fn polar(v: f32) -> (f32, f32) {
    if v <= 0.5 {
        libm::sincosf(PI * v)
    } else {
        let (s, c) = libm::sincosf(PI * (1.0 - v));
        (s, -c)
    }
}

/// `x - floor(x)`, in `[0, 1)` (a result that rounds up to 1 becomes 0).
#[inline]
fn wrap_unit(x: f32) -> f32 {
    let f = x - libm::floorf(x);
    if f >= 1.0 {
        0.0
    } else {
        f
    }
}

/// `sin(theta)` at the centre of row `y` of `height`: `sin(pi (y + 0.5) /
/// height)`, in `(0, 1]`.
#[inline]
pub fn row_sin_theta(y: u32, height: u32) -> f32 {
    polar((y as f32 + 0.5) / height.max(1) as f32).0
}

/// Sampling weight of a texel of row `y` of `height` with linear RGB `rgb`:
/// [`luminance`]`(rgb) * `[`row_sin_theta`]`(y, height)`.
#[inline]
pub fn texel_weight(rgb: Vec3, y: u32, height: u32) -> f32 {
    luminance(rgb) * row_sin_theta(y, height)
}

/// Solid angle in steradians of a texel of row `y` of a `width x height`
/// map: `2 pi / width * (cos(theta_top) - cos(theta_bottom))`, computed as
/// `4 pi / width * sin(theta_centre) * sin(pi / (2 height))` (the same
/// quantity, without cancellation). The texels sum to `4 pi`.
#[inline]
pub fn texel_solid_angle(width: u32, height: u32, y: u32) -> f32 {
    let height = height.max(1);
    2.0 * TAU / width.max(1) as f32 * row_sin_theta(y, height) * libm::sinf(PI / (2.0 * height as f32))
}

/// The unit direction of map coordinates `uv` (`u` any value, wrapping;
/// `v` in `[0, 1]`, `v = 0` is +Y) under a rotation of `rotation_turns`
/// about +Y (conventions in the [module doc](self)).
#[inline]
pub fn uv_to_direction(uv: Vec2, rotation_turns: f32) -> Vec3 {
    let (sin_theta, cos_theta) = polar(uv.y);
    let (sin_phi, cos_phi) = libm::sincosf(TAU * wrap_unit(uv.x + rotation_turns));
    Vec3::new(-sin_theta * sin_phi, cos_theta, sin_theta * cos_phi)
}

/// The map coordinates in `[0, 1) x [0, 1]` of the direction `dir` (any
/// length) under a rotation of `rotation_turns` about +Y: the inverse of
/// [`uv_to_direction`]. On the CPU a direction along +Y or -Y gets the `u`
/// of `phi = 0` (+Z) less the rotation, and a zero direction that `u` and
/// `v = 0`; in a shader `atan2(0, 0)` is undefined, so `u` is arbitrary
/// there (`v` is still right for +Y and -Y).
#[inline]
pub fn direction_to_uv(dir: Vec3, rotation_turns: f32) -> Vec2 {
    let rho = libm::sqrtf(dir.x * dir.x + dir.z * dir.z);
    let v = libm::atan2f(rho, dir.y) * (1.0 / PI);
    let u = wrap_unit(libm::atan2f(-dir.x, dir.z) * (1.0 / TAU) - rotation_turns);
    Vec2::new(u, if v >= 0.0 { v.min(1.0) } else { 0.0 })
}

/// Draws a direction from the environment map whose 2D distribution table
/// is `table` ([`EnvironmentMap`]'s) with the uniform pair `u` in
/// `[0, 1)^2` (`u.y` picks the row, `u.x` the column). The pdf is per
/// steradian and 0 within [`MIN_SIN_THETA`] of a pole. Shader-ready.
#[inline]
pub fn sample_environment(table: &[f32], params: EnvironmentParams, u: Vec2) -> EnvironmentSample {
    let s = sample_2d(table, params.width, params.height, u);
    let (sin_theta, cos_theta) = polar(s.point.y);
    let (sin_phi, cos_phi) = libm::sincosf(TAU * wrap_unit(s.point.x + params.rotation_turns));
    let pdf = if sin_theta >= MIN_SIN_THETA {
        s.pdf / (TWO_PI_SQUARED * sin_theta)
    } else {
        0.0
    };
    EnvironmentSample {
        direction: Vec3::new(-sin_theta * sin_phi, cos_theta, sin_theta * cos_phi),
        pdf,
        uv: s.point,
        texel: s.cell,
    }
}

/// Density per steradian with which [`sample_environment`] draws `dir` (any
/// non-zero length): `pdf_uv / (2 pi^2 sin(theta))`. 0 within
/// [`MIN_SIN_THETA`] of a pole, for a zero or non-finite `dir`, and where the
/// map is black (if it is not all black). Shader-ready.
#[inline]
pub fn pdf_environment(table: &[f32], params: EnvironmentParams, dir: Vec3) -> f32 {
    let length = libm::sqrtf(dir.length_squared());
    let sin_theta = libm::sqrtf(dir.x * dir.x + dir.z * dir.z) / length;
    // Also false for NaN: zero, infinite and NaN directions. `<= f32::MAX`,
    // not `< INFINITY`: naga rejects infinite literals in SPIR-V.
    if sin_theta >= MIN_SIN_THETA && length <= f32::MAX {
        let uv = direction_to_uv(dir, params.rotation_turns);
        pdf_2d(table, params.width, params.height, uv) / (TWO_PI_SQUARED * sin_theta)
    } else {
        0.0
    }
}

/// A validated equirectangular environment map's sampling table, with its
/// rotation (conventions in the [module doc](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvironmentMap<'a> {
    distribution: Distribution2d<'a>,
    rotation_turns: f32,
}

impl<'a> EnvironmentMap<'a> {
    /// Table entries for a `width x height` map: `1 + height + width *
    /// height` ([`Distribution2d::table_len`]).
    pub fn table_len(width: u32, height: u32) -> usize {
        Distribution2d::table_len(width, height)
    }

    /// Builds the sampling table of the `width x height` map of row-major
    /// linear RGB texels `rgb` into `table` (weights: [`texel_weight`]),
    /// with no rotation.
    ///
    /// A texel whose luminance is negative, NaN or infinite is an error;
    /// negative channels with a non-negative luminance (out-of-gamut HDR
    /// colours) are accepted.
    ///
    /// # Errors
    /// [`Error::DistributionSize`] if a side is 0 or over
    /// [`MAX_DISTRIBUTION_SIDE`](crate::limits::MAX_DISTRIBUTION_SIDE);
    /// [`Error::BufferSize`] if `rgb` does not have `width * height`
    /// entries or `table` not [`Self::table_len`]`(width, height)`;
    /// [`Error::Weight`] (the weight, luminance times `sin(theta)`) for the
    /// first bad texel, row by row. On error `table` may be partly written.
    pub fn build(width: u32, height: u32, rgb: &[[f32; 3]], table: &'a mut [f32]) -> Result<Self, Error> {
        check_size(width, height)?;
        check_len(
            Buffer::EnvironmentTexels,
            width as usize * height as usize,
            rgb.len(),
        )?;
        Self::build_with(width, height, table, |x, y| {
            Vec3::from_array(rgb[y as usize * width as usize + x as usize])
        })
    }

    /// [`Self::build`] with the linear RGB of texel `(x, y)` given by
    /// `radiance(x, y)`, called once per texel, row by row (for RGBA or
    /// half-float images, or radiance computed on the fly).
    ///
    /// # Errors
    /// As [`Self::build`], less the texel buffer's length.
    pub fn build_with(
        width: u32,
        height: u32,
        table: &'a mut [f32],
        mut radiance: impl FnMut(u32, u32) -> Vec3,
    ) -> Result<Self, Error> {
        // sin(theta) once per row, not per texel.
        let mut row = (u32::MAX, 0.0f32);
        let distribution = Distribution2d::build_with(width, height, table, |x, y| {
            if row.0 != y {
                row = (y, row_sin_theta(y, height));
            }
            luminance(radiance(x, y)) * row.1
        })?;
        Ok(EnvironmentMap {
            distribution,
            rotation_turns: 0.0,
        })
    }

    /// Wraps a table built earlier by [`Self::build`] (possibly read back
    /// from a file or buffer), with no rotation. The entries are not checked.
    ///
    /// # Errors
    /// As [`Distribution2d::new`].
    pub fn new(width: u32, height: u32, table: &'a [f32]) -> Result<Self, Error> {
        Ok(EnvironmentMap {
            distribution: Distribution2d::new(width, height, table)?,
            rotation_turns: 0.0,
        })
    }

    /// The same map rotated by `turns` about +Y (replacing any earlier
    /// rotation; positive turns the content to the viewer's right).
    pub fn with_rotation_turns(self, turns: f32) -> Self {
        EnvironmentMap {
            rotation_turns: turns,
            ..self
        }
    }

    /// Rotation about +Y in turns.
    pub fn rotation_turns(&self) -> f32 {
        self.rotation_turns
    }

    /// The 2D distribution over map coordinates (pdf per unit `u`, `v`).
    pub fn distribution(&self) -> Distribution2d<'a> {
        self.distribution
    }

    /// Shape and rotation as the [`EnvironmentParams`] shaders take.
    pub fn params(&self) -> EnvironmentParams {
        EnvironmentParams {
            width: self.distribution.width(),
            height: self.distribution.height(),
            rotation_turns: self.rotation_turns,
            reserved: 0,
        }
    }

    /// `∫ Y(omega) d omega` over the sphere, in luminance times steradians,
    /// of the map with each texel's luminance `Y` constant over the texel:
    /// `sum(Y * `[`texel_solid_angle`]`)`, from the table's integral as
    /// `4 pi height sin(pi / (2 height)) * integral` (to `f32` rounding).
    pub fn luminance_integral(&self) -> f32 {
        let h = self.distribution.height() as f32;
        2.0 * TAU * h * libm::sinf(PI / (2.0 * h)) * self.distribution.integral()
    }

    /// [`sample_environment`] of this map.
    #[inline]
    pub fn sample(&self, u: Vec2) -> EnvironmentSample {
        sample_environment(self.distribution.table(), self.params(), u)
    }

    /// A direction drawn with `u` in `[0, 1)^2` and its density per
    /// steradian (0 within [`MIN_SIN_THETA`] of a pole: discard it); the
    /// density equals [`Self::pdf`] of the direction.
    #[inline]
    pub fn sample_direction(&self, u: Vec2) -> (Vec3, f32) {
        let s = self.sample(u);
        (s.direction, s.pdf)
    }

    /// [`pdf_environment`] of this map: the density per steradian with
    /// which [`Self::sample_direction`] draws `dir`.
    #[inline]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        pdf_environment(self.distribution.table(), self.params(), dir)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::sequences::seed::random_f32;
    use std::vec;
    use std::vec::Vec;

    fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
        (a - b).abs().max_element() <= tolerance
    }

    #[test]
    fn axes_and_orientation_follow_the_conventions() {
        let d = |u: f32, v: f32| uv_to_direction(Vec2::new(u, v), 0.0);
        assert!(close(d(0.5, 0.5), Vec3::NEG_Z, 1e-6));
        assert!(close(d(0.75, 0.5), Vec3::X, 1e-6));
        assert!(close(d(0.0, 0.5), Vec3::Z, 1e-6));
        assert!(close(d(1.0, 0.5), Vec3::Z, 1e-6));
        assert!(close(d(0.25, 0.5), Vec3::NEG_X, 1e-6));
        assert!(close(d(0.3, 0.0), Vec3::Y, 1e-6));
        assert!(close(d(0.3, 1.0), Vec3::NEG_Y, 1e-6));
        assert!(close(d(0.5, 0.25), Vec3::new(0.0, 1.0, -1.0).normalize(), 1e-6));
        // Looking at the image centre (-Z, up +Y), larger u is to the right.
        let right = Vec3::NEG_Z.cross(Vec3::Y);
        assert!((d(0.51, 0.5) - d(0.5, 0.5)).dot(right) > 0.0);
        // A step du is a rotation by -2 pi du about +Y (right-hand rule).
        for (u, v, du) in [(0.1, 0.3, 0.2), (0.7, 0.8, 0.05), (0.9, 0.5, 0.3)] {
            let turned = glam::Quat::from_rotation_y(-TAU * du) * d(u, v);
            assert!(close(turned, d(u + du, v), 1e-5));
        }
        // A rotation of r turns shows column u where column u + r was.
        let uv = Vec2::new(0.2, 0.4);
        assert!(close(uv_to_direction(uv, 0.25), d(0.45, 0.4), 1e-6));
        assert!(close(uv_to_direction(uv, -1.75), d(0.45, 0.4), 1e-5));
        let back = direction_to_uv(d(0.45, 0.4), 0.25);
        assert!((back - uv).abs().max_element() < 1e-6, "{back}");
    }

    /// uv -> direction -> uv and direction -> uv -> direction, with and
    /// without rotation, on random points.
    #[test]
    fn round_trips() {
        for i in 0..10_000 {
            let rotation = [0.0, 0.37, -2.6][i as usize % 3];
            let uv = Vec2::new(random_f32(1, 2 * i), random_f32(1, 2 * i + 1));
            let dir = uv_to_direction(uv, rotation);
            assert!((dir.length() - 1.0).abs() < 1e-6);
            let back = direction_to_uv(dir, rotation);
            let sin_theta = libm::sinf(PI * uv.y);
            // u is undetermined at the poles: its error grows as 1 / sin(theta).
            let du = (back.x - uv.x).abs();
            assert!(du.min(1.0 - du) * sin_theta < 2e-6, "{uv} -> {back}");
            assert!((back.y - uv.y).abs() < 2e-6, "{uv} -> {back}");
            // A random direction of any length.
            let z = 1.0 - 2.0 * random_f32(2, 2 * i);
            let phi = TAU * random_f32(2, 2 * i + 1);
            let r = libm::sqrtf(1.0 - z * z);
            let dir = Vec3::new(r * libm::cosf(phi), z, r * libm::sinf(phi));
            let back = uv_to_direction(direction_to_uv(3.0 * dir, rotation), rotation);
            assert!(close(back, dir, 2e-6), "{dir} -> {back}");
        }
    }

    #[test]
    fn solid_angles_sum_to_the_sphere() {
        for (width, height) in [(7, 5), (16, 8), (1, 1), (2048, 1024)] {
            let mut total = 0.0f64;
            for y in 0..height {
                let omega = texel_solid_angle(width, height, y);
                let (top, bottom) = (PI * y as f32 / height as f32, PI * (y + 1) as f32 / height as f32);
                let want = TAU / width as f32 * (libm::cosf(top) - libm::cosf(bottom));
                assert!(
                    (omega - want).abs() <= 1e-5 * want.max(1e-3),
                    "{width}x{height} row {y}"
                );
                total += omega as f64 * width as f64;
            }
            assert!(
                (total - 4.0 * core::f64::consts::PI).abs() < 1e-5,
                "{width}x{height}: {total}"
            );
        }
    }

    #[test]
    fn luminance_is_identical_to_luma() {
        for rgb in [Vec3::ONE, Vec3::new(0.3, 2.0, 7.5), Vec3::new(-0.1, 0.2, 1e5)] {
            assert_eq!(luminance(rgb), crate::luma(rgb));
        }
        assert_eq!(
            texel_weight(Vec3::ONE, 1, 3),
            luminance(Vec3::ONE) * row_sin_theta(1, 3)
        );
        assert!((row_sin_theta(1, 3) - 1.0).abs() < 1e-7);
    }

    /// At and near the poles: pdf 0 within MIN_SIN_THETA, finite outside,
    /// never NaN or infinite, for any input.
    #[test]
    fn poles_and_degenerate_directions_give_finite_pdfs() {
        let (width, height) = (8, 4);
        let mut rgb = vec![[1.0f32; 3]; 32];
        rgb[3] = [50.0, 50.0, 50.0]; // bright texel in the top row
        let mut table = vec![0.0; EnvironmentMap::table_len(width, height)];
        let map = EnvironmentMap::build(width, height, &rgb, &mut table).unwrap();
        for dir in [
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::ZERO,
            Vec3::NAN,
            Vec3::INFINITY,
            Vec3::splat(1e30),
        ] {
            assert_eq!(map.pdf(dir), 0.0, "{dir}");
        }
        for sin_theta in [2e-9f32, 1e-6, 1e-4, 0.1] {
            let dir = Vec3::new(sin_theta * 0.6, 1.0, sin_theta * 0.8);
            let pdf = map.pdf(dir);
            assert!(pdf > 0.0 && pdf.is_finite(), "sin {sin_theta}: {pdf}");
            assert!(map.pdf(dir * Vec3::new(1.0, -1.0, 1.0)).is_finite());
        }
        // u.y = 0 lands on the pole: pdf 0, direction +Y; the far end is finite.
        let s = map.sample(Vec2::new(0.3, 0.0));
        assert_eq!((s.pdf, s.direction.y), (0.0, 1.0));
        for u in [
            Vec2::ONE,
            Vec2::new(0.5, 0.999_999_9),
            Vec2::NAN,
            Vec2::splat(-3.0),
        ] {
            let s = map.sample(u);
            assert!(
                s.pdf.is_finite() && s.direction.is_finite() && s.pdf >= 0.0,
                "{u}: {s:?}"
            );
        }
    }

    #[test]
    fn bad_maps_are_errors() {
        let mut table = vec![0.0; EnvironmentMap::table_len(4, 2)];
        for rgb in [[f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 0.0], [0.0, -1.0, 0.0]] {
            let mut texels = [[0.5f32; 3]; 8];
            texels[6] = rgb;
            let e = EnvironmentMap::build(4, 2, &texels, &mut table).unwrap_err();
            let want = texel_weight(Vec3::from_array(rgb), 1, 2);
            assert_eq!(
                e,
                Error::Weight {
                    x: 2,
                    y: 1,
                    bits: want.to_bits()
                }
            );
        }
        // A negative channel with a positive luminance is accepted.
        let mut texels = [[0.5f32; 3]; 8];
        texels[1] = [-0.1, 1.0, 0.0];
        assert!(EnvironmentMap::build(4, 2, &texels, &mut table).is_ok());
        assert_eq!(
            EnvironmentMap::build(4, 2, &texels[..7], &mut table).unwrap_err(),
            Error::BufferSize {
                buffer: Buffer::EnvironmentTexels,
                expected: 8,
                actual: 7
            }
        );
        assert_eq!(
            EnvironmentMap::build(0, 2, &texels, &mut table).unwrap_err(),
            Error::DistributionSize { width: 0, height: 2 }
        );
        assert_eq!(
            EnvironmentMap::build(4, 2, &texels, &mut table[..10]).unwrap_err(),
            Error::BufferSize {
                buffer: Buffer::DistributionTable,
                expected: 11,
                actual: 10
            }
        );
    }

    /// The luminance integral is the texel sum of luminance times solid angle.
    #[test]
    fn luminance_integral_is_the_texel_sum() {
        let (width, height) = (13, 6);
        let rgb: Vec<[f32; 3]> = (0..78)
            .map(|i| [random_f32(4, 3 * i), random_f32(4, 3 * i + 1), 2.0])
            .collect();
        let mut table = vec![0.0; EnvironmentMap::table_len(width, height)];
        let map = EnvironmentMap::build(width, height, &rgb, &mut table).unwrap();
        let mut want = 0.0f64;
        for y in 0..height {
            for x in 0..width {
                let c = rgb[(y * width + x) as usize];
                want += luminance(Vec3::from_array(c)) as f64 * texel_solid_angle(width, height, y) as f64;
            }
        }
        assert!((map.luminance_integral() as f64 / want - 1.0).abs() < 1e-6);
        assert_eq!(
            map.params(),
            EnvironmentParams {
                width,
                height,
                rotation_turns: 0.0,
                reserved: 0
            }
        );
        assert_eq!(map.with_rotation_turns(0.5).params().rotation_turns, 0.5);
    }
}
