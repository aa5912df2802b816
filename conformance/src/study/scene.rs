//! The scenes a rendered-quality study can use: the built-in Cornell box, and
//! the same room as a textured glTF (issue 14's demodulation study) with its
//! untextured twin.
//!
//! `cornell-textured` is `gpu-tracer/tests/data/gltf/cornell_textured.gltf`
//! (written by `cargo run -p gpu-tracer --example make_gltf_fixtures`): the
//! Cornell box's triangles, object ids, material order and camera, with a
//! high-contrast 4-texel checker (albedo luma about 0.72 / 0.044, a contrast
//! of about 16) on every surface but the light, one texel per 16 world units
//! (about 5 px at 256x256, so most 4x4 sorting blocks straddle a texel edge).
//! `cornell-untextured` is that file with every texture replaced by its mean
//! linear colour: the same room, reflecting the same light on average, with
//! nothing for a sort key to mistake for noise. `cornell-glossy` is
//! `gpu_tracer::cornell::cornell_glossy`: the room with three GGX spheres
//! (roughness 0.1, 0.3, 0.6) in place of the blocks, for the samplers on
//! glossy reflections. The insets, regions and camera of the study are the
//! Cornell box's for these four. `sun-sky` is
//! `gpu_tracer::outdoor::sun_and_sky` rendered with its constant sky
//! (`gpu_tracer::outdoor::SKY`): soft shadows from a sun with a disk and
//! sky occlusion, with its own camera and insets (sunlit ground, ground in
//! the sphere's shadow, the wall's shaded face).

use anyhow::{Context, Result};
use glam::Vec3;
use gpu_tracer::cornell::{cornell_box, cornell_glossy};
use gpu_tracer::gltf::load_gltf;
use gpu_tracer::outdoor::{sun_and_sky, SKY};
use gpu_tracer::scene::{Image, Scene};
use std::path::PathBuf;

/// Which scene a study renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum StudyScene {
    /// `gpu_tracer::cornell::cornell_box`.
    #[default]
    Cornell,
    /// The Cornell box with the checker texture, loaded from glTF.
    CornellTextured,
    /// [`StudyScene::CornellTextured`] with each texture replaced by its mean
    /// linear colour (multiplied into the material's albedo).
    CornellUntextured,
    /// `gpu_tracer::cornell::cornell_glossy`: three metallic-roughness
    /// spheres in the room.
    CornellGlossy,
    /// `gpu_tracer::outdoor::sun_and_sky` under its sky: a directional sun
    /// with a disk and a constant environment.
    SunSky,
}

impl StudyScene {
    /// Every scene.
    pub const ALL: [StudyScene; 5] = [
        StudyScene::Cornell,
        StudyScene::CornellTextured,
        StudyScene::CornellUntextured,
        StudyScene::CornellGlossy,
        StudyScene::SunSky,
    ];

    /// Name on the command line and in cache file names.
    pub fn name(self) -> &'static str {
        match self {
            StudyScene::Cornell => "cornell",
            StudyScene::CornellTextured => "cornell-textured",
            StudyScene::CornellUntextured => "cornell-untextured",
            StudyScene::CornellGlossy => "cornell-glossy",
            StudyScene::SunSky => "sun-sky",
        }
    }

    /// The scene called `name` ([`StudyScene::name`]).
    pub fn from_name(name: &str) -> Option<StudyScene> {
        StudyScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Radiance of the constant environment the scene is rendered with
    /// (`TraceSettings::environment`): [`SKY`] for [`StudyScene::SunSky`],
    /// black (closed rooms) otherwise.
    pub fn environment(self) -> Vec3 {
        match self {
            StudyScene::SunSky => SKY,
            _ => Vec3::ZERO,
        }
    }

    /// Whether `self` and `other` are the same room seen by the same camera (a scene and
    /// itself, or the textured box and its untextured twin, one glTF): what
    /// [`StudyConfig::modulate_by`](super::config::StudyConfig::modulate_by) needs.
    pub fn camera_matches(self, other: StudyScene) -> bool {
        let twins = [StudyScene::CornellTextured, StudyScene::CornellUntextured];
        self == other || (twins.contains(&self) && twins.contains(&other))
    }

    /// The glTF file of the textured scenes.
    pub fn gltf_path() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../gpu-tracer/tests/data/gltf/cornell_textured.gltf")
    }

    /// Builds the scene.
    ///
    /// # Errors
    /// The glTF file cannot be loaded.
    pub fn load(self) -> Result<Scene> {
        if self == StudyScene::Cornell {
            return Ok(cornell_box());
        }
        if self == StudyScene::CornellGlossy {
            return Ok(cornell_glossy());
        }
        if self == StudyScene::SunSky {
            return Ok(sun_and_sky());
        }
        let path = StudyScene::gltf_path();
        let mut scene = load_gltf(&path, None)
            .with_context(|| format!("loading {}", path.display()))?
            .scene;
        // The study's insets are placed for the Cornell box's camera exactly.
        scene.camera = cornell_box().camera;
        if self == StudyScene::CornellUntextured {
            let means: Vec<Vec3> = scene.images.iter().map(mean_linear_colour).collect();
            for m in &mut scene.materials {
                if let Some(t) = m.base_color_texture.take() {
                    m.albedo *= means[t.image as usize];
                }
            }
        }
        Ok(scene)
    }
}

/// Mean of an sRGB image's texels, decoded to linear RGB.
pub fn mean_linear_colour(image: &Image) -> Vec3 {
    let sum = image.texels.iter().fold(Vec3::ZERO, |acc, t| {
        acc + Vec3::new(
            kernels::texture::srgb_to_linear(t[0] as u32),
            kernels::texture::srgb_to_linear(t[1] as u32),
            kernels::texture::srgb_to_linear(t[2] as u32),
        )
    });
    sum / image.texels.len().max(1) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_is_found_by_its_name() {
        for s in StudyScene::ALL {
            assert_eq!(StudyScene::from_name(s.name()), Some(s));
        }
        let glossy = StudyScene::from_name("cornell-glossy")
            .expect("listed")
            .load()
            .expect("built-in");
        assert_eq!(glossy, cornell_glossy());
        // Only the outdoor scene has a sky.
        assert_eq!(StudyScene::SunSky.load().expect("built-in"), sun_and_sky());
        for s in StudyScene::ALL {
            let want = if s == StudyScene::SunSky { SKY } else { Vec3::ZERO };
            assert_eq!(s.environment(), want, "{s:?}");
        }
    }

    #[test]
    fn textured_scene_is_the_cornell_box_with_textures() {
        let plain = cornell_box();
        let textured = StudyScene::CornellTextured.load().expect("textured");
        let untextured = StudyScene::CornellUntextured.load().expect("untextured");
        assert_eq!(textured.triangles.len(), plain.triangles.len());
        for (a, b) in textured.triangles.iter().zip(&plain.triangles) {
            assert_eq!((a.object, a.material), (b.object, b.material));
            for (p, q) in a.vertices.iter().zip(b.vertices) {
                assert!((*p - q).length() < 1e-3, "{p} vs {q}");
            }
        }
        assert_eq!(textured.materials.len(), plain.materials.len());
        let light = gpu_tracer::cornell::LIGHT as usize;
        for (i, (t, p)) in textured.materials.iter().zip(&plain.materials).enumerate() {
            assert!((t.albedo - p.albedo).length() < 1e-6, "material {i}");
            assert!((t.emission - p.emission).length() < 1e-4, "material {i}");
            assert_eq!(t.base_color_texture.is_some(), i != light, "material {i}");
        }
        // The checker is high-contrast; the twin's albedo is its mean.
        let mean = mean_linear_colour(&textured.images[0]);
        assert!(mean.x > 0.3 && mean.x < 0.5, "{mean}");
        for (i, (u, t)) in untextured.materials.iter().zip(&textured.materials).enumerate() {
            assert!(u.base_color_texture.is_none());
            let want = if i == light { t.albedo } else { t.albedo * mean };
            assert!((u.albedo - want).length() < 1e-6, "material {i}");
        }
        assert_eq!(textured.camera, plain.camera);
        assert_eq!(textured.camera, untextured.camera);
    }

    #[test]
    fn only_one_room_under_one_camera_modulates() {
        use StudyScene::*;
        assert!(CornellUntextured.camera_matches(CornellTextured));
        assert!(CornellTextured.camera_matches(CornellUntextured));
        assert!(SunSky.camera_matches(SunSky));
        assert!(!Cornell.camera_matches(CornellTextured));
        assert!(!SunSky.camera_matches(CornellUntextured));
    }
}
