//! Environment maps ([`EnvironmentMap`]): equirectangular images of the
//! radiance arriving from infinitely far away, what rays that leave the
//! scene see. Conventions (which texel is which direction, rotation) are
//! `sampler_core::distributions::environment`'s: +Y up, the image's top row
//! is +Y, its centre column looks down -Z, `u` grows to the viewer's right.

use crate::error::{Error, Result};
use glam::Vec3;
use sampler_core::limits::MAX_DISTRIBUTION_SIDE;
use sampler_core::EnvironmentParams;

/// An equirectangular environment map in linear RGB radiance (the same unit
/// as emissive surfaces), with its rotation about +Y.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Name for messages (the file's path).
    pub name: String,
    /// Texels per row, `1..=MAX_DISTRIBUTION_SIDE` (32768).
    pub width: u32,
    /// Rows, `1..=MAX_DISTRIBUTION_SIDE`; the top row looks up (+Y).
    pub height: u32,
    /// Row-major linear RGB radiance from the top-left texel, `width *
    /// height` entries, each channel finite and `>= 0`.
    pub texels: Vec<[f32; 3]>,
    /// Rotation about +Y in degrees (any finite value): a positive angle
    /// turns the map's content to the viewer's right (clockwise seen from
    /// above).
    pub rotation_degrees: f32,
}

impl EnvironmentMap {
    /// A map of one radiance in every direction (a `2 x 1` image): the same
    /// light as the constant sky `radiance`, but importance-sampled.
    pub fn constant(radiance: Vec3) -> EnvironmentMap {
        EnvironmentMap {
            name: format!("constant {radiance}"),
            width: 2,
            height: 1,
            texels: vec![radiance.to_array(); 2],
            rotation_degrees: 0.0,
        }
    }

    /// Checks the size, the texel count and every texel
    /// ([`Error::InvalidEnvironmentMap`] says what is wrong).
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| {
            Err(Error::InvalidEnvironmentMap {
                name: self.name.clone(),
                reason,
            })
        };
        let side = 1..=MAX_DISTRIBUTION_SIDE;
        if !side.contains(&self.width) || !side.contains(&self.height) {
            return bad(format!(
                "{}x{} texels: each side must be 1 to {MAX_DISTRIBUTION_SIDE}",
                self.width, self.height
            ));
        }
        let want = self.width as usize * self.height as usize;
        if self.texels.len() != want {
            return bad(format!(
                "{} texels for a {}x{} map",
                self.texels.len(),
                self.width,
                self.height
            ));
        }
        if let Some(i) = self
            .texels
            .iter()
            .position(|t| !t.iter().all(|c| c.is_finite() && *c >= 0.0))
        {
            let (x, y) = (i % self.width as usize, i / self.width as usize);
            return bad(format!(
                "texel ({x}, {y}) is {:?}: radiance must be finite and >= 0",
                self.texels[i]
            ));
        }
        if !self.rotation_degrees.is_finite() {
            return bad(format!(
                "rotation {} degrees is not finite",
                self.rotation_degrees
            ));
        }
        Ok(())
    }

    /// The rotation in turns, in `[0, 1)` (what the kernels take).
    pub fn rotation_turns(&self) -> f32 {
        (self.rotation_degrees as f64 / 360.0).rem_euclid(1.0) as f32
    }

    /// The buffer the kernels read at binding 10 (the sampling table of
    /// `sampler_core::EnvironmentMap`, then the texels, three `f32` each)
    /// and the map's shape and rotation for `TraceParams::environment_map`.
    /// Assumes [`EnvironmentMap::validate`] passed.
    pub fn buffer(&self) -> Result<(Vec<f32>, EnvironmentParams)> {
        let table_len = sampler_core::EnvironmentMap::table_len(self.width, self.height);
        let mut data = vec![0.0f32; table_len + 3 * self.texels.len()];
        let (table, texels) = data.split_at_mut(table_len);
        let map = sampler_core::EnvironmentMap::build(self.width, self.height, &self.texels, table)
            .map_err(|e| Error::InvalidEnvironmentMap {
                name: self.name.clone(),
                reason: e.to_string(),
            })?
            .with_rotation_turns(self.rotation_turns());
        let params = map.params();
        for (slot, t) in texels.chunks_exact_mut(3).zip(&self.texels) {
            slot.copy_from_slice(t);
        }
        Ok((data, params))
    }

    /// Mean over all directions (weighted by solid angle) of the mean of
    /// the three channels: the radiance of the constant sky that would
    /// emit the same power. Assumes [`EnvironmentMap::validate`] passed.
    pub fn mean_radiance(&self) -> f64 {
        let (w, h) = (self.width as usize, self.height as usize);
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for y in 0..h {
            let sin_theta = (std::f64::consts::PI * (y as f64 + 0.5) / h as f64).sin();
            for t in &self.texels[y * w..(y + 1) * w] {
                sum += sin_theta * (t[0] as f64 + t[1] as f64 + t[2] as f64) / 3.0;
            }
            weight += sin_theta * w as f64;
        }
        sum / weight
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_maps_are_refused_with_the_reason() {
        let ok = EnvironmentMap::constant(Vec3::new(1.0, 2.0, 3.0));
        assert!(ok.validate().is_ok());
        assert!((ok.mean_radiance() - 2.0).abs() < 1e-9);
        let cases = [
            (
                EnvironmentMap {
                    width: 0,
                    ..ok.clone()
                },
                "each side",
            ),
            (
                EnvironmentMap {
                    width: 3,
                    ..ok.clone()
                },
                "texels for",
            ),
            (
                EnvironmentMap {
                    texels: vec![[0.0; 3], [1.0, f32::NAN, 0.0]],
                    ..ok.clone()
                },
                "texel (1, 0)",
            ),
            (
                EnvironmentMap {
                    texels: vec![[0.0; 3], [-1.0, 0.0, 0.0]],
                    ..ok.clone()
                },
                "texel (1, 0)",
            ),
            (
                EnvironmentMap {
                    texels: vec![[0.0; 3], [f32::INFINITY, 0.0, 0.0]],
                    ..ok.clone()
                },
                "finite",
            ),
            (
                EnvironmentMap {
                    rotation_degrees: f32::NAN,
                    ..ok.clone()
                },
                "rotation",
            ),
        ];
        for (map, want) in cases {
            let msg = map.validate().unwrap_err().to_string();
            assert!(msg.contains(want) && msg.contains("environment map"), "{msg}");
        }
        // The NaN case names the right texel: (0, 0) holds the NaN.
        let nan_first = EnvironmentMap {
            texels: vec![[f32::NAN, 0.0, 0.0], [0.0; 3]],
            ..ok.clone()
        };
        assert!(nan_first
            .validate()
            .unwrap_err()
            .to_string()
            .contains("texel (0, 0)"));
        let turned = EnvironmentMap {
            rotation_degrees: -90.0,
            ..ok
        };
        assert_eq!(turned.rotation_turns(), 0.75);
    }
}
