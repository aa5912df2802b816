//! Sort keys of the feature-aware permutation on the CPU (issue 14, item 1):
//! what the sorting pass ranks, per pixel, so that it sorts the noise a seed
//! controls rather than the image's content.
//!
//! - [`FeatureKey::Demodulated`] (the default, and what the GPU computes in
//!   `features_cs`): `luma(radiance) / luma(albedo)` of the primary hit
//!   (`kernels::surface_features::demodulated_intensity`): on a textured
//!   surface the key follows the irradiance, not the texture.
//! - [`FeatureKey::Raw`]: `luma(radiance)`, the plain permutation's key, kept to
//!   measure what demodulation buys.
//! - [`FeatureKey::HistoryResidual`]: the demodulated value minus a smoothed
//!   history of it: an exponential running mean per pixel (weight
//!   `max(1 / (n + 1), 1 / 32)` for the pixel's `n`-th frame on its surface,
//!   so the first frames average equally), averaged over the 3x3 neighbours
//!   on the same surface. The history estimates the noise-free signal, so the
//!   residual is (nearly) the frame's noise: shading gradients inside a block
//!   no longer decide the order. A pixel whose surface changed since the last
//!   frame (`sampler_core::same_surface` fails against its previous feature)
//!   restarts its history; with a moving camera that is every disoccluded or
//!   newly covered pixel (the history is kept in screen space, not
//!   reprojected). CPU only.

use glam::Vec4;
use kernels::abi::GBufferGpu;
use kernels::surface_features::{demodulated_intensity, surface_feature};
use sampler_core::{same_surface, FeatureThresholds, Intensity, SurfaceFeature};

/// Which value the feature-aware sorting pass ranks (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FeatureKey {
    /// Radiance luma over albedo luma (the GPU's key).
    #[default]
    Demodulated,
    /// Radiance luma.
    Raw,
    /// Demodulated value minus its smoothed running mean.
    HistoryResidual,
}

impl FeatureKey {
    /// Every key.
    pub const ALL: [FeatureKey; 3] = [
        FeatureKey::Demodulated,
        FeatureKey::Raw,
        FeatureKey::HistoryResidual,
    ];

    /// Name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FeatureKey::Demodulated => "demodulated",
            FeatureKey::Raw => "raw",
            FeatureKey::HistoryResidual => "history",
        }
    }

    /// The key called `name` ([`FeatureKey::name`]).
    pub fn from_name(name: &str) -> Option<FeatureKey> {
        FeatureKey::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Smallest weight of a new frame in the running mean of
/// [`FeatureKey::HistoryResidual`].
pub const HISTORY_MIN_WEIGHT: f32 = 1.0 / 32.0;

/// Per-frame features and keys of a `width x height` frame, with the history
/// [`FeatureKey::HistoryResidual`] keeps.
#[derive(Clone, Debug)]
pub struct FeatureKeys {
    key: FeatureKey,
    width: usize,
    height: usize,
    thresholds: FeatureThresholds,
    /// This frame's features (`width * height`).
    features: Vec<SurfaceFeature>,
    /// This frame's keys (`width * height`).
    keys: Vec<f32>,
    /// Running mean of the demodulated value, and frames in it (history key).
    mean: Vec<f32>,
    count: Vec<u32>,
    previous: Vec<SurfaceFeature>,
    demodulated: Vec<f32>,
}

impl FeatureKeys {
    /// Keys of type `key` for frames of `width x height` pixels, surfaces
    /// told apart with `thresholds`.
    pub fn new(key: FeatureKey, width: u32, height: u32, thresholds: FeatureThresholds) -> Self {
        let n = (width * height) as usize;
        let history = if key == FeatureKey::HistoryResidual { n } else { 0 };
        FeatureKeys {
            key,
            width: width as usize,
            height: height as usize,
            thresholds,
            features: vec![SurfaceFeature::default(); n],
            keys: vec![0.0; n],
            mean: vec![0.0; history],
            count: vec![0; history],
            previous: vec![SurfaceFeature::none(); history],
            demodulated: vec![0.0; history],
        }
    }

    /// The features of the last [`Self::update`].
    pub fn features(&self) -> &[SurfaceFeature] {
        &self.features
    }

    /// The keys of the last [`Self::update`].
    pub fn keys(&self) -> &[f32] {
        &self.keys
    }

    /// Computes the features and keys of a frame from its colour and G-buffer
    /// (both `width * height`), then folds the frame into the history.
    ///
    /// # Panics
    /// If a buffer's length is not `width * height`.
    pub fn update(&mut self, color: &[Vec4], gbuffer: &[GBufferGpu]) {
        let n = self.width * self.height;
        assert_eq!(color.len(), n, "colour buffer length");
        assert_eq!(gbuffer.len(), n, "G-buffer length");
        for (f, g) in self.features.iter_mut().zip(gbuffer) {
            *f = surface_feature(g);
        }
        match self.key {
            FeatureKey::Demodulated => {
                for ((k, g), c) in self.keys.iter_mut().zip(gbuffer).zip(color) {
                    *k = demodulated_intensity(*c, g);
                }
            }
            FeatureKey::Raw => {
                for (k, c) in self.keys.iter_mut().zip(color) {
                    *k = c.intensity();
                }
            }
            FeatureKey::HistoryResidual => self.history_residual(color, gbuffer),
        }
    }

    fn history_residual(&mut self, color: &[Vec4], gbuffer: &[GBufferGpu]) {
        let (w, h) = (self.width, self.height);
        for i in 0..w * h {
            self.demodulated[i] = demodulated_intensity(color[i], &gbuffer[i]);
            if !same_surface(&self.features[i], &self.previous[i], &self.thresholds) {
                self.count[i] = 0;
            }
        }
        // Key: value minus the same-surface 3x3 mean of the history (before
        // this frame); pixels without history keep their value.
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let (mut sum, mut taps) = (0.0f32, 0u32);
                for ny in y.saturating_sub(1)..(y + 2).min(h) {
                    for nx in x.saturating_sub(1)..(x + 2).min(w) {
                        let j = ny * w + nx;
                        if self.count[j] > 0
                            && same_surface(&self.features[i], &self.features[j], &self.thresholds)
                        {
                            sum += self.mean[j];
                            taps += 1;
                        }
                    }
                }
                let d = self.demodulated[i];
                self.keys[i] = if taps > 0 { d - sum / taps as f32 } else { d };
            }
        }
        for i in 0..w * h {
            let n = self.count[i];
            let weight = (1.0 / (n as f32 + 1.0)).max(HISTORY_MIN_WEIGHT);
            let d = self.demodulated[i];
            self.mean[i] = if n == 0 {
                d
            } else {
                self.mean[i] + weight * (d - self.mean[i])
            };
            self.count[i] = n.saturating_add(1);
        }
        self.previous.copy_from_slice(&self.features);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec3};
    use kernels::abi::{GBUFFER_HIT, GBUFFER_NO_HIT};

    fn gbuffer(n: usize, albedo: f32) -> Vec<GBufferGpu> {
        (0..n)
            .map(|_| GBufferGpu {
                normal_depth: Vec3::Z.extend(5.0),
                albedo: Vec3::splat(albedo).extend(0.0),
                ids: UVec4::new(1, 0, 0, GBUFFER_HIT),
                ..GBufferGpu::default()
            })
            .collect()
    }

    #[test]
    fn keys_follow_their_definitions() {
        let (w, h) = (4u32, 3u32);
        let n = (w * h) as usize;
        let g = gbuffer(n, 0.5);
        let color: Vec<Vec4> = (0..n).map(|i| Vec4::splat(0.1 * i as f32)).collect();
        let mut raw = FeatureKeys::new(FeatureKey::Raw, w, h, FeatureThresholds::DEFAULT);
        raw.update(&color, &g);
        let mut demod = FeatureKeys::new(FeatureKey::Demodulated, w, h, FeatureThresholds::DEFAULT);
        demod.update(&color, &g);
        for i in 0..n {
            assert!((raw.keys()[i] - 0.1 * i as f32).abs() < 1e-5);
            assert!((demod.keys()[i] - 0.2 * i as f32).abs() < 1e-5);
        }
        assert_eq!(raw.features(), demod.features());
        assert_ne!(GBUFFER_NO_HIT, raw.features()[0].id);
    }

    #[test]
    fn history_residual_removes_the_signal_and_restarts_on_new_surfaces() {
        let (w, h) = (5u32, 4u32);
        let n = (w * h) as usize;
        let mut g = gbuffer(n, 1.0);
        // A fixed gradient across the frame: the signal.
        let signal: Vec<f32> = (0..n).map(|i| (i % 5) as f32).collect();
        let mut keys = FeatureKeys::new(FeatureKey::HistoryResidual, w, h, FeatureThresholds::DEFAULT);
        let frame = |s: &[f32]| -> Vec<Vec4> { s.iter().map(|v| Vec4::splat(*v)).collect() };
        keys.update(&frame(&signal), &g);
        // Frame 0: no history, the key is the value.
        assert!((keys.keys()[7] - signal[7]).abs() < 1e-6);
        keys.update(&frame(&signal), &g);
        // Interior pixel: the 3x3 mean of a linear ramp is the pixel's own value.
        let i = 2 * 5 + 2;
        assert!(keys.keys()[i].abs() < 1e-5, "{}", keys.keys()[i]);
        // Add noise to one pixel: the key is that noise.
        let mut noisy = signal.clone();
        noisy[i] += 0.75;
        keys.update(&frame(&noisy), &g);
        assert!((keys.keys()[i] - 0.75).abs() < 1e-5, "{}", keys.keys()[i]);
        // A pixel that changes surface restarts: its key is its value again.
        g[i].ids.x = 9;
        keys.update(&frame(&signal), &g);
        assert!((keys.keys()[i] - signal[i]).abs() < 1e-6, "{}", keys.keys()[i]);
    }
}
