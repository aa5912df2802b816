//! Which pixels see a glossy surface first: the split of the interior that
//! issue 29's glossy-box diagnostic reads (`crate::study::surfaces`).
//!
//! A pixel's first hit is **glossy** when its material is the glTF
//! metallic-roughness model ([`MODEL_METALLIC_ROUGHNESS`]) with a
//! `roughnessFactor` below [`GLOSSY_ROUGHNESS`]; every other hit (Lambert,
//! rough metallic-roughness, the sky) is diffuse. Read from a G-buffer's
//! material index (`ids.y`).

use super::regions::Region;
use kernels::abi::{GBufferGpu, MaterialGpu, GBUFFER_HIT, MODEL_METALLIC_ROUGHNESS};

/// `roughnessFactor` (perceptual, glTF) below which a metallic-roughness
/// surface counts as glossy: 0.75 (GGX `alpha` about 0.56), so that the glossy
/// box's three spheres (0.1, 0.3, 0.6) are glossy and glTF's default
/// roughness of 1 is not.
pub const GLOSSY_ROUGHNESS: f32 = 0.75;

/// Per pixel of `gbuffer`, whether its first hit is glossy (module docs);
/// `materials` is the scene's material buffer, indexed by `ids.y` (an index
/// outside it counts as diffuse).
pub fn glossy_first_hits(materials: &[MaterialGpu], gbuffer: &[GBufferGpu]) -> Vec<bool> {
    gbuffer
        .iter()
        .map(|g| {
            g.ids.w & GBUFFER_HIT != 0
                && materials
                    .get(g.ids.y as usize)
                    .is_some_and(|m| m.model.x == MODEL_METALLIC_ROUGHNESS && m.pbr.y < GLOSSY_ROUGHNESS)
        })
        .collect()
}

/// Share of the [`Region::Interior`] pixels of `regions` whose first hit is
/// glossy; 0 without interior pixels.
pub fn glossy_interior_share(regions: &[Region], glossy: &[bool]) -> f64 {
    let interior = regions.iter().filter(|&&r| r == Region::Interior).count();
    let shiny = regions
        .iter()
        .zip(glossy)
        .filter(|(&r, &g)| r == Region::Interior && g)
        .count();
    if interior == 0 {
        0.0
    } else {
        shiny as f64 / interior as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_glossy_box_spheres_are_glossy_and_the_cornell_box_is_not() {
        use gpu_tracer::{cpu, TraceSettings};
        let count = |scene: gpu_tracer::Scene| {
            let scene = gpu_tracer::SceneGpu::build(&scene).unwrap();
            let params = scene.trace_params(&TraceSettings::new(48, 48), 0).unwrap();
            let mut g = vec![GBufferGpu::default(); 48 * 48];
            cpu::gbuffer_frame(&scene, &params, &mut g).unwrap();
            glossy_first_hits(&scene.materials, &g)
                .iter()
                .filter(|&&b| b)
                .count()
        };
        assert_eq!(count(gpu_tracer::cornell::cornell_box()), 0);
        let glossy = count(gpu_tracer::cornell::cornell_glossy());
        assert!(glossy > 48 && glossy < 48 * 48 / 2, "{glossy} glossy pixels");
    }

    #[test]
    fn the_glossy_share_counts_interior_pixels_only() {
        let regions = [Region::Interior, Region::Interior, Region::Edge, Region::Interior];
        let glossy = [true, false, true, false];
        assert!((glossy_interior_share(&regions, &glossy) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(glossy_interior_share(&[Region::Edge], &[true]), 0.0);
    }
}
