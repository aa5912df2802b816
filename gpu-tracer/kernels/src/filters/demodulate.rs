//! Demodulation by the primary hit's albedo (SVGF): the filters smooth the
//! illumination `radiance / albedo`, and the result is multiplied back, so
//! texture detail is not blurred away and not mistaken for noise.

use glam::{Vec3, Vec4};

/// Albedo channels below this are treated as this value: a black texel
/// would otherwise divide by zero, and a near-black one amplify its noise
/// without bound. The same floor multiplies back, so a pixel round-trips.
pub const MIN_ALBEDO: f32 = 1.0 / 256.0;

/// `albedo` with each channel at least [`MIN_ALBEDO`] (NaN becomes the
/// floor too).
#[inline]
pub fn guarded_albedo(albedo: Vec3) -> Vec3 {
    Vec3::new(
        floor_albedo(albedo.x),
        floor_albedo(albedo.y),
        floor_albedo(albedo.z),
    )
}

#[inline]
fn floor_albedo(a: f32) -> f32 {
    // `a >= MIN_ALBEDO` is false for NaN.
    if a >= MIN_ALBEDO {
        a
    } else {
        MIN_ALBEDO
    }
}

/// `color / albedo` per channel (`w` kept), with [`guarded_albedo`].
#[inline]
pub fn demodulate(color: Vec4, albedo: Vec3) -> Vec4 {
    (color.truncate() / guarded_albedo(albedo)).extend(color.w)
}

/// `illumination * albedo` per channel (`w` kept): the inverse of
/// [`demodulate`] with the same guard.
#[inline]
pub fn remodulate(illumination: Vec4, albedo: Vec3) -> Vec4 {
    (illumination.truncate() * guarded_albedo(albedo)).extend(illumination.w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_guard() {
        let c = Vec4::new(0.5, 0.25, 2.0, 7.0);
        for albedo in [Vec3::new(0.5, 0.8, 0.1), Vec3::ZERO, Vec3::splat(f32::NAN)] {
            let d = demodulate(c, albedo);
            assert!(d.is_finite(), "{albedo}");
            let back = remodulate(d, albedo);
            assert!((back - c).abs().max_element() < 1e-6, "{albedo}: {back}");
        }
        assert_eq!(
            demodulate(c, Vec3::new(0.5, 0.5, 0.5)),
            Vec4::new(1.0, 0.5, 4.0, 7.0)
        );
    }
}
