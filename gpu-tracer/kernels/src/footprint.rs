//! The texture footprint of a pixel at a camera ray's first hit: where the
//! pixel's centre ray meets the hit triangle's plane (its texture
//! coordinates) and how wide the pixel is there in texture space, from a
//! ray cone (Akenine-Möller et al. 2019, "Texture Level of Detail
//! Strategies for Real-Time Ray Tracing", Ray Tracing Gems ch. 20).
//!
//! Textures at the first hit are then looked up at the centre's
//! coordinates, filtered over that width ([`crate::texture_filter`]), so
//! every sample of a pixel reads the same texture value, the pixel's
//! average: the texture's detail stops adding noise to the pixel's
//! estimate (a pixel straddling a texel edge no longer flickers between
//! the texels as its jitter moves), and the image is the texture filtered
//! by the pixel, as a rasteriser's mip-mapped lookup would give.
//!
//! Later vertices use a coarser rule ([`cone_footprint`]): the path carries
//! a ray cone whose spread grows at every bounce by the BSDF's
//! [`bounce_spread`] (a wide cone after a diffuse bounce, a narrow one
//! after a sharp glossy one), and a hit reads its textures, at its own
//! point, filtered over the cone's width there. So indirect light sees
//! textures filtered as wide as the bounce that found them spreads (a
//! diffusely reflected checker reads about its mean), which removes the
//! noise of texel edges from indirect light at the cost of a small bias
//! (detail of textures seen only through diffuse bounces is blurred);
//! mirror-like reflections keep their detail.
//!
//! # The cone
//!
//! A pixel subtends `2 tan(fov_y / 2) / height` radians; at distance `t`
//! along the centre ray its cone is `w = t * 2 tan(fov_y / 2) / height`
//! wide. On a surface at angle `theta` to the ray it stretches to `w / |cos
//! theta|` (the footprint's long axis, as the paper's level of detail
//! uses), and the triangle maps world lengths to texture lengths by
//! `sqrt(uv area / world area)`, so the footprint's side in texture
//! coordinates is `w / |cos theta| * sqrt(A_uv / A_world)`.

use crate::abi::{TraceParams, TriangleAttrGpu};
use crate::camera::primary_ray;
use crate::surface::triangle_uv;
use glam::{UVec2, Vec2, Vec3};

/// Smallest `|cos theta|` the footprint divides by: at grazing angles the
/// footprint is capped at 20 times the cone's width.
pub const MIN_FOOTPRINT_COS: f32 = 0.05;

/// Spread (radians, full angle) a diffuse bounce adds to a path's ray cone:
/// 0.5, a cone of about 29 degrees, much narrower than the cosine lobe
/// (whose directions spread over the hemisphere) and wide enough that a
/// texture seen through a diffuse bounce reads a level a few octaves
/// coarser than its texels at room scale.
pub const DIFFUSE_CONE_SPREAD: f32 = 0.5;

/// Spread a bounce adds to the ray cone: [`DIFFUSE_CONE_SPREAD`] for a
/// Lambertian surface; for a metallic-roughness one `2 alpha` (alpha =
/// roughness^2, the GGX lobe's width), at most [`DIFFUSE_CONE_SPREAD`].
#[inline]
pub fn bounce_spread(glossy: bool, alpha: f32) -> f32 {
    if glossy {
        (2.0 * alpha).min(DIFFUSE_CONE_SPREAD)
    } else {
        DIFFUSE_CONE_SPREAD
    }
}

/// The footprint's side in texture coordinates of a ray cone `width` world
/// units wide at a hit on the triangle `(v0, v1, v2)` with texture
/// coordinates `attr`, seen along the unit direction `dir`: `width / |cos|
/// times sqrt(A_uv / A_world)` (module docs); 0 for a triangle without
/// texture or world area.
#[inline]
pub fn cone_footprint(
    width: f32,
    dir: Vec3,
    (v0, v1, v2): (Vec3, Vec3, Vec3),
    attr: &TriangleAttrGpu,
) -> f32 {
    let n = (v1 - v0).cross(v2 - v0);
    let world_area2 = n.length();
    let uv_area2 = uv_area2(attr);
    if world_area2 <= 0.0 || uv_area2 <= 0.0 || uv_area2.is_nan() {
        return 0.0;
    }
    let cos = (libm::fabsf(n.dot(dir)) / world_area2).max(MIN_FOOTPRINT_COS);
    width / cos * libm::sqrtf(uv_area2 / world_area2)
}

/// Twice the triangle's area in texture space.
#[inline]
fn uv_area2(attr: &TriangleAttrGpu) -> f32 {
    let (uv0, uv1, uv2) = (
        triangle_uv(attr, 0.0, 0.0),
        triangle_uv(attr, 1.0, 0.0),
        triangle_uv(attr, 0.0, 1.0),
    );
    let (a, b) = (uv1 - uv0, uv2 - uv0);
    libm::fabsf(a.x * b.y - a.y * b.x)
}

/// The spread (radians) of a camera pixel's ray cone: `2 tan(fov_y / 2) /
/// height`.
#[inline]
pub fn pixel_spread(params: &TraceParams) -> f32 {
    2.0 * params.tan_half_fov_y / params.height.max(1) as f32
}

/// Texture coordinates of pixel `pixel`'s centre ray on the plane of the
/// triangle `(v0, v1, v2)` (world units) with texture coordinates `attr`,
/// and the footprint's side in texture coordinates (module docs). Returns
/// `(hit_uv, 0)` (a point lookup at the jittered hit) when the centre ray
/// misses the plane, meets it behind the camera or more than 4 times nearer
/// or farther than the hit at `hit_t`, or when the triangle has no texture
/// area.
#[inline]
pub fn primary_footprint(
    params: &TraceParams,
    pixel: UVec2,
    (v0, v1, v2): (Vec3, Vec3, Vec3),
    attr: &TriangleAttrGpu,
    hit_uv: Vec2,
    hit_t: f32,
) -> (Vec2, f32) {
    let centre = primary_ray(params, pixel.x, pixel.y, Vec2::splat(0.5));
    let (e1, e2) = (v1 - v0, v2 - v0);
    let n = e1.cross(e2);
    let world_area2 = n.length();
    let denom = n.dot(centre.dir);
    if world_area2 <= 0.0 || denom == 0.0 {
        return (hit_uv, 0.0);
    }
    let t = n.dot(v0 - centre.origin) / denom;
    if !(t > 0.25 * hit_t && t < 4.0 * hit_t) {
        return (hit_uv, 0.0);
    }
    // Barycentrics of the plane point (extrapolated outside the triangle).
    let p = centre.origin + centre.dir * t - v0;
    let (d00, d01, d11) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d20, d21) = (p.dot(e1), p.dot(e2));
    let det = d00 * d11 - d01 * d01;
    if det <= 0.0 {
        return (hit_uv, 0.0);
    }
    let b1 = (d11 * d20 - d01 * d21) / det;
    let b2 = (d00 * d21 - d01 * d20) / det;
    let uv = triangle_uv(attr, b1, b2);
    let (uv0, uv1, uv2) = (
        triangle_uv(attr, 0.0, 0.0),
        triangle_uv(attr, 1.0, 0.0),
        triangle_uv(attr, 0.0, 1.0),
    );
    let (a, b) = (uv1 - uv0, uv2 - uv0);
    let uv_area2 = libm::fabsf(a.x * b.y - a.y * b.x);
    if uv_area2 <= 0.0 || uv_area2.is_nan() {
        return (hit_uv, 0.0);
    }
    let cone = t * 2.0 * params.tan_half_fov_y / params.height.max(1) as f32;
    let cos = (libm::fabsf(denom) / world_area2).max(MIN_FOOTPRINT_COS);
    (uv, cone / cos * libm::sqrtf(uv_area2 / world_area2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// Half of a 4 x 4 square at z = 0 facing +z, its texture 0..1 over it.
    fn square() -> ((Vec3, Vec3, Vec3), TriangleAttrGpu) {
        let tri = (
            Vec3::new(-2.0, -2.0, 0.0),
            Vec3::new(2.0, -2.0, 0.0),
            Vec3::new(-2.0, 2.0, 0.0),
        );
        let attr = TriangleAttrGpu {
            uv01: Vec4::new(0.0, 1.0, 1.0, 1.0),
            uv2: Vec4::new(0.0, 0.0, 0.0, 0.0),
            ..Default::default()
        };
        (tri, attr)
    }

    /// A camera 2 units in front of a square (texture 0..1 over 4 world
    /// units), 100 pixels high with a 90-degree field of view: the centre
    /// pixel's footprint is 2 * 2 / 100 = 0.04 world units, 0.01 in uv.
    #[test]
    fn the_footprint_is_the_pixel_cone_in_texture_space() {
        let params = TraceParams {
            width: 100,
            height: 100,
            tan_half_fov_y: 1.0,
            camera_origin: Vec4::new(0.0, 0.0, 2.0, 0.0),
            camera_forward: Vec4::new(0.0, 0.0, -1.0, 0.0),
            camera_right: Vec4::X,
            camera_up: Vec4::Y,
            ..Default::default()
        };
        let (tri, attr) = square();
        // Pixel (50, 50)'s centre looks at (0.02, -0.02): uv (0.505, 0.505).
        let (uv, w) = primary_footprint(&params, UVec2::new(50, 50), tri, &attr, Vec2::ZERO, 2.0);
        assert!((uv - Vec2::new(0.505, 0.505)).abs().max_element() < 1e-5, "{uv}");
        // The centre ray is slightly oblique: the distance grows by 1 / cos
        // and the footprint on the surface by 1 / cos again.
        let cos = 2.0 / (2.0f32 * 2.0 + 2.0 * 0.02 * 0.02).sqrt();
        assert!((w - 0.01 / (cos * cos)).abs() < 1e-7, "{w}");
        // The jittered hit does not move the lookup.
        let (uv2, _) = primary_footprint(&params, UVec2::new(50, 50), tri, &attr, Vec2::splat(0.3), 2.01);
        assert_eq!(uv, uv2);
        // A hit far from the centre ray's plane point (another surface): point lookup.
        assert_eq!(
            primary_footprint(&params, UVec2::new(50, 50), tri, &attr, Vec2::splat(0.3), 20.0),
            (Vec2::splat(0.3), 0.0)
        );
    }

    /// Later hits: the cone's width over the cosine, scaled to texture
    /// space; the spread a bounce adds follows the BSDF's lobe width.
    #[test]
    fn cones_widen_with_rough_bounces() {
        let (tri, attr) = square();
        assert!((cone_footprint(0.04, -Vec3::Z, tri, &attr) - 0.01).abs() < 1e-7);
        // At 60 degrees the footprint doubles; at grazing angles it is capped.
        let oblique = Vec3::new(0.0, 3f32.sqrt() / 2.0, -0.5);
        assert!((cone_footprint(0.04, oblique, tri, &attr) - 0.02).abs() < 1e-6);
        assert!((cone_footprint(0.04, Vec3::X, tri, &attr) - 0.01 / MIN_FOOTPRINT_COS).abs() < 1e-6);
        // No texture area: no filtering.
        assert_eq!(
            cone_footprint(0.04, -Vec3::Z, tri, &TriangleAttrGpu::default()),
            0.0
        );
        assert_eq!(bounce_spread(false, 0.0), DIFFUSE_CONE_SPREAD);
        assert!((bounce_spread(true, 0.01) - 0.02).abs() < 1e-7);
        assert_eq!(bounce_spread(true, 0.9), DIFFUSE_CONE_SPREAD);
    }
}
