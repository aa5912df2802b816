//! Which trace kernel variant renders a scene exactly
//! (`kernels::trace_variant`): the smallest whose features cover what the
//! scene uses.

use super::SceneGpu;
use kernels::trace_variant::{
    emitter_fits, environment_fits, material_fits, triangle_fits, BASIC, FULL, UNTEXTURED,
};

/// The trace kernel's variants (`kernels::trace_variant`), smallest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceVariant {
    /// Lambertian untextured materials without cut-outs, flat-shaded
    /// triangles, emissive triangles, no environment map: the same colours
    /// as [`TraceVariant::Full`] bit for bit on a scene that fits, from the
    /// smallest kernel (5x faster on lavapipe, 2.9x on an NVIDIA H200,
    /// `BENCHMARKS.md`).
    Basic,
    /// Everything but texture lookups: metallic-roughness materials,
    /// vertex normals, punctual lights and environment maps, no texture,
    /// normal map or alpha cut-out.
    Untextured,
    /// Every material, light and surface feature: correct for any scene.
    Full,
}

impl TraceVariant {
    /// The variants, smallest first.
    pub const ALL: [TraceVariant; 3] = [TraceVariant::Basic, TraceVariant::Untextured, TraceVariant::Full];

    /// The kernel's feature set (`kernels::trace_variant::{BASIC,
    /// UNTEXTURED, FULL}`).
    pub fn features(self) -> u32 {
        match self {
            TraceVariant::Basic => BASIC,
            TraceVariant::Untextured => UNTEXTURED,
            TraceVariant::Full => FULL,
        }
    }

    /// The name used in messages and bench rows.
    pub fn name(self) -> &'static str {
        match self {
            TraceVariant::Basic => "basic",
            TraceVariant::Untextured => "untextured",
            TraceVariant::Full => "full",
        }
    }
}

impl SceneGpu {
    /// Whether the trace kernel `variant` renders this scene exactly
    /// (`kernels::trace_variant`: every material, triangle, emitter and
    /// the environment fit its feature set). Always true for
    /// [`TraceVariant::Full`].
    pub fn fits_trace_variant(&self, variant: TraceVariant) -> bool {
        let f = variant.features();
        let emitters = &self.emitters[..(self.emitter_count as usize).min(self.emitters.len())];
        self.materials.iter().all(|m| material_fits(f, m))
            && self
                .triangles
                .iter()
                .zip(&self.attrs)
                .all(|(t, a)| triangle_fits(f, t, a))
            && emitters.iter().all(|e| emitter_fits(f, e))
            && environment_fits(f, &self.environment_map)
    }

    /// The smallest trace variant that renders this scene exactly.
    pub fn trace_variant(&self) -> TraceVariant {
        TraceVariant::ALL
            .into_iter()
            .find(|&v| self.fits_trace_variant(v))
            .unwrap_or(TraceVariant::Full)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cornell::cornell_box;
    use crate::scene::Light;
    use glam::Vec3;

    #[test]
    fn each_feature_takes_a_scene_to_the_variant_that_has_it() {
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        assert_eq!(scene.trace_variant(), TraceVariant::Basic);

        let mut glossy = scene.clone();
        glossy.materials[0].model.x = kernels::abi::MODEL_METALLIC_ROUGHNESS;
        assert_eq!(glossy.trace_variant(), TraceVariant::Untextured);

        let mut textured = scene.clone();
        textured.materials[0].textures.x = 0;
        assert_eq!(textured.trace_variant(), TraceVariant::Full);

        let mut normal_mapped = scene.clone();
        normal_mapped.materials[0].normal.x = 0;
        assert_eq!(normal_mapped.trace_variant(), TraceVariant::Full);

        let mut cut_out = scene.clone();
        cut_out.triangles[3].v2.w = kernels::abi::CUT_OUT;
        assert_eq!(cut_out.trace_variant(), TraceVariant::Full);

        let mut smooth = scene.clone();
        smooth.attrs[5].normal0 = glam::Vec4::Y;
        assert_eq!(smooth.trace_variant(), TraceVariant::Untextured);

        let mut env = scene.clone();
        env.environment_map.width = 4;
        assert_eq!(env.trace_variant(), TraceVariant::Untextured);

        let mut lit = cornell_box();
        lit.lights
            .push(Light::point("bulb", Vec3::new(278.0, 500.0, 278.0), 1.0e5));
        assert_eq!(
            SceneGpu::build(&lit).unwrap().trace_variant(),
            TraceVariant::Untextured
        );
        assert!((0..3).all(|i| scene.fits_trace_variant(TraceVariant::ALL[i])));
    }

    /// Every variant a scene fits renders what the full one does, bit for
    /// bit, with every sampler (the seed stream and the a-priori samplers
    /// draw different numbers at every step a variant skips): the Cornell
    /// box (basic), the glossy box and the sun and sky (untextured); a
    /// variant is refused for a scene it does not fit.
    #[test]
    fn every_variant_a_scene_fits_renders_it_bit_for_bit() {
        use crate::cpu::{render_frame_variant, white_seeds};
        use crate::error::Error;
        use crate::TraceSettings;
        use kernels::abi::{SAMPLER_KRONECKER, SAMPLER_SCREEN_SOBOL, SAMPLER_SEEDS, SAMPLER_SPATIOTEMPORAL};
        let (w, h) = (24u32, 18u32);
        let seeds = white_seeds(w, h, 3);
        let scenes = [
            ("cornell", cornell_box(), TraceVariant::Basic),
            (
                "cornell-glossy",
                crate::cornell::cornell_glossy(),
                TraceVariant::Untextured,
            ),
            (
                "sun-and-sky",
                crate::outdoor::sun_and_sky(),
                TraceVariant::Untextured,
            ),
        ];
        for (name, scene, smallest) in scenes {
            let scene = SceneGpu::build(&scene).unwrap();
            assert_eq!(scene.trace_variant(), smallest, "{name}");
            for sampler in [
                SAMPLER_SEEDS,
                SAMPLER_SCREEN_SOBOL,
                SAMPLER_SPATIOTEMPORAL,
                SAMPLER_SPATIOTEMPORAL | SAMPLER_KRONECKER,
            ] {
                let mut settings = TraceSettings::new(w, h);
                settings.spp = 2;
                settings.sampler = sampler;
                let params = scene.trace_params(&settings, 5).unwrap();
                let render = |variant| {
                    let mut color = vec![glam::Vec4::ZERO; (w * h) as usize];
                    render_frame_variant(&scene, &params, &seeds, &mut color, variant)
                        .map(|rays| (color, rays))
                };
                let full = render(TraceVariant::Full).unwrap();
                assert!(
                    full.0.iter().any(|c| c.x > 0.0),
                    "{name}: a black frame proves nothing"
                );
                for variant in TraceVariant::ALL {
                    if scene.fits_trace_variant(variant) {
                        assert!(
                            render(variant).unwrap() == full,
                            "{name}, {}, sampler {sampler:#x}",
                            variant.name()
                        );
                    } else {
                        assert!(matches!(
                            render(variant),
                            Err(Error::UnfitTraceVariant { variant: v }) if v == variant.name()
                        ));
                    }
                }
            }
        }
    }

    /// The G-buffer without texture lookups (`gbuffer_untextured_cs`) is
    /// the full one, bit for bit, on every scene the untextured trace
    /// kernel fits.
    #[test]
    fn the_untextured_gbuffer_matches_the_full_one() {
        use crate::TraceSettings;
        use kernels::gbuffer::{gbuffer_pixel, gbuffer_pixel_variant};
        use kernels::trace_variant::UNTEXTURED;
        let (w, h) = (32u32, 24u32);
        for scene in [
            cornell_box(),
            crate::cornell::cornell_glossy(),
            crate::outdoor::sun_and_sky(),
        ] {
            let scene = SceneGpu::build(&scene).unwrap();
            assert!(scene.fits_trace_variant(TraceVariant::Untextured));
            let params = scene.trace_params(&TraceSettings::new(w, h), 0).unwrap();
            let mut hits = 0;
            for y in 0..h {
                for x in 0..w {
                    let p = glam::UVec2::new(x, y);
                    let (s, prev) = (&scene, &scene.previous);
                    let full = gbuffer_pixel(
                        &params,
                        p,
                        &s.nodes,
                        &s.triangles,
                        &s.materials,
                        &s.attrs,
                        &s.images,
                        prev,
                    );
                    let lean = gbuffer_pixel_variant::<UNTEXTURED>(
                        &params,
                        p,
                        &s.nodes,
                        &s.triangles,
                        &s.materials,
                        &s.attrs,
                        &s.images,
                        prev,
                    );
                    assert_eq!(full, lean, "pixel {p}");
                    hits += (full.ids.w & kernels::abi::GBUFFER_HIT != 0) as u32;
                }
            }
            assert!(hits > 0, "no hit proves nothing");
        }
    }
}
