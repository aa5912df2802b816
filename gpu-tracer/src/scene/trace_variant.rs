//! Which trace kernel variant renders a scene exactly
//! (`kernels::trace_variant`): the basic one where the scene uses none of
//! what it leaves out, the full one otherwise.

use super::SceneGpu;
use kernels::trace_variant::{
    attr_fits_basic, emitter_fits_basic, environment_fits_basic, material_fits_basic,
};

/// The trace kernel's two variants (`kernels::trace_variant`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceVariant {
    /// Every material, light and surface feature: correct for any scene.
    Full,
    /// Lambertian untextured materials without cut-outs, flat-shaded
    /// triangles, emissive triangles, no environment map: the same colours
    /// as [`TraceVariant::Full`] bit for bit on a scene that fits
    /// ([`SceneGpu::fits_basic_trace`]), from a smaller kernel (3-4x faster
    /// on lavapipe, `BENCHMARKS.md`).
    Basic,
}

impl SceneGpu {
    /// Whether the basic trace variant renders this scene exactly: every
    /// material Lambertian, untextured and without cut-out, no triangle
    /// flagged as cut-out or carrying vertex normals, every emitter an
    /// emissive triangle, no environment map.
    pub fn fits_basic_trace(&self) -> bool {
        let emitters = &self.emitters[..(self.emitter_count as usize).min(self.emitters.len())];
        self.materials.iter().all(material_fits_basic)
            && self
                .triangles
                .iter()
                .zip(&self.attrs)
                .all(|(t, a)| attr_fits_basic(t, a))
            && emitters.iter().all(emitter_fits_basic)
            && environment_fits_basic(&self.environment_map)
    }

    /// The fastest trace variant that renders this scene exactly.
    pub fn trace_variant(&self) -> TraceVariant {
        if self.fits_basic_trace() {
            TraceVariant::Basic
        } else {
            TraceVariant::Full
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cornell::cornell_box;
    use crate::scene::Light;
    use glam::Vec3;

    #[test]
    fn the_cornell_box_fits_the_basic_variant_and_each_feature_takes_it_out() {
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        assert_eq!(scene.trace_variant(), TraceVariant::Basic);

        let mut glossy = scene.clone();
        glossy.materials[0].model.x = kernels::abi::MODEL_METALLIC_ROUGHNESS;
        assert_eq!(glossy.trace_variant(), TraceVariant::Full);

        let mut textured = scene.clone();
        textured.materials[0].textures.x = 0;
        assert!(!textured.fits_basic_trace());

        let mut normal_mapped = scene.clone();
        normal_mapped.materials[0].normal.x = 0;
        assert!(!normal_mapped.fits_basic_trace());

        let mut cut_out = scene.clone();
        cut_out.triangles[3].v2.w = kernels::abi::CUT_OUT;
        assert!(!cut_out.fits_basic_trace());

        let mut smooth = scene.clone();
        smooth.attrs[5].normal0 = glam::Vec4::Y;
        assert!(!smooth.fits_basic_trace());

        let mut env = scene.clone();
        env.environment_map.width = 4;
        assert!(!env.fits_basic_trace());

        let mut lit = cornell_box();
        lit.lights
            .push(Light::point("bulb", Vec3::new(278.0, 500.0, 278.0), 1.0e5));
        assert_eq!(SceneGpu::build(&lit).unwrap().trace_variant(), TraceVariant::Full);
    }

    /// On the Cornell box the basic variant renders what the full one
    /// does, bit for bit, with every sampler (the seed stream and the
    /// a-priori samplers draw different numbers at every step it skips);
    /// on scenes it cannot render it is refused.
    #[test]
    fn the_basic_variant_renders_the_cornell_box_bit_for_bit() {
        use crate::cpu::{render_frame_variant, white_seeds};
        use crate::error::Error;
        use crate::TraceSettings;
        use kernels::abi::{SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL};
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        let (w, h) = (24u32, 18u32);
        let seeds = white_seeds(w, h, 3);
        for sampler in [
            SAMPLER_SEEDS,
            SAMPLER_SCREEN_SOBOL,
            SAMPLER_SPATIOTEMPORAL,
            SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER,
        ] {
            let mut settings = TraceSettings::new(w, h);
            settings.spp = 2;
            settings.sampler = sampler;
            for frame in [0, 5] {
                let params = scene.trace_params(&settings, frame).unwrap();
                let mut full = vec![glam::Vec4::ZERO; (w * h) as usize];
                let mut basic = full.clone();
                let rays_full =
                    render_frame_variant(&scene, &params, &seeds, &mut full, TraceVariant::Full).unwrap();
                let rays_basic =
                    render_frame_variant(&scene, &params, &seeds, &mut basic, TraceVariant::Basic).unwrap();
                assert!(full.iter().any(|c| c.x > 0.0), "a black frame proves nothing");
                assert_eq!(full, basic, "sampler {sampler:#x}, frame {frame}");
                assert_eq!(rays_full, rays_basic);
            }
        }
        let glossy = SceneGpu::build(&crate::cornell::cornell_glossy()).unwrap();
        let params = glossy.trace_params(&TraceSettings::new(w, h), 0).unwrap();
        let mut color = vec![glam::Vec4::ZERO; (w * h) as usize];
        assert!(matches!(
            render_frame_variant(&glossy, &params, &seeds, &mut color, TraceVariant::Basic),
            Err(Error::UnfitTraceVariant)
        ));
    }
}
