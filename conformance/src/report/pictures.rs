//! The report's pictures that show the difference between methods: a 4x
//! nearest-neighbour zoom of the same crop of frame [`GOAL_FRAME`] for every
//! method, the error after a Gaussian blur (sigma 1 and 2) on one shared
//! grey scale, the accumulated mean after 8 and 64 frames, and a map of the
//! regions and insets the figures use.

use crate::metrics::regions::Region;
use crate::study::{Method, Study, StudyResult, GOAL_FRAME};
use crate::{GaussianBlur, Grid};
use anyhow::{Context, Result};
use glam::Vec4;
use std::fmt::Write as _;
use std::path::Path;

/// Zoom factor of the crops (nearest neighbour).
pub const ZOOM: u32 = 4;

/// The crop every method is shown in: `(x0, y0, side)` in pixels, a quarter
/// of the image around the first inset's centre (it holds flat wall, an edge
/// and usually the light's silhouette at the Cornell box's framing).
pub fn crop_window(study: &Study) -> (u32, u32, u32) {
    let size = study.config.size;
    let side = (size / 4).max(8).min(size);
    let inset = &study.insets[0];
    let (cx, cy) = (inset.x0 + inset.side / 2, inset.y0 + inset.side / 2);
    let x0 = cx.saturating_sub(side / 2).min(size - side);
    let y0 = cy.saturating_sub(side / 2).min(size - side);
    (x0, y0, side)
}

fn save_grey(path: &Path, w: u32, h: u32, data: &[u8]) -> Result<()> {
    image::save_buffer(path, data, w, h, image::ExtendedColorType::L8)
        .with_context(|| format!("cannot write {}", path.display()))
}

fn save_rgb(path: &Path, w: u32, h: u32, data: &[u8]) -> Result<()> {
    image::save_buffer(path, data, w, h, image::ExtendedColorType::Rgb8)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Signed error to grey: 128 = 0, white/black = `+/- scale`.
fn grey(e: f32, scale: f32) -> u8 {
    (127.5 + 127.5 * (e / scale).clamp(-1.0, 1.0)) as u8
}

/// Writes every picture for `result` into `out`, names prefixed by
/// `prefix(method)`; returns the HTML of the pictures' section.
///
/// # Errors
/// No white run; I/O errors.
pub fn write_pictures(
    study: &Study,
    result: &StudyResult,
    out: &Path,
    prefix: impl Fn(Method) -> String,
    css: impl Fn(Method) -> String,
) -> Result<String> {
    let size = study.config.size;
    let n = size as usize;
    let (x0, y0, side) = crop_window(study);
    let spp = study.config.spp;
    let blurs = [GaussianBlur::new(1.0)?, GaussianBlur::new(2.0)?];
    let white = result.run(Method::White).context("white run")?;
    let white_error = Grid::new(n, n, white.snapshot.error.clone())?;
    // One grey scale per blur for every method: 3x white's blurred RMS.
    let scales: Vec<f32> = blurs
        .iter()
        .map(|b| 3.0 * b.apply(&white_error).rms() as f32)
        .collect();
    let mut h = format!(
        "<h2>Pictures, {spp} spp</h2><p>Crop ({x0}, {y0}), {side} px, of frame {f}, zoomed {ZOOM}x (nearest neighbour), \
the same for every method; the luma error after a Gaussian blur of sigma 1 and 2 (grey = 0, white/black = &plusmn;{s1:.3} \
and &plusmn;{s2:.3}: 3x white noise's blurred RMS, one scale for every method); the mean of the first 8 and 64 frames. Each picture is a PNG beside the page; \
<a href=\"#command\">command</a>.</p>\n",
        f = GOAL_FRAME.min(study.config.frames - 1),
        s1 = scales[0],
        s2 = scales[1],
    );
    h += &region_map(study, out, (x0, y0, side))?;
    h += "<table class=\"pictures\"><tr><th>method</th><th>frame (crop)</th><th>blur &sigma;1</th><th>blur &sigma;2</th><th>mean of 8 frames</th><th>mean of 64 frames</th></tr>\n";
    let z = side * ZOOM;
    for run in &result.runs {
        let p = prefix(run.method);
        // The crop, zoomed.
        let crop: Vec<Vec4> = (0..z * z)
            .map(|i| {
                let (x, y) = (x0 + (i % z) / ZOOM, y0 + (i / z) / ZOOM);
                run.snapshot.rgb[(y * size + x) as usize].extend(1.0)
            })
            .collect();
        gpu_tracer::image_out::write_png(out.join(format!("{p}-crop.png")), z, z, &crop, Default::default())?;
        let error = Grid::new(n, n, run.snapshot.error.clone())?;
        for (k, (blur, scale)) in blurs.iter().zip(&scales).enumerate() {
            let b = blur.apply(&error);
            let pixels: Vec<u8> = b.data().iter().map(|&e| grey(e, *scale)).collect();
            save_grey(&out.join(format!("{p}-blur{}.png", k + 1)), size, size, &pixels)?;
        }
        let mut row = format!(
            "<tr><td style=\"color:{}\">{}</td><td><img class=\"crop\" src=\"{p}-crop.png\" alt=\"crop\"></td>\
<td><img src=\"{p}-blur1.png\" alt=\"blur 1\"></td><td><img src=\"{p}-blur2.png\" alt=\"blur 2\"></td>",
            css(run.method),
            run.method.name()
        );
        for target in [8u32, 64] {
            match run.accumulated.iter().find(|(count, _)| *count == target) {
                Some((count, mean)) => {
                    // Luma in [0, 1] shown with a 1/2.2 gamma.
                    let pixels: Vec<u8> = mean
                        .iter()
                        .map(|&v| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) as u8)
                        .collect();
                    let file = format!("{p}-mean{count}.png");
                    save_grey(&out.join(&file), size, size, &pixels)?;
                    let _ = write!(row, "<td><img src=\"{file}\" alt=\"mean of {count}\"></td>");
                }
                None => row += "<td>(fewer frames)</td>",
            }
        }
        h += &row;
        h += "</tr>\n";
    }
    h += "</table>\n";
    Ok(h)
}

/// The region map: emitter zone (yellow), edges (red), interior (grey), the
/// insets (blue outlines) and the crop (green outline); returns its HTML.
fn region_map(study: &Study, out: &Path, (cx, cy, cs): (u32, u32, u32)) -> Result<String> {
    let size = study.config.size;
    let mut rgb: Vec<u8> = study
        .regions
        .iter()
        .flat_map(|r| match r {
            Region::Emitter => [230, 200, 40],
            Region::Edge => [200, 60, 50],
            Region::Interior => [150, 150, 150],
        })
        .collect();
    let mut outline = |x0: u32, y0: u32, side: u32, c: [u8; 3]| {
        for i in 0..side {
            for (x, y) in [
                (x0 + i, y0),
                (x0 + i, y0 + side - 1),
                (x0, y0 + i),
                (x0 + side - 1, y0 + i),
            ] {
                if x < size && y < size {
                    let k = 3 * (y * size + x) as usize;
                    rgb[k..k + 3].copy_from_slice(&c);
                }
            }
        }
    };
    for inset in &study.insets {
        outline(inset.x0, inset.y0, inset.side, [40, 90, 220]);
    }
    outline(cx, cy, cs, [40, 180, 60]);
    let file = format!("spp{}-regions.png", study.config.spp);
    save_rgb(&out.join(&file), size, size, &rgb)?;
    Ok(format!(
        "<figure><img src=\"{file}\" alt=\"regions\"><figcaption>Regions of the tables: emitter zone (yellow), \
edges (red), interior (grey); flat insets (blue) and the crop above (green).</figcaption></figure>\n"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_maps_zero_to_mid_grey_and_clamps() {
        assert_eq!(grey(0.0, 1.0), 127);
        assert_eq!(grey(5.0, 1.0), 255);
        assert_eq!(grey(-5.0, 1.0), 0);
    }
}
