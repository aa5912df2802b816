//! Smooth shading normals: a triangle's three vertex normals
//! ([`TriangleAttrGpu::normal0`] ...) blended at a hit, for the path loop
//! ([`crate::trace`]) on the CPU and the GPU alike.
//!
//! At barycentrics `(u, v)` (the point `v0 + (v1 - v0) u + (v2 - v0) v`, as
//! `crate::intersect` reports hits) the smooth normal is
//! `normalize((1 - u - v) n0 + u n1 + v n2)`, negated when it points away
//! from the triangle's front normal (files whose normals disagree with
//! their winding still shade from the right side; for consistent data the
//! blend already faces the front). [`crate::normal_map::shading_normal`]
//! then takes it to the side the ray sees, exactly as it does the geometric
//! normal, tilts it by the normal map where there is one (the tangent frame
//! is built around it), and falls back to the geometric normal when the
//! result does not face the outgoing direction.
//!
//! Fall-backs, each giving the front normal itself (flat shading): a
//! triangle without vertex normals (all three zero, the host's encoding of
//! "none"), and a blend that is (nearly) zero, NaN or infinite (opposite
//! vertex normals, bad data that slipped past the host's checks).
//!
//! The geometric normal keeps every job that is about the surface itself:
//! ray offsets, emission facing, the light-side cosine, rejecting
//! directions below the surface, and the G-buffer.

use crate::abi::TriangleAttrGpu;
use glam::Vec3;

/// Smallest squared length of a blend normalised here; shorter ones (and
/// NaN or infinite ones) give the front normal. Far below what three unit
/// normals within a hemisphere can blend to (`1e-30` is about
/// `(1e-15)^2`), the same bound as `crate::normal_map`'s.
const MIN_LENGTH_SQUARED: f32 = 1e-30;

/// Whether the triangle carries vertex normals: any component of
/// [`TriangleAttrGpu::normal0`], `normal1`, `normal2` non-zero.
#[inline]
pub fn has_vertex_normals(attr: &TriangleAttrGpu) -> bool {
    let any = attr.normal0.abs() + attr.normal1.abs() + attr.normal2.abs();
    // `!(x == 0)` rather than `x != 0`: NaN counts as present (then the
    // blend's own check falls back).
    !(any.x == 0.0 && any.y == 0.0 && any.z == 0.0)
}

/// The unit smooth normal at barycentrics `(u, v)` of a triangle with
/// attributes `attr` and unit front normal `front` (`(v1 - v0) x (v2 - v0)`
/// normalised): the normalised blend of the vertex normals, on `front`'s
/// side (module docs). `front` itself, bit for bit, for a triangle without
/// vertex normals or a degenerate blend.
#[inline]
pub fn interpolated_normal(attr: &TriangleAttrGpu, u: f32, v: f32, front: Vec3) -> Vec3 {
    if !has_vertex_normals(attr) {
        return front;
    }
    let n =
        attr.normal0.truncate() * (1.0 - u - v) + attr.normal1.truncate() * u + attr.normal2.truncate() * v;
    let len2 = n.length_squared();
    if !(len2 > MIN_LENGTH_SQUARED && len2 <= f32::MAX) {
        return front;
    }
    let n = n * (1.0 / libm::sqrtf(len2));
    if n.dot(front) < 0.0 {
        -n
    } else {
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn attr(n: [Vec3; 3]) -> TriangleAttrGpu {
        TriangleAttrGpu {
            normal0: n[0].extend(0.0),
            normal1: n[1].extend(0.0),
            normal2: n[2].extend(0.0),
            ..Default::default()
        }
    }

    /// Three normals of a bent surface over the `z = 0` triangle.
    fn bent() -> [Vec3; 3] {
        [
            Vec3::new(-0.3, -0.2, 1.0).normalize(),
            Vec3::new(0.5, 0.0, 1.0).normalize(),
            Vec3::new(0.0, 0.4, 1.0).normalize(),
        ]
    }

    #[test]
    fn the_blend_is_the_normalised_barycentric_mix() {
        let n = bent();
        let a = attr(n);
        for (u, v) in [
            (0.0, 0.0),
            (1.0, 0.0),
            (0.0, 1.0),
            (0.25, 0.5),
            (1.0 / 3.0, 1.0 / 3.0),
            (0.7, 0.1),
        ] {
            let want = (n[0] * (1.0 - u - v) + n[1] * u + n[2] * v).normalize();
            let got = interpolated_normal(&a, u, v, Vec3::Z);
            assert!((got - want).length() < 1e-6, "({u}, {v}): {got} vs {want}");
            assert!((got.length() - 1.0).abs() < 1e-6);
        }
        // At a vertex: that vertex's normal.
        assert!((interpolated_normal(&a, 1.0, 0.0, Vec3::Z) - n[1]).length() < 1e-6);
        // Continuity: points on either side of the edge u + v = 1 agree.
        let (inside, edge) = (
            interpolated_normal(&a, 0.4999, 0.4999, Vec3::Z),
            interpolated_normal(&a, 0.5, 0.5, Vec3::Z),
        );
        assert!((inside - edge).length() < 1e-3);
    }

    #[test]
    fn the_blend_faces_the_front() {
        // Normals authored against the winding: the blend is negated.
        let n = bent().map(|v| -v);
        let got = interpolated_normal(&attr(n), 0.2, 0.3, Vec3::Z);
        assert!(got.z > 0.0, "{got}");
        let want = -(n[0] * 0.5 + n[1] * 0.2 + n[2] * 0.3).normalize();
        assert!((got - want).length() < 1e-6);
    }

    #[test]
    fn no_normals_and_degenerate_blends_are_the_front_normal_bit_for_bit() {
        let front = Vec3::new(0.3, -0.4, 0.5).normalize();
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        assert!(!has_vertex_normals(&TriangleAttrGpu::default()));
        assert_eq!(
            bits(interpolated_normal(&TriangleAttrGpu::default(), 0.2, 0.3, front)),
            bits(front)
        );
        // Opposite normals cancel at the midpoint of their edge.
        let cancel = attr([Vec3::X, -Vec3::X, Vec3::X]);
        assert_eq!(bits(interpolated_normal(&cancel, 0.5, 0.0, front)), bits(front));
        // NaN and infinite data.
        for bad in [f32::NAN, f32::INFINITY] {
            let a = attr([Vec3::splat(bad), Vec3::Z, Vec3::Z]);
            assert!(has_vertex_normals(&a));
            assert_eq!(
                bits(interpolated_normal(&a, 0.2, 0.3, front)),
                bits(front),
                "{bad}"
            );
        }
        // Only `w` set: still no normals.
        let w_only = TriangleAttrGpu {
            normal0: Vec4::W,
            ..Default::default()
        };
        assert!(!has_vertex_normals(&w_only));
    }
}
