//! Per-triangle tangents for normal maps in the kernels' form
//! (`kernels::abi::TriangleAttrGpu::tangent`): the tangent as coefficients
//! `(a, b)` of the edges, `t = a (v1 - v0) + b (v2 - v0)`, and the bitangent
//! sign. Edge coefficients stay right when animation moves the vertices
//! (`SceneGpu::set_positions` keeps them), and the kernel normalises and
//! orthogonalises `t` at the hit (`kernels::normal_map::tangent_frame`).
//!
//! - From texture coordinates (no `TANGENT` in the file): the standard
//!   `dp/du` solve. With `d1 = uv1 - uv0`, `d2 = uv2 - uv0` and `det = d1.u
//!   d2.v - d2.u d1.v`, `dp/du = (d2.v e1 - d1.v e2) / det`, so `(a, b) =
//!   (d2.v, -d1.v) / det`. The sign makes the bitangent point up the image
//!   (`-dp/dv`, glTF's `v` grows downwards, and its normal maps have `+y`
//!   up): `+1` when `det < 0` (the usual, unmirrored mapping), `-1` when
//!   `det > 0` (mirrored). Degenerate coordinates (`det` zero or not finite)
//!   give `(1, 0)` (along the first edge), sign `+1`.
//! - From an authored tangent ([`Triangle::tangent`], world space): the
//!   least-squares `(a, b)` with `a e1 + b e2` closest to it (its in-plane
//!   part), its sign as given; a tangent without in-plane part (or not
//!   finite) falls back to the texture coordinates' direction with the
//!   authored sign.
//!
//! Coefficients are computed in f64 and scaled so the larger is 1 in
//! magnitude (only the direction matters), so they never overflow f32.

use super::Triangle;
use glam::{DVec2, DVec3, Vec2, Vec4};

/// [`kernels::abi::TriangleAttrGpu::tangent`] of `t` (module docs): `x`, `y`
/// edge coefficients (the larger is `±1`), `z` = `±1` sign, `w` = 0.
pub(super) fn tangent_gpu(t: &Triangle) -> Vec4 {
    let (uv_ab, uv_sign) = from_uvs(t.uvs);
    let Some(authored) = t.tangent else {
        return pack(uv_ab, uv_sign);
    };
    let sign = if authored.w < 0.0 { -1.0 } else { 1.0 };
    let [v0, v1, v2] = t.vertices.map(|v| v.as_dvec3());
    let (e1, e2) = (v1 - v0, v2 - v0);
    let r = authored.truncate().as_dvec3();
    match in_plane(e1, e2, r) {
        Some(ab) => pack(ab, sign),
        None => pack(uv_ab, sign),
    }
}

/// `(a, b)` of `dp/du` and the bitangent sign from texture coordinates
/// (module docs).
fn from_uvs(uvs: [Vec2; 3]) -> (DVec2, f32) {
    let [u0, u1, u2] = uvs.map(|u| u.as_dvec2());
    let (d1, d2) = (u1 - u0, u2 - u0);
    let det = d1.x * d2.y - d2.x * d1.y;
    if det != 0.0 && det.is_finite() {
        let ab = DVec2::new(d2.y, -d1.y) / det;
        if ab.is_finite() && ab != DVec2::ZERO {
            return (ab, if det < 0.0 { 1.0 } else { -1.0 });
        }
    }
    (DVec2::X, 1.0)
}

/// The least-squares `(a, b)` of `a e1 + b e2 ~ r` (the normal equations of
/// the 2x2 Gram matrix), `None` when the triangle is degenerate, `r` has no
/// in-plane part, or anything is not finite.
fn in_plane(e1: DVec3, e2: DVec3, r: DVec3) -> Option<DVec2> {
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    let (r1, r2) = (e1.dot(r), e2.dot(r));
    let ab = DVec2::new(g22 * r1 - g12 * r2, g11 * r2 - g12 * r1) / det;
    (det > 0.0 && ab.is_finite() && ab != DVec2::ZERO).then_some(ab)
}

/// The GPU word: `ab` scaled so the larger magnitude is 1, and `sign`.
fn pack(ab: DVec2, sign: f32) -> Vec4 {
    let ab = ab / ab.abs().max_element();
    Vec4::new(ab.x as f32, ab.y as f32, sign, 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// The glTF quad's lower-left triangle: `+x` right, `+y` up, front `+z`,
    /// uvs with `v` down.
    fn quad() -> Triangle {
        Triangle {
            uvs: [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)],
            ..Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], 0)
        }
    }

    /// World tangent and bitangent the kernel would build from `w`.
    fn frame(t: &Triangle, w: Vec4) -> (Vec3, Vec3) {
        let [v0, v1, v2] = t.vertices;
        let n = (v1 - v0).cross(v2 - v0).normalize();
        kernels::normal_map::tangent_frame(v1 - v0, v2 - v0, n, w)
    }

    #[test]
    fn uv_tangents_point_along_u_with_the_bitangent_up_the_image() {
        let t = quad();
        assert_eq!(tangent_gpu(&t), Vec4::new(1.0, 0.0, 1.0, 0.0));
        assert_eq!(frame(&t, tangent_gpu(&t)), (Vec3::X, Vec3::Y));
        // Mirrored in u: the tangent turns, the bitangent stays up (sign -1).
        let mirrored = Triangle {
            uvs: t.uvs.map(|uv| Vec2::new(1.0 - uv.x, uv.y)),
            ..t
        };
        let w = tangent_gpu(&mirrored);
        assert_eq!(w.z, -1.0);
        assert_eq!(frame(&mirrored, w), (-Vec3::X, Vec3::Y));
        // Rotated mapping on a scaled, moved triangle: u along the second
        // edge; the image's up (-dp/dv) along the first.
        let rotated = Triangle {
            vertices: [
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(3.0, 2.0, 3.0),
                Vec3::new(1.0, 4.0, 3.0),
            ],
            uvs: [Vec2::ZERO, Vec2::new(0.0, -1.0), Vec2::new(1.0, 0.0)],
            ..t
        };
        let (tx, by) = frame(&rotated, tangent_gpu(&rotated));
        assert!(
            (tx - Vec3::Y).length() < 1e-6 && (by - Vec3::X).length() < 1e-6,
            "{tx} {by}"
        );
        // Degenerate coordinates: along the first edge, sign +1.
        let flat = Triangle {
            uvs: [Vec2::ZERO; 3],
            ..t
        };
        assert_eq!(tangent_gpu(&flat), Vec4::new(1.0, 0.0, 1.0, 0.0));
        // Tiny determinants do not overflow.
        let tiny = Triangle {
            uvs: [Vec2::ZERO, Vec2::new(1e-30, 0.0), Vec2::new(0.0, -1e-30)],
            ..t
        };
        assert_eq!(tangent_gpu(&tiny), Vec4::new(1.0, 0.0, 1.0, 0.0));
    }

    #[test]
    fn authored_tangents_keep_their_in_plane_direction_and_sign() {
        let t = Triangle {
            tangent: Some(Vec4::new(1.0, 1.0, 0.5, -1.0)),
            ..quad()
        };
        let w = tangent_gpu(&t);
        assert_eq!(w, Vec4::new(1.0, 1.0, -1.0, 0.0));
        let (tx, by) = frame(&t, w);
        let d = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!((tx - d).length() < 1e-6 && (by + Vec3::Z.cross(d)).length() < 1e-6);
        // No in-plane part, or NaN: the texture coordinates' direction,
        // the authored sign.
        for bad in [
            Vec4::new(0.0, 0.0, 1.0, -1.0),
            Vec4::new(f32::NAN, 0.0, 0.0, -1.0),
        ] {
            let t = Triangle {
                tangent: Some(bad),
                ..quad()
            };
            assert_eq!(tangent_gpu(&t), Vec4::new(1.0, 0.0, -1.0, 0.0), "{bad}");
        }
    }
}
