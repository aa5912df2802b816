//! The high-sample reference images of the rendered-quality studies, and their cache.
//!
//! A [`Reference`] is the mean of two independent halves of `ref_spp / 2` samples
//! each, so its own noise can be estimated ([`Reference::noise_var`], used by
//! [`crate::study`] and [`crate::motion`] to correct accumulated errors).
//! References are cached as raw little-endian `f32` files under
//! [`default_cache_dir`]; the file name holds everything the image depends on (the
//! static study's names spell the settings out and add a hash of the renderer and
//! the scene, [`scene_key`]; the motion study's hash the pose too, [`pose_key`]).
//! Without the renderer's hash a reference cached before a change to the kernels
//! would be read back after it, and every figure measured against it would carry
//! the difference as error.

use super::config::StudyConfig;
use anyhow::{ensure, Result};
use glam::{Vec3, Vec4};
use gpu_tracer::cpu;
use gpu_tracer::scene::{SceneGpu, TraceSettings};
use kernels::abi::SEED_MODE_FIXED;
use sampler_core::luma;
use std::path::{Path, PathBuf};

/// The reference image: two independent halves.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Side in pixels.
    pub size: u32,
    /// Total samples per pixel.
    pub spp: u32,
    /// Mean of both halves, linear RGB, row-major.
    pub rgb: Vec<Vec3>,
    /// Luma of [`Self::rgb`].
    pub luma: Vec<f32>,
    /// Estimated variance of the reference's luma per pixel, averaged over the image:
    /// `mean((A - B)^2) / 4`.
    pub noise_var: f64,
    /// The same estimate per pixel, `(A - B)^2 / 4` (unbiased but noisy: sum it over
    /// regions), row-major.
    pub noise: Vec<f32>,
}

const CACHE_MAGIC: &[u8; 8] = b"BNREF01\0";

impl Reference {
    /// Renders (or loads from `cache_dir`) the reference for `config`. The file name
    /// holds every setting the image depends on, and [`scene_key`]: a reference
    /// rendered by another renderer or of another scene is never read back.
    ///
    /// # Errors
    /// Rendering errors; cache I/O errors are ignored (the image is then rendered).
    pub fn get(
        scene: &SceneGpu,
        config: &StudyConfig,
        cache_dir: Option<&Path>,
        progress: impl FnMut(u32, u32),
    ) -> Result<Reference> {
        let regularized = if config.glossy_regularization > 0.0 {
            format!("-reg{}", config.glossy_regularization)
        } else {
            String::new()
        };
        let name = format!(
            "{scene}-ref-{s}x{s}-spp{r}-depth{d}-rr{rr}{regularized}-{key:016x}.bin",
            scene = config.scene.name(),
            s = config.size,
            r = config.ref_spp / 2 * 2,
            d = config.max_depth,
            rr = TraceSettings::new(1, 1).rr_depth,
            key = scene_key(scene),
        );
        Reference::get_named(
            scene,
            config.size,
            config.max_depth,
            config.ref_spp,
            config.scene.environment(),
            config.glossy_regularization,
            &name,
            cache_dir,
            progress,
        )
    }

    /// Renders (or loads from `cache_dir`) a `size x size` reference of `scene` as
    /// posed (its current camera and geometry) with `ref_spp` samples per pixel (two
    /// halves of `ref_spp / 2`), paths of at most `max_depth` segments, cached under
    /// `cache_name`, which must identify the scene, pose and settings (for moving
    /// scenes: [`pose_key`]), with `environment` the constant sky's radiance
    /// (`TraceSettings::environment`) and `glossy_regularization` the path
    /// regularisation (`TraceSettings::glossy_regularization`; 0: the unbiased
    /// image). `progress(done, total)` counts render passes.
    ///
    /// # Errors
    /// `ref_spp < 2` or rendering errors; cache I/O errors are ignored (the image is
    /// then rendered).
    #[allow(clippy::too_many_arguments)]
    pub fn get_named(
        scene: &SceneGpu,
        size: u32,
        max_depth: u32,
        ref_spp: u32,
        environment: Vec3,
        glossy_regularization: f32,
        cache_name: &str,
        cache_dir: Option<&Path>,
        mut progress: impl FnMut(u32, u32),
    ) -> Result<Reference> {
        ensure!(ref_spp >= 2, "the reference needs at least 2 samples per pixel");
        let half_spp = ref_spp / 2;
        let path = cache_dir.map(|d| d.join(cache_name));
        let n = (size * size) as usize;
        if let Some(p) = &path {
            if let Some((a, b)) = read_cache(p, n) {
                return Ok(Reference::from_halves(size, 2 * half_spp, &a, &b));
            }
        }
        let pass_spp = half_spp.min(64);
        let passes = half_spp.div_ceil(pass_spp);
        let mut settings = TraceSettings::new(size, size);
        settings.max_depth = max_depth;
        settings.seed_mode = SEED_MODE_FIXED;
        settings.environment = environment;
        settings.glossy_regularization = glossy_regularization;
        let mut halves = [vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]];
        let mut color = vec![Vec4::ZERO; n];
        let total = 2 * passes;
        let mut done = 0;
        for (h, half) in halves.iter_mut().enumerate() {
            let mut left = half_spp;
            for pass in 0..passes {
                settings.spp = pass_spp.min(left);
                left -= settings.spp;
                let params = scene.trace_params(&settings, 0)?;
                // Salts far from the study's, one per pass and half.
                let salt = 0x5EED_0000 ^ ((h as u32) << 12) ^ pass;
                let seeds = cpu::white_seeds(size, size, salt);
                cpu::render_frame(scene, &params, &seeds, &mut color)?;
                let w = settings.spp as f32 / half_spp as f32;
                for (acc, c) in half.iter_mut().zip(&color) {
                    *acc += c.truncate() * w;
                }
                done += 1;
                progress(done, total);
            }
        }
        if let Some(p) = &path {
            // Best effort: a failed write only costs a re-render next time.
            let _ = write_cache(p, &halves[0], &halves[1]);
        }
        Ok(Reference::from_halves(size, 2 * half_spp, &halves[0], &halves[1]))
    }

    fn from_halves(size: u32, spp: u32, a: &[Vec3], b: &[Vec3]) -> Reference {
        let rgb: Vec<Vec3> = a.iter().zip(b).map(|(x, y)| (*x + *y) * 0.5).collect();
        let luma_image: Vec<f32> = rgb.iter().map(|c| luma(*c)).collect();
        let noise: Vec<f32> = a
            .iter()
            .zip(b)
            .map(|(x, y)| {
                let d = luma(*x) - luma(*y);
                d * d / 4.0
            })
            .collect();
        let noise_var = noise.iter().map(|&v| v as f64).sum::<f64>() / a.len() as f64;
        Reference {
            size,
            spp,
            rgb,
            luma: luma_image,
            noise_var,
            noise,
        }
    }
}

fn read_cache(path: &Path, n: usize) -> Option<(Vec<Vec3>, Vec<Vec3>)> {
    let bytes = std::fs::read(path).ok()?;
    if bytes.len() != 8 + 2 * n * 12 || &bytes[..8] != CACHE_MAGIC {
        return None;
    }
    let floats: Vec<f32> = bytes[8..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    let v: Vec<Vec3> = floats.chunks_exact(3).map(Vec3::from_slice).collect();
    let (a, b) = v.split_at(n);
    Some((a.to_vec(), b.to_vec()))
}

fn write_cache(path: &Path, a: &[Vec3], b: &[Vec3]) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut bytes = Vec::with_capacity(8 + (a.len() + b.len()) * 12);
    bytes.extend_from_slice(CACHE_MAGIC);
    for c in a.iter().chain(b) {
        for v in c.to_array() {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// The default reference cache: `target/quality-cache` of this workspace.
pub fn default_cache_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/quality-cache")
}

/// FNV-1a (64 bits) of `bytes`, continuing from `hash`: stable across runs and
/// platforms, unlike `std`'s hasher.
fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(hash, |h, &b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3))
}

/// FNV-1a's offset basis: the hash of no bytes.
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// A 64-bit fingerprint of the renderer: FNV-1a of the kernels' SPIR-V
/// (`gpu_tracer::gpu::KERNELS_SPV`). The CPU renderer runs the same kernel
/// source natively, and the SPIR-V is rebuilt from it with every change to how
/// paths are traced, so a cached reference whose name holds this key was
/// rendered by the renderer that renders the frames it is compared with.
/// (Between an edit of the kernels and `gpu-tracer/build-shaders.sh` the key
/// lags the CPU renderer; CI checks that the committed SPIR-V is fresh.)
/// Computed once per process.
pub fn renderer_key() -> u64 {
    static KEY: std::sync::OnceLock<u64> = std::sync::OnceLock::new();
    *KEY.get_or_init(|| fnv1a(FNV_OFFSET, gpu_tracer::gpu::KERNELS_SPV))
}

/// A 64-bit key of what a reference of `scene` as posed depends on besides its
/// sample count and path length: the renderer ([`renderer_key`]) and the scene's
/// buffers (triangles, their attributes, materials, texture images, emitters,
/// punctual lights, environment and camera). FNV-1a over their bytes (the GPU
/// structs) or `Debug` text (Rust prints `f32` with enough digits to round-trip),
/// so two scenes share a key only if they render alike.
pub fn scene_key(scene: &SceneGpu) -> u64 {
    let mut h = fnv1a(FNV_OFFSET, &renderer_key().to_le_bytes());
    h = fnv1a(h, bytemuck::cast_slice(&scene.triangles));
    h = fnv1a(h, bytemuck::cast_slice(&scene.attrs));
    h = fnv1a(h, bytemuck::cast_slice(&scene.materials));
    h = fnv1a(h, bytemuck::cast_slice(&scene.images));
    h = fnv1a(
        h,
        bytemuck::cast_slice(&scene.emitters[..scene.emitter_count as usize]),
    );
    h = fnv1a(h, bytemuck::cast_slice(&scene.environment));
    let text = format!(
        "{}|{:?}|{:?}|{:?}",
        scene.image_count, scene.lights, scene.environment_map, scene.camera
    );
    fnv1a(h, text.as_bytes())
}

/// A 64-bit key of everything a reference of `scene` depends on: [`scene_key`]
/// (renderer, scene as posed) and the settings (`size`, `ref_spp`, `max_depth`,
/// the Russian-roulette depth).
pub fn pose_key(scene: &SceneGpu, size: u32, ref_spp: u32, max_depth: u32) -> u64 {
    let text = format!(
        "{size}|{}|{max_depth}|{}",
        ref_spp / 2 * 2,
        TraceSettings::new(1, 1).rr_depth
    );
    fnv1a(scene_key(scene), text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use gpu_tracer::cornell::cornell_box;

    /// The keys name the renderer and everything in the scene a reference
    /// depends on: the same scene gives the same key, a changed material,
    /// emitter or camera another one, and the settings change the pose key.
    #[test]
    fn cache_keys_change_with_the_renderer_scene_and_settings() {
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        assert_eq!(renderer_key(), fnv1a(FNV_OFFSET, gpu_tracer::gpu::KERNELS_SPV));
        assert_ne!(renderer_key(), FNV_OFFSET, "the kernels' SPIR-V is not empty");
        let key = scene_key(&scene);
        assert_eq!(key, scene_key(&SceneGpu::build(&cornell_box()).unwrap()));
        let mut material = scene.clone();
        material.materials[0].albedo.x *= 0.5;
        let mut emitter = scene.clone();
        emitter.emitters[0] = Default::default();
        let mut camera = scene.clone();
        camera.camera.origin.x += 1e-3;
        for (what, other) in [("material", material), ("emitter", emitter), ("camera", camera)] {
            assert_ne!(scene_key(&other), key, "{what}");
        }
        let pose = pose_key(&scene, 64, 128, 8);
        assert_eq!(pose, pose_key(&scene, 64, 129, 8), "odd spp round down to halves");
        for other in [
            pose_key(&scene, 32, 128, 8),
            pose_key(&scene, 64, 256, 8),
            pose_key(&scene, 64, 128, 3),
        ] {
            assert_ne!(other, pose);
        }
    }
}
