//! Path regularisation: glossy surfaces met after rough ones are made rougher.
//!
//! A diffuse wall lit through a sharp glossy surface (wall -> metal sphere ->
//! light: a caustic) receives that light only when the wall's BSDF sample hits
//! the sphere *and* the sphere's narrow lobe hits the light. At one sample per
//! pixel this is a rare, bright contribution whose chance depends on several
//! number pairs jointly, so no per-pixel sequence makes it blue in space or in
//! time (`QUALITY.md`, "Why the glossy box's interior is white in time").
//! Regularisation (Kaplanyan & Dachsbacher 2013, "Path Space Regularization
//! for Holistic and Robust Light Transport"; real-time path tracers apply a
//! roughness floor of this kind) widens such lobes so that next-event
//! estimation and BSDF sampling find the light often, with a smaller weight.
//!
//! The rule: at every vertex a metallic-roughness surface's perceptual
//! roughness is raised to at least `strength * path_roughness`
//! ([`roughness_floor`]), where `path_roughness` is the largest roughness of
//! the lobes that continued the path at its earlier vertices (1 for a
//! Lambertian vertex and for a metallic-roughness vertex's diffuse lobe; 0
//! before the first vertex, so surfaces seen from the camera, and mirrors
//! seen in mirrors, keep their own roughness). `strength` is
//! `crate::abi::TraceParams::glossy_regularization`, in `[0, 1]`: 0 leaves
//! every path as it was, bit for bit (unbiased); 1 makes every glossy surface
//! seen after a diffuse bounce as rough as roughness 1.
//!
//! **Biased**: the converged image loses the caustics' sharpness, and some
//! energy, since the single-scattering GGX model loses more energy the
//! rougher it is (measured in `QUALITY.md`).

/// The roughness below which a metallic-roughness surface at the next vertex
/// is raised: `strength * path_roughness`, both in `[0, 1]` (module docs).
/// 0 when `strength` is 0: regularisation off.
#[inline]
pub fn roughness_floor(strength: f32, path_roughness: f32) -> f32 {
    strength * path_roughness
}

/// A surface's perceptual roughness `roughness` raised to at least `floor`
/// ([`roughness_floor`]); `floor <= 0` (or NaN) returns `roughness` as it
/// is, bit for bit.
#[inline]
pub fn raised_roughness(roughness: f32, floor: f32) -> f32 {
    if floor > 0.0 {
        roughness.max(floor)
    } else {
        roughness
    }
}

/// The path's roughness after a vertex whose continuing lobe has roughness
/// `lobe_roughness` (`crate::shading::Shading::continuation_roughness`): the
/// larger of both, in `[0, 1]`.
#[inline]
pub fn path_roughness_after(path_roughness: f32, lobe_roughness: f32) -> f32 {
    path_roughness.max(lobe_roughness)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_floor_follows_the_roughest_earlier_lobe() {
        // Camera: no earlier vertex, no floor.
        let mut path = 0.0;
        assert_eq!(roughness_floor(1.0, path), 0.0);
        // A mirror seen from the camera keeps mirrors after it sharp.
        path = path_roughness_after(path, 0.01);
        assert_eq!(roughness_floor(1.0, path), 0.01);
        // After a diffuse bounce every later glossy lobe is at least `strength`.
        path = path_roughness_after(path, 1.0);
        assert_eq!(roughness_floor(0.5, path), 0.5);
        assert_eq!(path_roughness_after(path, 0.2), 1.0);
        // Strength 0: off whatever the path met.
        assert_eq!(roughness_floor(0.0, path), 0.0);
    }

    #[test]
    fn a_floor_only_raises() {
        assert_eq!(raised_roughness(0.1, 0.5), 0.5);
        assert_eq!(raised_roughness(0.8, 0.5), 0.8);
        // No floor: the value as it was, NaN included (bit for bit).
        assert_eq!(raised_roughness(0.1, 0.0), 0.1);
        assert!(raised_roughness(f32::NAN, 0.0).is_nan());
        assert_eq!(raised_roughness(0.3, f32::NAN), 0.3);
    }
}
