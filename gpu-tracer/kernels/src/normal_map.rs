//! Normal maps (glTF `normalTexture`): a triangle's tangent frame and the
//! shading normal a texel gives in it, for the path loop ([`crate::trace`])
//! on the CPU and the GPU alike.
//!
//! # Tangent frame
//!
//! Built around the smooth normal where the triangle has vertex normals
//! (`crate::vertex_normal`), around the flat front normal otherwise. The
//! host
//! stores the tangent in [`TriangleAttrGpu::tangent`] as a combination of
//! the triangle's edges `e1 = v1 - v0`, `e2 = v2 - v0`: from the file's
//! `TANGENT` attribute when it has one, otherwise the standard `dp/du`
//! solve on the texture coordinates (the host's `scene::tangent` module).
//! Storing edge coefficients rather than a world vector keeps the frame
//! right when animation moves the vertices (an affine map carries edges and
//! their combinations alike). [`tangent_frame`] projects it onto the plane
//! (Gram-Schmidt against the front normal `n`), normalises it, and takes
//! the bitangent `b = sign * (n x t)` (glTF's `bitangent = cross(normal,
//! tangent.xyz) * tangent.w`); a degenerate tangent becomes
//! [`Frame::from_normal`]'s.
//!
//! # Shading normal
//!
//! glTF: `n_s = normalize(t (2r - 1) s + b (2g - 1) s + n (2b - 1))` with
//! the texel `(r, g, b)` read as linear data ([`TEXEL_LINEAR`]) and `s` the
//! texture's `scale`. Surfaces are two-sided: `n` here is the base normal
//! (the smooth normal, or the geometric one without vertex normals) on the
//! side facing the incoming ray, so a surface seen from behind uses the
//! same tangent-plane tilt about the flipped normal. Without a normal map
//! the shading normal is that base normal itself.
//!
//! Guard: a shading normal (smooth, normal-mapped or both) must face the
//! outgoing direction `wo` (`n_s . wo > 0`), or the BSDF frame would put
//! `wo` below its horizon. Where it does not (or the texel gives no
//! direction at all, or anything is NaN), [`shading_normal`] falls back to
//! the geometric normal (chosen over bending `n_s` towards it: no extra
//! parameter, never NaN, and it only happens at grazing views of strong
//! tilts, or near the silhouettes of smooth meshes).
//!
//! The integrator uses `n_s` for the BSDF (evaluation, sampling, the cosine
//! of next-event estimation) and keeps the geometric normal for ray
//! offsets, emission facing, the light-side cosine, and to reject light
//! directions and continuations below the geometric surface.

use crate::abi::{MaterialGpu, TriangleAttrGpu, TEXEL_LINEAR, TEXTURE_NONE};
use crate::sampling::Frame;
use crate::surface::texture_uv;
use crate::texture::sample_image;
use crate::trace_variant::{FULL, SHADING, TEXTURES};
use crate::vertex_normal::{has_vertex_normals, interpolated_normal};
use glam::{Vec2, Vec3, Vec4};

/// Smallest squared length of a vector normalised here; shorter ones (and
/// NaN or infinite ones) take a fallback. Far below any tangent or normal a
/// valid triangle or texel gives (`1e-30` is about `(1e-15)^2`).
const MIN_LENGTH_SQUARED: f32 = 1e-30;

/// Unit tangent and bitangent of a triangle with edges `e1 = v1 - v0`, `e2 =
/// v2 - v0`, unit front normal `front` (`e1 x e2` normalised) and stored
/// tangent `tangent` ([`TriangleAttrGpu::tangent`]): `t` = the in-plane
/// part of `tangent.x e1 + tangent.y e2`, normalised (or
/// [`Frame::from_normal`]'s tangent when that is degenerate), `b = s (front
/// x t)` with `s = -1` when `tangent.z < 0`, `+1` otherwise. Both are unit
/// and orthogonal to `front`.
#[inline]
pub fn tangent_frame(e1: Vec3, e2: Vec3, front: Vec3, tangent: Vec4) -> (Vec3, Vec3) {
    let raw = e1 * tangent.x + e2 * tangent.y;
    let t = raw - front * front.dot(raw);
    let len2 = t.length_squared();
    let t = if len2 > MIN_LENGTH_SQUARED && len2 <= f32::MAX {
        t * (1.0 / libm::sqrtf(len2))
    } else {
        Frame::from_normal(front).tangent
    };
    let sign = if tangent.z < 0.0 { -1.0 } else { 1.0 };
    (t, front.cross(t) * sign)
}

/// The (unnormalised) glTF normal-map direction
/// `t (2r - 1) scale + b (2g - 1) scale + n (2b - 1)` of the linear texel
/// `texel` (each channel in `[0, 1]`) in the frame `(t, b, n)`.
#[inline]
pub fn texel_normal(t: Vec3, b: Vec3, n: Vec3, texel: Vec3, scale: f32) -> Vec3 {
    let c = texel * 2.0 - Vec3::ONE;
    t * (c.x * scale) + b * (c.y * scale) + n * c.z
}

/// The unit shading normal at a hit of a triangle with attributes `attr`,
/// edges `e1`, `e2` and unit front normal `front`, at texture coordinates
/// `uv` (the surface's, before any texture transform), seen from the unit
/// outgoing direction `wo`; `facing` is the unit geometric normal facing
/// `wo` (`front` or `-front`), and `bary` the hit's barycentrics `(u, v)`.
///
/// The base normal: without vertex normals `facing` itself; with them the
/// smooth normal `s` at `bary`
/// ([`interpolated_normal`], on the front's side) taken to `facing`'s
/// side (negated when `facing . front < 0`). Without a normal texture
/// (`material.normal.x` = [`TEXTURE_NONE`]) the result is the base normal,
/// or `facing` when that does not face `wo`; for a triangle without vertex
/// normals that is `facing` itself, bit for bit. With one, the normalised
/// [`texel_normal`] of the texture's texel in the frame (`t`, `b`, base)
/// of [`tangent_frame`] around `s` (`front` without vertex normals), or
/// `facing` when that is degenerate, not finite or does not face `wo`
/// (module docs).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn shading_normal(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
    attr: &TriangleAttrGpu,
    edges: (Vec3, Vec3),
    front: Vec3,
    facing: Vec3,
    bary: Vec2,
    wo: Vec3,
) -> Vec3 {
    shading_normal_variant::<FULL>(
        material,
        images,
        image_count,
        uv,
        attr,
        edges,
        front,
        facing,
        bary,
        wo,
    )
}

/// [`shading_normal`] for the trace variant of `FEATURES`
/// ([`crate::trace_variant`]): without [`TEXTURES`] no normal map is read,
/// without [`SHADING`] no vertex normals; `facing` itself without either.
/// The same normal, bit for bit, for a triangle and material the variant
/// fits.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn shading_normal_variant<const FEATURES: u32>(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
    attr: &TriangleAttrGpu,
    edges: (Vec3, Vec3),
    front: Vec3,
    facing: Vec3,
    bary: Vec2,
    wo: Vec3,
) -> Vec3 {
    if FEATURES == 0 {
        return facing;
    }
    let (smooth, base) = if FEATURES & SHADING != 0 && has_vertex_normals(attr) {
        let s = interpolated_normal(attr, bary.x, bary.y, front);
        (s, if facing.dot(front) < 0.0 { -s } else { s })
    } else {
        (front, facing)
    };
    let m = material.normal;
    if FEATURES & TEXTURES == 0 || m.x == TEXTURE_NONE {
        return if base.dot(wo) > 0.0 { base } else { facing };
    }
    let uv = texture_uv(m.y, &material.normal_uv, uv);
    let texel = sample_image(images, image_count, m.x, m.y | TEXEL_LINEAR, uv);
    let (t, b) = tangent_frame(edges.0, edges.1, smooth, attr.tangent);
    let n = texel_normal(t, b, base, texel, material.pbr.z);
    let len2 = n.length_squared();
    if len2 > MIN_LENGTH_SQUARED && len2 <= f32::MAX {
        let n = n * (1.0 / libm::sqrtf(len2));
        if n.dot(wo) > 0.0 {
            return n;
        }
    }
    facing
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::abi::UvTransformGpu;
    use glam::UVec4;

    /// The glTF quad: `v0 = (0, 0, 0)`, `v1 = (1, 0, 0)`, `v2 = (0, 1, 0)`
    /// with uvs `(0, 1)`, `(1, 1)`, `(0, 0)` (v down): `dp/du = +x`, the
    /// image's up (`-dp/dv`) is `+y`, and the front normal `+z`. The host's
    /// `dp/du` solve gives edge coefficients `(1, 0)`, sign +1.
    fn quad() -> (Vec3, Vec3, Vec3) {
        (Vec3::X, Vec3::Y, Vec3::Z)
    }

    #[test]
    fn tangent_frame_follows_the_edges_and_the_sign() {
        let (e1, e2, n) = quad();
        let (t, b) = tangent_frame(e1, e2, n, Vec4::new(1.0, 0.0, 1.0, 0.0));
        assert_eq!((t, b), (Vec3::X, Vec3::Y));
        // Handedness -1 flips the bitangent only.
        let (t, b) = tangent_frame(e1, e2, n, Vec4::new(1.0, 0.0, -1.0, 0.0));
        assert_eq!((t, b), (Vec3::X, -Vec3::Y));
        // A combination of both edges: 2 e1 + 2 e2 -> (1, 1, 0) / sqrt 2.
        let (t, b) = tangent_frame(e1, e2, n, Vec4::new(2.0, 2.0, 1.0, 0.0));
        let d = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert!((t - d).length() < 1e-6 && (b - n.cross(d)).length() < 1e-6);
        // Degenerate (the zero default, NaN): any unit tangent in the plane.
        for tangent in [Vec4::ZERO, Vec4::splat(f32::NAN)] {
            let (t, b) = tangent_frame(e1, e2, n, tangent);
            assert!(
                (t.length() - 1.0).abs() < 1e-6 && t.dot(n).abs() < 1e-6,
                "{tangent}"
            );
            assert!((b.length() - 1.0).abs() < 1e-6 && b.dot(n).abs() < 1e-6 && b.dot(t).abs() < 1e-6);
        }
        // A tilted triangle: the frame is orthonormal around its normal.
        let (e1, e2) = (Vec3::new(1.0, 0.2, -0.3), Vec3::new(0.1, 0.9, 0.4));
        let n = e1.cross(e2).normalize();
        let (t, b) = tangent_frame(e1, e2, n, Vec4::new(0.7, -0.2, -1.0, 0.0));
        assert!(t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6 && t.dot(b).abs() < 1e-6);
        assert!((t.cross(b) + n).length() < 1e-5, "left-handed with sign -1");
    }

    /// A one-texel normal texture over the quad of [`quad`].
    fn mapped(texel: [u8; 3], scale: f32, tangent_sign: f32) -> (MaterialGpu, [u32; 5], TriangleAttrGpu) {
        let mut m = MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO);
        m.normal = UVec4::new(0, 0, 0, 0);
        m.pbr.z = scale;
        let [r, g, b] = texel.map(u32::from);
        let images = [4, 1, 1, 0, r | g << 8 | b << 16 | 255 << 24];
        let attr = TriangleAttrGpu {
            tangent: Vec4::new(1.0, 0.0, tangent_sign, 0.0),
            ..Default::default()
        };
        (m, images, attr)
    }

    fn normal_of(texel: [u8; 3], scale: f32, sign: f32, wo: Vec3, back: bool) -> Vec3 {
        let (m, images, attr) = mapped(texel, scale, sign);
        let (e1, e2, n) = quad();
        let facing = if back { -n } else { n };
        shading_normal(
            &m,
            &images,
            1,
            Vec2::splat(0.5),
            &attr,
            (e1, e2),
            n,
            facing,
            Vec2::ZERO,
            wo,
        )
    }

    #[test]
    fn known_texels_give_the_expected_world_normal() {
        let up = Vec3::Z;
        // Flat (128, 128, 255): +z within the 8-bit offset (1/255 of a unit).
        let n = normal_of([128, 128, 255], 1.0, 1.0, up, false);
        assert!((n - Vec3::Z).length() < 0.01, "{n}");
        // Tilted 45 degrees towards +x (tangent): texel (1, 0.5, 1) -> (1, ~0, 1).
        let n = normal_of([255, 128, 255], 1.0, 1.0, up, false);
        let d = Vec3::new(1.0, 0.0, 1.0).normalize();
        assert!((n - d).length() < 0.01, "{n}");
        // Towards +y (bitangent, image up) with sign +1, -y with sign -1.
        let n = normal_of([128, 255, 255], 1.0, 1.0, up, false);
        assert!((n - Vec3::new(0.0, 1.0, 1.0).normalize()).length() < 0.01, "{n}");
        let n = normal_of([128, 255, 255], 1.0, -1.0, up, false);
        assert!((n - Vec3::new(0.0, -1.0, 1.0).normalize()).length() < 0.01, "{n}");
        // Scale multiplies the tangent-plane part only: 0 gives the normal.
        let n = normal_of([255, 0, 255], 0.0, 1.0, up, false);
        assert_eq!(n, Vec3::Z);
        // Seen from behind: the same tilt about the flipped normal.
        let n = normal_of([255, 128, 255], 1.0, 1.0, -up, true);
        assert!((n - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 0.01, "{n}");
    }

    #[test]
    fn shading_normals_never_face_away_and_never_nan() {
        // Tilted 45 degrees to +x, seen from 60 degrees on the -x side:
        // n_s . wo < 0, so the geometric normal is used.
        let wo = Vec3::new(-(60f32.to_radians().sin()), 0.0, 60f32.to_radians().cos());
        assert_eq!(normal_of([255, 128, 255], 1.0, 1.0, wo, false), Vec3::Z);
        // A texel pointing into the surface.
        assert_eq!(normal_of([128, 128, 0], 1.0, 1.0, Vec3::Z, false), Vec3::Z);
        // NaN and infinite scales.
        for s in [f32::NAN, f32::INFINITY] {
            assert_eq!(normal_of([255, 128, 255], s, 1.0, Vec3::Z, false), Vec3::Z, "{s}");
        }
    }

    #[test]
    fn no_normal_texture_is_the_facing_normal_bit_for_bit() {
        let m = MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO);
        let facing = Vec3::new(0.3, -0.4, 0.5).normalize();
        let n = shading_normal(
            &m,
            &[0],
            0,
            Vec2::ZERO,
            &TriangleAttrGpu::default(),
            (Vec3::X, Vec3::Y),
            Vec3::Z,
            facing,
            Vec2::ZERO,
            Vec3::Z,
        );
        assert_eq!(
            n.to_array().map(f32::to_bits),
            facing.to_array().map(f32::to_bits)
        );
    }

    /// Vertex normals all tilted 30 degrees towards +x over the quad.
    fn smooth_attr(tangent_sign: f32) -> (TriangleAttrGpu, Vec3) {
        let tilt = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
        let attr = TriangleAttrGpu {
            tangent: Vec4::new(1.0, 0.0, tangent_sign, 0.0),
            normal0: tilt.extend(0.0),
            normal1: tilt.extend(0.0),
            normal2: tilt.extend(0.0),
            ..Default::default()
        };
        (attr, tilt)
    }

    /// Without a normal map the shading normal is the smooth normal on the
    /// side facing `wo` (negated from behind), and the geometric one where
    /// the smooth normal turns away from `wo`.
    #[test]
    fn vertex_normals_make_the_shading_normal() {
        let (attr, tilt) = smooth_attr(1.0);
        let m = MaterialGpu::untextured(Vec4::ONE, Vec4::ZERO);
        let (e1, e2, n) = quad();
        let at = |facing: Vec3, wo: Vec3| {
            shading_normal(
                &m,
                &[0],
                0,
                Vec2::ZERO,
                &attr,
                (e1, e2),
                n,
                facing,
                Vec2::new(0.2, 0.3),
                wo,
            )
        };
        assert!((at(n, Vec3::Z) - tilt).length() < 1e-6);
        assert!((at(-n, -Vec3::Z) + tilt).length() < 1e-6);
        // Seen from 70 degrees on the -x side: the tilted normal faces away.
        let wo = Vec3::new(-(70f32.to_radians().sin()), 0.0, 70f32.to_radians().cos());
        assert_eq!(at(n, wo), n);
    }

    /// With a normal map the tangent frame is built around the smooth
    /// normal: a flat texel gives the smooth normal, a tilted one tilts it.
    #[test]
    fn normal_maps_perturb_the_smooth_normal() {
        let (smooth, tilt) = smooth_attr(1.0);
        let (e1, e2, n) = quad();
        let bary = Vec2::new(0.2, 0.3);
        let normal_for_texel = |texel: [u8; 3]| {
            let (m, images, _) = mapped(texel, 1.0, 1.0);
            shading_normal(
                &m,
                &images,
                1,
                Vec2::splat(0.5),
                &smooth,
                (e1, e2),
                n,
                n,
                bary,
                Vec3::Z,
            )
        };
        let got = normal_for_texel([128, 128, 255]);
        assert!((got - tilt).length() < 0.01, "{got}");
        // Texel (1, 0.5, 1): 45 degrees further about the tangent, which is
        // +x projected onto the smooth normal's plane.
        let got = normal_for_texel([255, 128, 255]);
        let t = (Vec3::X - tilt * tilt.x).normalize();
        let want = (t + tilt).normalize();
        assert!((got - want).length() < 0.01, "{got} vs {want}");
        assert!(got.dot(t) > 0.0 && got.dot(tilt) > 0.0);
    }

    #[test]
    fn the_texture_transform_moves_the_lookup() {
        // A 2x1 image: left texel flat, right texel tilted to +x; the
        // transform u' = u + 0.5 moves uv (0.25, 0.5) onto the right texel.
        let (mut m, _, attr) = mapped([0, 0, 0], 1.0, 1.0);
        let images = [
            4u32,
            2,
            1,
            0,
            128 | 128 << 8 | 255 << 16,
            255 | 128 << 8 | 255 << 16,
        ];
        let (e1, e2, n) = quad();
        let at = |m: &MaterialGpu| {
            shading_normal(
                m,
                &images,
                1,
                Vec2::new(0.25, 0.5),
                &attr,
                (e1, e2),
                n,
                n,
                Vec2::ZERO,
                n,
            )
        };
        assert!((at(&m) - Vec3::Z).length() < 0.01);
        m.normal.y = crate::abi::UV_TRANSFORM;
        m.normal_uv = UvTransformGpu {
            u: Vec4::new(1.0, 0.0, 0.5, 0.0),
            ..UvTransformGpu::IDENTITY
        };
        assert!((at(&m) - Vec3::new(1.0, 0.0, 1.0).normalize()).length() < 0.01);
    }
}
