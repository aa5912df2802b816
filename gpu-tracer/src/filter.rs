//! The real-time filters between a noisy frame and the viewer, on the CPU:
//! [`FrameFilter`] runs the kernels' per-pixel filter functions
//! (`kernels::filters`, the same code the GPU runs) over whole frames with
//! rayon and keeps the temporal history between frames.
//!
//! Chains ([`FilterChain`]): `taa` (reprojected exponential history with
//! neighbourhood clamping), `gauss` (separable Gaussian), `atrous` (SVGF's
//! edge-avoiding a-trous, 5 iterations), and `taa+atrous` (SVGF's order:
//! temporal accumulation, then the spatial filter). `taa`, `atrous` and
//! `taa+atrous` filter the illumination demodulated by the G-buffer's
//! albedo and multiply it back; the temporal history is kept demodulated.

use crate::error::{Error, Result};
use glam::{UVec2, Vec2, Vec4};
use kernels::abi::GBufferGpu;
use kernels::filters::atrous::{atrous_pixel, variance_pixel, ATROUS_ITERATIONS};
use kernels::filters::demodulate::{demodulate, remodulate};
use kernels::filters::gauss::gauss_pass_pixel;
use kernels::filters::taa::taa_pixel;
use kernels::filters::{FilterParams, FILTER_CLAMP, FILTER_HISTORY_VALID};
use rayon::prelude::*;
use std::fmt;
use std::str::FromStr;

/// Which filters run after each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FilterChain {
    /// The raw frame.
    None,
    /// Temporal accumulation only.
    Taa,
    /// A Gaussian blur only.
    Gauss,
    /// The a-trous filter only.
    Atrous,
    /// Temporal accumulation, then the a-trous filter.
    TaaAtrous,
}

impl FilterChain {
    /// Every chain, in the order of the tracer's help.
    pub const ALL: [FilterChain; 5] = [
        FilterChain::None,
        FilterChain::Taa,
        FilterChain::Gauss,
        FilterChain::Atrous,
        FilterChain::TaaAtrous,
    ];

    /// The name on the command line: `none`, `taa`, `gauss`, `atrous`,
    /// `taa+atrous`.
    pub fn name(self) -> &'static str {
        match self {
            FilterChain::None => "none",
            FilterChain::Taa => "taa",
            FilterChain::Gauss => "gauss",
            FilterChain::Atrous => "atrous",
            FilterChain::TaaAtrous => "taa+atrous",
        }
    }

    /// Whether the chain keeps a temporal history.
    pub fn temporal(self) -> bool {
        matches!(self, FilterChain::Taa | FilterChain::TaaAtrous)
    }

    /// Whether the chain runs the a-trous filter.
    pub fn atrous(self) -> bool {
        matches!(self, FilterChain::Atrous | FilterChain::TaaAtrous)
    }
}

impl fmt::Display for FilterChain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FilterChain {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        FilterChain::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| format!("unknown filter `{s}`: expected none, taa, gauss, atrous or taa+atrous"))
    }
}

/// The filters' settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSettings {
    /// Weight of the current frame in the temporal history, in `(0, 1]`;
    /// 0.1 by default (the usual TAA blend).
    pub alpha: f32,
    /// Clamp the history to the current 3x3 neighbourhood's colour box
    /// (default on).
    pub clamp: bool,
    /// Sigma of the Gaussian in pixels, in `(0, 4]` (1 by default).
    pub sigma: f32,
}

impl Default for FilterSettings {
    fn default() -> Self {
        FilterSettings {
            alpha: 0.1,
            clamp: true,
            sigma: 1.0,
        }
    }
}

impl FilterSettings {
    /// Checks the ranges of the fields.
    ///
    /// # Errors
    /// [`Error::InvalidSetting`] for `alpha` outside `(0, 1]` or `sigma`
    /// outside `(0, 4]` (NaN included).
    pub fn check(&self) -> Result<()> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(Error::InvalidSetting {
                name: "alpha",
                value: self.alpha,
                expected: "a weight in (0, 1]",
            });
        }
        if !(self.sigma > 0.0 && self.sigma <= 4.0) {
            return Err(Error::InvalidSetting {
                name: "sigma",
                value: self.sigma,
                expected: "pixels in (0, 4]",
            });
        }
        Ok(())
    }
}

/// Checks that the three inputs of a filter hold `n` pixels each.
///
/// # Errors
/// [`Error::BufferSize`] naming the first that does not.
pub fn check_inputs(n: usize, color: &[Vec4], gbuffer: &[GBufferGpu], motion: &[Vec2]) -> Result<()> {
    for (buffer, len) in [
        ("color", color.len()),
        ("gbuffer", gbuffer.len()),
        ("motion", motion.len()),
    ] {
        if len != n {
            return Err(Error::BufferSize {
                buffer,
                expected: n,
                actual: len,
            });
        }
    }
    Ok(())
}

/// A filter chain over a `width x height` frame sequence, with its history.
#[derive(Clone, Debug)]
pub struct FrameFilter {
    chain: FilterChain,
    settings: FilterSettings,
    width: u32,
    height: u32,
    /// The previous temporal output, demodulated (valid when `has_history`).
    history: Vec<Vec4>,
    has_history: bool,
}

impl FrameFilter {
    /// A filter with an empty history.
    ///
    /// # Errors
    /// [`Error::FrameSize`] for a zero size, [`Error::InvalidSetting`] for
    /// `alpha` outside `(0, 1]` or `sigma` outside `(0, 4]` (NaN included).
    pub fn new(chain: FilterChain, settings: FilterSettings, width: u32, height: u32) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::FrameSize {
                width,
                height,
                padded_width: width,
            });
        }
        settings.check()?;
        Ok(FrameFilter {
            chain,
            settings,
            width,
            height,
            history: Vec::new(),
            has_history: false,
        })
    }

    /// The chain.
    pub fn chain(&self) -> FilterChain {
        self.chain
    }

    /// Forgets the history (a camera cut): the next frame starts it anew.
    pub fn reset(&mut self) {
        self.has_history = false;
    }

    /// Filters the next frame: `color` (linear RGB in `xyz`), its G-buffer
    /// and the backward motion of every pixel (`kernels::motion`'s form:
    /// disoccluded pixels far outside the frame; zeros for a still camera).
    /// Returns the filtered frame (`w` = 1).
    ///
    /// # Errors
    /// [`Error::BufferSize`] when a buffer is not `width * height` long.
    pub fn apply(&mut self, color: &[Vec4], gbuffer: &[GBufferGpu], motion: &[Vec2]) -> Result<Vec<Vec4>> {
        let n = self.width as usize * self.height as usize;
        check_inputs(n, color, gbuffer, motion)?;
        let params = FilterParams {
            width: self.width,
            height: self.height,
            ..Default::default()
        };
        let albedo = |i: usize| gbuffer[i].albedo.truncate();
        let mut frame: Vec<Vec4> = match self.chain {
            FilterChain::None => return Ok(color.iter().map(|c| c.truncate().extend(1.0)).collect()),
            FilterChain::Gauss => {
                let p = FilterParams {
                    weight: self.settings.sigma,
                    ..params
                };
                let rows = self.map(|x, y| gauss_pass_pixel(&FilterParams { step: 0, ..p }, x, y, color));
                let out = self.map(|x, y| gauss_pass_pixel(&FilterParams { step: 1, ..p }, x, y, &rows));
                return Ok(out.into_iter().map(|c| c.truncate().extend(1.0)).collect());
            }
            _ => (0..n)
                .into_par_iter()
                .map(|i| demodulate(color[i], albedo(i)))
                .collect(),
        };
        if self.chain.temporal() {
            let p = FilterParams {
                weight: self.settings.alpha,
                flags: if self.has_history { FILTER_HISTORY_VALID } else { 0 }
                    | if self.settings.clamp { FILTER_CLAMP } else { 0 },
                ..params
            };
            let history = std::mem::take(&mut self.history);
            frame = self.map(|x, y| taa_pixel(&p, x, y, &frame, &history, motion));
            self.history.clone_from(&frame);
            self.has_history = true;
        }
        if self.chain.atrous() {
            frame = self.map(|x, y| variance_pixel(&params, x, y, &frame, gbuffer));
            for it in 0..ATROUS_ITERATIONS {
                let p = FilterParams {
                    step: 1 << it,
                    ..params
                };
                frame = self.map(|x, y| atrous_pixel(&p, x, y, &frame, gbuffer));
            }
        }
        Ok((0..n)
            .into_par_iter()
            .map(|i| remodulate(frame[i], albedo(i)).truncate().extend(1.0))
            .collect())
    }

    /// `f(x, y)` for every pixel, row-major, rows in parallel.
    fn map(&self, f: impl Fn(u32, u32) -> Vec4 + Sync) -> Vec<Vec4> {
        let w = self.width;
        let mut out = vec![Vec4::ZERO; w as usize * self.height as usize];
        out.par_chunks_mut(w as usize).enumerate().for_each(|(y, row)| {
            for (x, v) in row.iter_mut().enumerate() {
                *v = f(x as u32, y as u32);
            }
        });
        out
    }
}

/// A [`FrameFilter`] fed by a frame sequence's colour and G-buffer alone:
/// it derives each frame's motion vectors itself
/// ([`crate::motion::reprojection_motion`] against the previous frame's
/// visibility), so a renderer that hands over colour and G-buffer per frame
/// gets the reprojected, disocclusion-aware history.
#[derive(Clone, Debug)]
pub struct SequenceFilter {
    filter: FrameFilter,
    previous: Option<Vec<UVec2>>,
}

impl SequenceFilter {
    /// A sequence filter over `width x height` frames.
    ///
    /// # Errors
    /// As [`FrameFilter::new`].
    pub fn new(chain: FilterChain, settings: FilterSettings, width: u32, height: u32) -> Result<Self> {
        Ok(SequenceFilter {
            filter: FrameFilter::new(chain, settings, width, height)?,
            previous: None,
        })
    }

    /// Filters the next frame of the sequence.
    ///
    /// # Errors
    /// [`Error::BufferSize`] when `color` or `gbuffer` is not `width *
    /// height` long.
    pub fn next(&mut self, color: &[Vec4], gbuffer: &[GBufferGpu]) -> Result<Vec<Vec4>> {
        let (w, h) = (self.filter.width, self.filter.height);
        let n = w as usize * h as usize;
        if gbuffer.len() != n {
            return Err(Error::BufferSize {
                buffer: "gbuffer",
                expected: n,
                actual: gbuffer.len(),
            });
        }
        let motion: Vec<Vec2> = match &self.previous {
            Some(previous) => crate::motion::reprojection_motion(gbuffer, previous, w, h)
                .into_iter()
                .map(Vec2::from)
                .collect(),
            None => vec![Vec2::ZERO; n],
        };
        let out = self.filter.apply(color, gbuffer, &motion)?;
        let previous = self.previous.get_or_insert_with(|| vec![UVec2::ZERO; n]);
        crate::motion::write_visibility(gbuffer, previous);
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec3};
    use kernels::abi::{GBUFFER_HIT, GBUFFER_PREV_IN_FRONT};

    fn flat_scene(w: u32, h: u32) -> Vec<GBufferGpu> {
        vec![
            GBufferGpu {
                normal_depth: Vec4::new(0.0, 0.0, 1.0, 3.0),
                albedo: Vec4::new(0.5, 0.25, 1.0, 0.0),
                // Seen in the previous frame at the same depth: a still camera.
                motion: Vec4::new(0.0, 0.0, 3.0, 0.0),
                ids: UVec4::new(0, 0, 0, GBUFFER_HIT | GBUFFER_PREV_IN_FRONT),
            };
            (w * h) as usize
        ]
    }

    fn noisy(w: u32, h: u32, frame: u32) -> Vec<Vec4> {
        (0..w * h)
            .map(|i| {
                let h = sampler_core::sequences::seed::hash_u32(i ^ frame.wrapping_mul(0x9e37_79b9));
                let v = (h >> 8) as f32 / (1u32 << 24) as f32;
                (Vec3::new(0.5, 0.25, 1.0) * (0.5 + v)).extend(1.0)
            })
            .collect()
    }

    #[test]
    fn every_chain_lowers_the_error_of_noise_on_a_flat_surface() {
        let (w, h) = (32u32, 32u32);
        let g = flat_scene(w, h);
        let still = vec![Vec2::ZERO; (w * h) as usize];
        let truth = Vec3::new(0.5, 0.25, 1.0);
        let rms = |f: &[Vec4]| {
            (f.iter()
                .map(|c| (c.truncate() - truth).length_squared())
                .sum::<f32>()
                / f.len() as f32)
                .sqrt()
        };
        let raw = rms(&noisy(w, h, 7));
        for chain in FilterChain::ALL {
            let mut filter = FrameFilter::new(chain, FilterSettings::default(), w, h).unwrap();
            let mut out = Vec::new();
            for t in 0..8 {
                out = filter.apply(&noisy(w, h, t), &g, &still).unwrap();
            }
            let e = rms(&out);
            assert!(out.iter().all(|c| c.is_finite() && c.w == 1.0), "{chain}");
            if chain == FilterChain::None {
                assert!((e - rms(&noisy(w, h, 7))).abs() < 1e-6);
            } else {
                assert!(e < 0.7 * raw, "{chain}: {e} vs raw {raw}");
            }
        }
    }

    #[test]
    fn bad_input_is_refused() {
        let s = FilterSettings::default();
        assert!(matches!(
            FrameFilter::new(FilterChain::Taa, s, 0, 4),
            Err(Error::FrameSize { .. })
        ));
        for alpha in [0.0, 1.5, f32::NAN] {
            let bad = FilterSettings { alpha, ..s };
            assert!(matches!(
                FrameFilter::new(FilterChain::Taa, bad, 4, 4),
                Err(Error::InvalidSetting { name: "alpha", .. })
            ));
        }
        let bad = FilterSettings { sigma: f32::NAN, ..s };
        assert!(FrameFilter::new(FilterChain::Gauss, bad, 4, 4).is_err());
        let mut f = FrameFilter::new(FilterChain::Taa, s, 4, 4).unwrap();
        let err = f.apply(&[Vec4::ZERO; 15], &flat_scene(4, 4), &[Vec2::ZERO; 16]);
        assert!(matches!(err, Err(Error::BufferSize { buffer: "color", .. })));
        let no_clamp = FilterSettings { clamp: false, ..s };
        let mut seq = SequenceFilter::new(FilterChain::Taa, no_clamp, 4, 4).unwrap();
        assert!(matches!(
            seq.next(&[Vec4::ZERO; 16], &flat_scene(4, 3)),
            Err(Error::BufferSize {
                buffer: "gbuffer",
                ..
            })
        ));
        let first = seq.next(&[Vec4::ONE; 16], &flat_scene(4, 4)).unwrap();
        let second = seq.next(&[Vec4::ZERO; 16], &flat_scene(4, 4)).unwrap();
        assert!(
            first[5].x > 0.99 && (second[5].x - 0.9).abs() < 1e-5,
            "{} {}",
            first[5],
            second[5]
        );
        assert_eq!("taa+atrous".parse::<FilterChain>(), Ok(FilterChain::TaaAtrous));
        assert!("blur".parse::<FilterChain>().is_err());
    }
}
