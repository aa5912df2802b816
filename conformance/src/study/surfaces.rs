//! The interior's history split by what the pixel sees first: a glossy
//! surface or a diffuse one (issue 29's diagnostic for the glossy box,
//! where the render defaults are white in time in the interior while the
//! diffuse Cornell box keeps 0.85 of white's error).
//!
//! Glossy and diffuse first hits as [`crate::metrics::surfaces`] defines
//! them, classified once from the still camera's frame-0 G-buffer
//! ([`super::Study::glossy`]); the history records the interior's squared
//! error for each ([`super::HistoryErrors::ema_interior_by_surface`]).

use super::history::{EMA_ALPHA, EMA_FROM};
use super::method::Method;
use super::result::StudyResult;
use crate::metrics::surfaces::GLOSSY_ROUGHNESS;

impl StudyResult {
    /// RMSE of `method`'s history (EMA alone) over frames [`EMA_FROM`].. on
    /// the interior's glossy (`glossy`) or diffuse first hits, relative to
    /// white noise's. `None` for a missing run, too few frames or no such pixel.
    pub fn history_by_surface(&self, method: Method, glossy: bool) -> Option<f64> {
        let k = usize::from(!glossy);
        let sum = |m: Method| -> Option<f64> {
            let e = &self.run(m)?.history.ema_interior_by_surface;
            (e.len() > EMA_FROM).then(|| e[EMA_FROM..].iter().map(|v| v[k]).sum())
        };
        let (m, w) = (sum(method)?, sum(Method::White)?);
        (w > 0.0).then(|| (m / w).sqrt())
    }

    /// The share of `method`'s squared history error (EMA alone, frames
    /// [`EMA_FROM`]..) in the interior that falls on glossy first hits.
    /// `None` for a missing run, too few frames or no interior error.
    pub fn glossy_error_share(&self, method: Method) -> Option<f64> {
        let e = &self.run(method)?.history.ema_interior_by_surface;
        let (g, d) = e
            .get(EMA_FROM..)?
            .iter()
            .fold((0.0, 0.0), |(g, d), v| (g + v[0], d + v[1]));
        (g + d > 0.0).then(|| g / (g + d))
    }

    /// Markdown table of [`Self::history_by_surface`] per method, with the
    /// glossy share of the interior; empty when the interior has no glossy
    /// first hit.
    pub fn surfaces_markdown(&self) -> String {
        if self.glossy_interior_share <= 0.0 {
            return String::new();
        }
        let cell = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
        let error_share = self
            .glossy_error_share(Method::White)
            .map_or("-".to_string(), |v| format!("{:.1}%", 100.0 * v));
        let mut s = format!(
            "\nThe interior's history by first hit (EMA {EMA_ALPHA}, white = 1; glossy: metallic-roughness, \
             roughness < {GLOSSY_ROUGHNESS}: {:.1}% of the interior's pixels, {error_share} of white's squared \
             error there after the EMA):\n\n\
             | method | EMA interior, glossy first hits | EMA interior, diffuse first hits |\n|---|---|---|\n",
            100.0 * self.glossy_interior_share
        );
        for r in &self.runs {
            s += &format!(
                "| {} | {} | {} |\n",
                r.method.name(),
                cell(self.history_by_surface(r.method, true)),
                cell(self.history_by_surface(r.method, false))
            );
        }
        s
    }
}
