//! Ray queries against a built scene on the host ([`SceneGpu::closest_hit`],
//! [`SceneGpu::occluded`]): the kernels' own traversals over the scene's
//! buffers (cut-out holes included), for tools that place insets, check
//! visibility or find what a pixel sees.

use super::SceneGpu;
use kernels::bvh::{any_hit, closest_hit, Hit};
use kernels::intersect::Ray;

impl SceneGpu {
    /// The nearest hit of `ray` at distances in `(0, f32::MAX)`, as the
    /// trace kernel finds it; `None` when it leaves the scene.
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        closest_hit(
            &self.nodes,
            &self.triangles,
            &self.materials,
            &self.attrs,
            &self.images,
            self.image_count,
            ray,
            0.0,
            f32::MAX,
        )
    }

    /// Whether anything blocks `ray` at distances in `(0, t_max)` (a shadow
    /// ray's test).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        any_hit(
            &self.nodes,
            &self.triangles,
            &self.materials,
            &self.attrs,
            &self.images,
            self.image_count,
            ray,
            0.0,
            t_max,
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::cornell::cornell_box;
    use crate::scene::SceneGpu;
    use glam::Vec3;
    use kernels::intersect::Ray;

    /// In the Cornell box a ray down from the middle hits the floor at its
    /// height; a ray from the floor to the ceiling is blocked by nothing
    /// short of the ceiling.
    #[test]
    fn queries_see_the_room() {
        let scene = SceneGpu::build(&cornell_box()).expect("scene");
        let down = Ray::new(Vec3::new(278.0, 273.0, 100.0), -Vec3::Y);
        let hit = scene.closest_hit(&down).expect("floor");
        assert!((hit.t - 273.0).abs() < 1e-3, "{}", hit.t);
        let up = Ray::new(Vec3::new(278.0, 1.0, 100.0), Vec3::Y);
        assert!(!scene.occluded(&up, 500.0));
        assert!(scene.occluded(&up, 560.0));
        assert!(scene
            .closest_hit(&Ray::new(Vec3::new(278.0, 273.0, 100.0), -Vec3::Z))
            .is_none());
    }
}
