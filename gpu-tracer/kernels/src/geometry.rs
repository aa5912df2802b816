//! Triangle geometry the tracer and the light sampler share: normals and
//! areas, and how far a new ray starts from the surface it leaves.

use glam::Vec3;

/// Relative offset of ray origins from surfaces, against self-intersection:
/// a new ray starts `RAY_OFFSET * (1 + max |p_i|)` away from the surface
/// point `p` along the normal facing the new direction. f32 rounding of hit
/// points is about `1e-7` relative; 5e-5 leaves a wide margin while staying
/// below 0.03 units in a 555-unit Cornell box.
pub const RAY_OFFSET: f32 = 5e-5;

/// Unit geometric normal `(v1 - v0) x (v2 - v0)` (front side) and area of a
/// triangle; a zero-area triangle gives a zero normal and area 0.
#[inline]
pub fn normal_and_area(v0: Vec3, v1: Vec3, v2: Vec3) -> (Vec3, f32) {
    let c = (v1 - v0).cross(v2 - v0);
    let len = c.length();
    if len > 0.0 {
        (c / len, 0.5 * len)
    } else {
        (Vec3::ZERO, 0.0)
    }
}

/// Distance by which rays leave a surface at `p`: `RAY_OFFSET * (1 + max |p_i|)`.
#[inline]
pub fn surface_offset(p: Vec3) -> f32 {
    RAY_OFFSET * (1.0 + p.abs().max_element())
}

/// `p` moved off its surface along the unit `normal`.
#[inline]
pub fn offset_point(p: Vec3, normal: Vec3) -> Vec3 {
    p + normal * surface_offset(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_normal_and_area() {
        let (n, a) = normal_and_area(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0));
        assert_eq!((n, a), (Vec3::Z, 3.0));
        assert_eq!(
            normal_and_area(Vec3::ZERO, Vec3::X, Vec3::X * 2.0),
            (Vec3::ZERO, 0.0)
        );
    }
}
