//! Per-triangle vertex normals in the kernels' form
//! (`kernels::abi::TriangleAttrGpu::normal0`, `normal1`, `normal2`): three
//! unit world-space vectors, or three zeros for flat shading.
//!
//! A triangle keeps its normals only when all three are usable: finite and
//! at least [`MIN_NORMAL_LENGTH`] long. Otherwise (a NaN, an infinity, a
//! zero vector, which real files do carry for degenerate or unused
//! vertices) the whole triangle shades flat, with its geometric normal,
//! rather than with a blend of what is left: one rule, no error for data
//! that is merely unhelpful. The glTF loader counts such triangles in a
//! notice.

use super::Triangle;
use glam::{Vec3, Vec4};

/// Shortest vertex normal that is normalised rather than dropped (in the
/// units of the file, which should give unit normals: a quantised `i8`
/// normal is never shorter than about `1 - 1/127`, far above this).
pub const MIN_NORMAL_LENGTH: f32 = 1e-6;

/// `normals` normalised when all three are usable (module docs), `None`
/// otherwise.
pub fn usable_normals(normals: [Vec3; 3]) -> Option<[Vec3; 3]> {
    let ok = normals
        .iter()
        .all(|n| n.is_finite() && n.as_dvec3().length() >= f64::from(MIN_NORMAL_LENGTH));
    ok.then(|| normals.map(|n| (n.as_dvec3() / n.as_dvec3().length()).as_vec3()))
}

/// The kernels' three normal words of `t`: its usable normals, normalised,
/// `w` = 0; three zeros without normals or with an unusable one.
pub(super) fn normals_gpu(t: &Triangle) -> [Vec4; 3] {
    match t.normals.and_then(usable_normals) {
        Some(n) => n.map(|n| n.extend(0.0)),
        None => [Vec4::ZERO; 3],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn usable_normals_are_normalised_and_bad_ones_drop_the_triangle() {
        let n =
            usable_normals([Vec3::new(0.0, 0.0, 2.0), Vec3::new(3.0, 4.0, 0.0), Vec3::X]).expect("usable");
        assert_eq!(n, [Vec3::Z, Vec3::new(0.6, 0.8, 0.0), Vec3::X]);
        for bad in [
            Vec3::ZERO,
            Vec3::splat(f32::NAN),
            Vec3::new(f32::INFINITY, 0.0, 0.0),
            Vec3::splat(1e-9),
        ] {
            assert_eq!(usable_normals([Vec3::Z, bad, Vec3::Z]), None, "{bad}");
        }
        // Huge but finite: normalised without overflow.
        let big = usable_normals([Vec3::splat(f32::MAX), Vec3::Z, Vec3::Z]).expect("finite");
        assert!((big[0] - Vec3::ONE.normalize()).length() < 1e-6);
    }

    #[test]
    fn triangles_without_usable_normals_get_zeros() {
        let mut t = Triangle::new([Vec3::ZERO, Vec3::X, Vec3::Y], 0);
        assert_eq!(normals_gpu(&t), [Vec4::ZERO; 3]);
        t.normals = Some([Vec3::Z, Vec3::ZERO, Vec3::Z]);
        assert_eq!(normals_gpu(&t), [Vec4::ZERO; 3]);
        t.normals = Some([Vec3::Z * 2.0, Vec3::Z, -Vec3::Z]);
        assert_eq!(normals_gpu(&t), [Vec4::Z, Vec4::Z, -Vec4::Z]);
    }

    /// The normals follow their triangle into BVH leaf order, survive
    /// `set_positions`, and `set_normals` replaces them (scene order).
    #[test]
    fn scene_buffers_carry_keep_and_replace_the_normals() {
        use crate::scene::SceneGpu;
        let mut scene = crate::cornell::cornell_box();
        let bent = [Vec3::new(0.0, 1.0, 0.1), Vec3::Y, Vec3::new(0.1, 1.0, 0.0)];
        scene.triangles[3].normals = Some(bent);
        let mut gpu = SceneGpu::build(&scene).expect("builds");
        let leaf = |gpu: &SceneGpu, orig: u32| {
            let i = gpu
                .original_index
                .iter()
                .position(|&o| o == orig)
                .expect("present");
            let a = gpu.attrs[i];
            [a.normal0, a.normal1, a.normal2]
        };
        let want = usable_normals(bent).expect("usable").map(|n| n.extend(0.0));
        assert_eq!(leaf(&gpu, 3), want);
        assert_eq!(leaf(&gpu, 4), [Vec4::ZERO; 3]);
        let moved: Vec<[Vec3; 3]> = scene
            .triangles
            .iter()
            .map(|t| t.vertices.map(|v| v + Vec3::X))
            .collect();
        gpu.set_positions(&moved).expect("moves");
        assert_eq!(leaf(&gpu, 3), want);
        let mut normals = vec![[Vec3::ZERO; 3]; scene.triangles.len()];
        normals[4] = [Vec3::X; 3];
        gpu.set_normals(&normals).expect("sets");
        assert_eq!(leaf(&gpu, 3), [Vec4::ZERO; 3]);
        assert_eq!(leaf(&gpu, 4), [Vec4::X; 3]);
        assert!(gpu.set_normals(&normals[1..]).is_err());
    }
}
