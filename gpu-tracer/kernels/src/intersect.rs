//! Ray-primitive tests: rays against triangles (Möller–Trumbore) and
//! axis-aligned boxes (slab test).
//!
//! Distances `t` are in units of the ray direction's length (world units for
//! unit directions). Both tests are written so that no NaN is produced for
//! finite inputs: the slab test never multiplies `0 * inf`.

use glam::Vec3;

/// A ray `origin + t * dir`. `dir` need not be unit length but must be
/// non-zero and finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point (world units).
    pub origin: Vec3,
    /// Direction.
    pub dir: Vec3,
}

/// Smallest magnitude a direction component takes before inversion in
/// [`Ray::inv_dir`]: keeps reciprocals finite (`1 / 1e-30 = 1e30`), so the
/// slab test never computes `0 * inf`.
pub const MIN_DIR_COMPONENT: f32 = 1e-30;

impl Ray {
    /// Ray from `origin` along `dir`.
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    /// Point at distance `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }

    /// Component-wise reciprocal of the direction, with components smaller
    /// than [`MIN_DIR_COMPONENT`] in magnitude replaced by
    /// `±MIN_DIR_COMPONENT` (sign kept; `+0` and `-0` keep theirs). Finite.
    #[inline]
    pub fn inv_dir(&self) -> Vec3 {
        Vec3::new(
            1.0 / clamp_away_from_zero(self.dir.x),
            1.0 / clamp_away_from_zero(self.dir.y),
            1.0 / clamp_away_from_zero(self.dir.z),
        )
    }
}

#[inline]
fn clamp_away_from_zero(x: f32) -> f32 {
    if libm::fabsf(x) < MIN_DIR_COMPONENT {
        libm::copysignf(MIN_DIR_COMPONENT, x)
    } else {
        x
    }
}

/// Where a ray meets a triangle: distance and barycentrics of `v1` and `v2`
/// (the point is `(1 - u - v) v0 + u v1 + v v2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray, in `(t_min, t_max)` of the query.
    pub t: f32,
    /// Barycentric weight of `v1`, in `[0, 1]`.
    pub u: f32,
    /// Barycentric weight of `v2`, in `[0, 1]`, with `u + v <= 1`.
    pub v: f32,
}

/// Möller–Trumbore ray-triangle test, two-sided.
///
/// Returns the hit when the ray meets the triangle at a distance strictly
/// inside `(t_min, t_max)`. Degenerate (zero-area) triangles and rays
/// parallel to the triangle's plane (the cosine between the ray and
/// the plane's normal below `1e-6` in magnitude) never hit. Edges are inclusive (`u, v >= 0`, `u + v <= 1`),
/// so a ray through a shared edge hits at least one of the two triangles up
/// to rounding of the barycentrics.
#[inline]
pub fn intersect_triangle(
    ray: &Ray,
    v0: Vec3,
    v1: Vec3,
    v2: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<TriangleHit> {
    let e1 = v1 - v0;
    let e2 = v2 - v0;
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    // Scale-free parallel test: det = dir . (e1 x e2) = |dir| |e1 x e2| cos(angle), so
    // this rejects |cos| <= 1e-6 and zero-area triangles (e1 x e2 = 0).
    let normal = e1.cross(e2);
    if det * det <= 1e-12 * ray.dir.length_squared() * normal.length_squared() {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - v0;
    let u = s.dot(p) * inv_det;
    // Not `(0.0..=1.0).contains(&u)`: rust-gpu cannot compile the
    // `Bound<&f32>` it builds (a pointer inside an enum). NaN is rejected too.
    #[allow(clippy::manual_range_contains)]
    if !(u >= 0.0 && u <= 1.0) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    if t > t_min && t < t_max {
        Some(TriangleHit { t, u, v })
    } else {
        None
    }
}

/// Slab test of a ray against the box `[min, max]`, given the ray's
/// [`Ray::inv_dir`].
///
/// Returns the entry distance `max(t_enter, t_min)` when the ray's segment
/// `[t_min, t_max]` overlaps the box, `None` otherwise. A ray starting
/// inside the box returns `t_min`. Flat boxes (min == max on an axis, as for
/// an axis-aligned triangle) are hit by rays that cross their plane. A ray
/// with a zero direction component lying exactly in a face's plane may count
/// as inside or outside (a measure-zero set of rays).
#[inline]
pub fn intersect_aabb(
    origin: Vec3,
    inv_dir: Vec3,
    min: Vec3,
    max: Vec3,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let t0 = (min - origin) * inv_dir;
    let t1 = (max - origin) * inv_dir;
    let near = t0.min(t1);
    let far = t0.max(t1);
    let enter = near.x.max(near.y).max(near.z).max(t_min);
    let exit = far.x.min(far.y).min(far.z).min(t_max);
    if enter <= exit {
        Some(enter)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Vec3 = Vec3::new(0.0, 0.0, 0.0);
    const B: Vec3 = Vec3::new(1.0, 0.0, 0.0);
    const C: Vec3 = Vec3::new(0.0, 1.0, 0.0);

    #[test]
    fn triangle_hit_reports_distance_and_barycentrics() {
        let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -1.0));
        let hit = intersect_triangle(&ray, A, B, C, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 2.0).abs() < 1e-6);
        assert!((hit.u - 0.25).abs() < 1e-6 && (hit.v - 0.5).abs() < 1e-6);
        // Two-sided: from below too.
        let below = Ray::new(Vec3::new(0.25, 0.5, -3.0), Vec3::new(0.0, 0.0, 1.0));
        let hit = intersect_triangle(&below, A, B, C, 0.0, f32::INFINITY).expect("hit");
        assert!((hit.t - 3.0).abs() < 1e-6);
    }

    #[test]
    fn triangle_misses() {
        let down = Vec3::new(0.0, 0.0, -1.0);
        // Outside the edges.
        for o in [
            Vec3::new(0.6, 0.6, 1.0),
            Vec3::new(-0.1, 0.5, 1.0),
            Vec3::new(0.5, -0.1, 1.0),
        ] {
            assert_eq!(
                intersect_triangle(&Ray::new(o, down), A, B, C, 0.0, 10.0),
                None,
                "{o}"
            );
        }
        let ray = Ray::new(Vec3::new(0.2, 0.2, 1.0), down);
        // Behind the origin, beyond t_max, before t_min.
        assert_eq!(
            intersect_triangle(&Ray::new(Vec3::new(0.2, 0.2, -1.0), down), A, B, C, 0.0, 10.0),
            None
        );
        assert_eq!(intersect_triangle(&ray, A, B, C, 0.0, 0.5), None);
        assert_eq!(intersect_triangle(&ray, A, B, C, 1.5, 10.0), None);
        // Parallel to the plane, and a degenerate triangle.
        let parallel = Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X);
        assert_eq!(intersect_triangle(&parallel, A, B, C, 0.0, 10.0), None);
        assert_eq!(intersect_triangle(&ray, A, B, B * 2.0, 0.0, 10.0), None);
    }

    #[test]
    fn shared_edge_is_not_a_crack() {
        // Two triangles forming the unit square; rays on the diagonal x + y = 1.
        let d = Vec3::new(1.0, 1.0, 0.0);
        let down = Vec3::new(0.0, 0.0, -1.0);
        for i in 1..100 {
            let s = i as f32 / 100.0;
            let ray = Ray::new(Vec3::new(s, 1.0 - s, 1.0), down);
            let hit = intersect_triangle(&ray, A, B, C, 0.0, 10.0).is_some()
                || intersect_triangle(&ray, B, d, C, 0.0, 10.0).is_some();
            assert!(hit, "crack at s = {s}");
        }
    }

    #[test]
    fn aabb_slab_test() {
        let (min, max) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let t = intersect_aabb(ray.origin, ray.inv_dir(), min, max, 0.0, 100.0);
        assert_eq!(t, Some(4.0));
        // Inside: entry is t_min.
        assert_eq!(
            intersect_aabb(Vec3::ZERO, ray.inv_dir(), min, max, 0.0, 100.0),
            Some(0.0)
        );
        // Segment too short, box behind, ray beside the box.
        assert_eq!(
            intersect_aabb(ray.origin, ray.inv_dir(), min, max, 0.0, 3.9),
            None
        );
        assert_eq!(
            intersect_aabb(Vec3::new(0.0, 0.0, 5.0), ray.inv_dir(), min, max, 0.0, 100.0),
            None
        );
        assert_eq!(
            intersect_aabb(Vec3::new(2.0, 0.0, -5.0), ray.inv_dir(), min, max, 0.0, 100.0),
            None
        );
        // Zero direction components (0 * inf would be NaN without the clamp in inv_dir).
        let edge = Ray::new(Vec3::new(0.5, -1.0, -5.0), Vec3::Z);
        assert!(edge.inv_dir().is_finite());
        assert_eq!(
            intersect_aabb(edge.origin, edge.inv_dir(), min, max, 0.0, 100.0),
            Some(4.0)
        );
        // Flat box (a triangle lying in z = 0).
        let flat = intersect_aabb(
            ray.origin,
            ray.inv_dir(),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            0.0,
            100.0,
        );
        assert_eq!(flat, Some(5.0));
    }
}
