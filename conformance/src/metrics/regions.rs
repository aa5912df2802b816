//! Image regions of a rendered frame, from its G-buffer, for the per-region error
//! figures of the static study ([`crate::study`]) and the motion study
//! ([`crate::motion`]).
//!
//! The whole-image error of a 1-spp Cornell-box frame is dominated by the light's
//! silhouette (QUALITY.md, issues 5, 6 and 14), so every blurred figure is also reported
//! per region. The regions are those of issue 14 ("Goals"). Every pixel belongs to
//! exactly one region, tested in this order:
//!
//! 1. **Emitter zone** ([`Region::Emitter`]): every pixel within [`EMITTER_ZONE_RADIUS`]
//!    (3) pixels (Chebyshev distance between pixel centres) of a pixel whose centre ray
//!    sees an emitter (`GBUFFER_EMITTER`): the light and a band of 3 pixels around its
//!    silhouette, where a pixel's estimate is the light's or the ceiling's radiance
//!    depending on its jitter.
//! 2. **Edges** ([`Region::Edge`]): every pixel whose centre lies within
//!    [`EDGE_RADIUS`] (2) pixels of a depth / normal / id discontinuity, outside the
//!    emitter zone. A *discontinuity* separates two 8-neighbours with another object
//!    id, another hit / no-hit state, normals more than [`EDGE_NORMAL_DEGREES`] apart,
//!    or linear depths differing by more than [`EDGE_DEPTH_JUMP`] (relative to the
//!    nearer one); it runs along the pixels' common border, half a pixel from each
//!    centre. So the pixels touching a discontinuity (a differing pixel in their 3x3
//!    neighbourhood) are at 0.5 px, and the edge region is those pixels dilated by
//!    `EDGE_RADIUS - 1` (Chebyshev): 2 pixels on each side of a straight edge.
//! 3. **Interior** ([`Region::Interior`]): the rest: pixels at least 2.5 px from any
//!    discontinuity, where the permutation's assumption (a seed's estimate survives a
//!    move) holds best.
//!
//! # History of the definition
//!
//! The first definition (issue 13) used a 2-pixel emitter band and made the edge region
//! every pixel of each aligned 4x4 *sorting block* holding an edge pixel (the plain
//! sort mixes a block's seeds, so a block straddling an edge was counted as a whole).
//! Issue 14 fixed the regions from the G-buffer alone, independent of the block size
//! (the feature-aware permutation no longer mixes a block across an edge, so the
//! block-dilated region would have credited it for interior pixels), with a 3-pixel
//! emitter band (the band that holds about 97% of white noise's blurred error on a
//! held-out Cornell box). Figures measured before that change (QUALITY.md, "Seeds in
//! motion") use the old regions.
//!
//! Regions are computed from a frame's own G-buffer (the motion study: per frame; the
//! static study: frame 0 of the still camera); the G-buffer is the centre ray's primary
//! hit, the same for every method.

use kernels::abi::{GBufferGpu, GBUFFER_EMITTER, GBUFFER_HIT};

/// Radius in pixels of the emitter zone around emitter pixels (Chebyshev distance):
/// issue 14's "within 3 px of a pixel whose primary hit is an emitter".
pub const EMITTER_ZONE_RADIUS: u32 = 3;
/// Distance in pixels from a discontinuity (the border between two pixels) within which
/// a pixel centre belongs to the edge region: issue 14's "within 2 px of a
/// depth/normal/id discontinuity".
pub const EDGE_RADIUS: u32 = 2;
/// Normals of neighbouring pixels more than this many degrees apart make an edge. 25:
/// far above the zero angle between pixels of one flat Cornell-box face, far below the
/// 90 degrees between two faces.
pub const EDGE_NORMAL_DEGREES: f32 = 25.0;
/// Relative linear-depth difference between neighbouring pixels that makes an edge
/// (depth jump, `|d1 - d2| > EDGE_DEPTH_JUMP * min(d1, d2)`). 0.1: above the slope of
/// the side walls seen at a grazing angle at 64x64 (about 5% per pixel), below the jump
/// from a block's face to the wall behind it (15% or more).
pub const EDGE_DEPTH_JUMP: f32 = 0.1;

/// Which region a pixel belongs to (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Region {
    /// The light and the band around its silhouette.
    Emitter = 0,
    /// Within [`EDGE_RADIUS`] pixels of a geometric discontinuity.
    Edge = 1,
    /// Everything else.
    Interior = 2,
}

impl Region {
    /// Every region, in precedence order.
    pub const ALL: [Region; 3] = [Region::Emitter, Region::Edge, Region::Interior];

    /// Short name used in tables.
    pub fn name(self) -> &'static str {
        match self {
            Region::Emitter => "emitter",
            Region::Edge => "edges",
            Region::Interior => "interior",
        }
    }
}

/// Whether the G-buffer texels `a` and `b` of neighbouring pixels lie on different
/// surfaces (module docs, "Edges").
fn differs(a: &GBufferGpu, b: &GBufferGpu) -> bool {
    let (hit_a, hit_b) = (a.ids.w & GBUFFER_HIT != 0, b.ids.w & GBUFFER_HIT != 0);
    if hit_a != hit_b {
        return true;
    }
    if !hit_a {
        return false;
    }
    if a.ids.x != b.ids.x {
        return true;
    }
    let cos = a.normal_depth.truncate().dot(b.normal_depth.truncate());
    if cos < EDGE_NORMAL_DEGREES.to_radians().cos() {
        return true;
    }
    let (da, db) = (a.normal_depth.w, b.normal_depth.w);
    (da - db).abs() > EDGE_DEPTH_JUMP * da.min(db)
}

/// Marks every pixel within Chebyshev distance `r` of a marked pixel of `mask`
/// (`width * height`, row-major).
fn dilate(mask: &[bool], w: usize, h: usize, r: usize) -> Vec<bool> {
    // Separable: rows, then columns.
    let mut rows = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            rows[y * w + x] = (x.saturating_sub(r)..(x + r + 1).min(w)).any(|nx| mask[y * w + nx]);
        }
    }
    let mut out = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            out[y * w + x] = (y.saturating_sub(r)..(y + r + 1).min(h)).any(|ny| rows[ny * w + x]);
        }
    }
    out
}

/// The region of every pixel of a `width x height` frame (row-major) from its G-buffer
/// (module docs).
///
/// # Panics
/// If `gbuffer` is not `width * height` long.
pub fn classify_regions(gbuffer: &[GBufferGpu], width: u32, height: u32) -> Vec<Region> {
    let (w, h) = (width as usize, height as usize);
    assert_eq!(gbuffer.len(), w * h, "G-buffer must be width * height");
    // Pixels touching a discontinuity (0.5 px from it).
    let mut touching = vec![false; w * h];
    for y in 0..h {
        for x in 0..w {
            let g = &gbuffer[y * w + x];
            touching[y * w + x] = (y.saturating_sub(1)..(y + 2).min(h))
                .any(|ny| (x.saturating_sub(1)..(x + 2).min(w)).any(|nx| differs(g, &gbuffer[ny * w + nx])));
        }
    }
    let edge = dilate(&touching, w, h, EDGE_RADIUS as usize - 1);
    let light: Vec<bool> = gbuffer
        .iter()
        .map(|g| g.ids.w & (GBUFFER_EMITTER | GBUFFER_HIT) == (GBUFFER_EMITTER | GBUFFER_HIT))
        .collect();
    let emitter = dilate(&light, w, h, EMITTER_ZONE_RADIUS as usize);
    (0..w * h)
        .map(|i| {
            if emitter[i] {
                Region::Emitter
            } else if edge[i] {
                Region::Edge
            } else {
                Region::Interior
            }
        })
        .collect()
}

/// Sum of `value^2` over each region ([`Region::ALL`] order); `values` and
/// `regions` are per pixel, in the same order.
pub fn square_sums_by_region(values: &[f32], regions: &[Region]) -> [f64; 3] {
    let mut sums = [0.0f64; 3];
    for (v, r) in values.iter().zip(regions) {
        sums[*r as usize] += (*v as f64) * (*v as f64);
    }
    sums
}

/// The share of the image of each region ([`Region::ALL`] order).
pub fn region_shares(regions: &[Region]) -> [f64; 3] {
    let n = regions.len().max(1) as f64;
    Region::ALL.map(|r| regions.iter().filter(|&&x| x == r).count() as f64 / n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec4, Vec4};

    fn texel(object: u32, normal: [f32; 3], depth: f32, emitter: bool) -> GBufferGpu {
        GBufferGpu {
            normal_depth: Vec4::new(normal[0], normal[1], normal[2], depth),
            ids: UVec4::new(
                object,
                0,
                0,
                GBUFFER_HIT | if emitter { GBUFFER_EMITTER } else { 0 },
            ),
            ..Default::default()
        }
    }

    #[test]
    fn regions_follow_the_definitions_on_a_synthetic_frame() {
        // 17x13 frame: object 0 left of column 8, object 1 from column 8 on, both flat;
        // one emitter pixel at (1, 11).
        let (w, h) = (17u32, 13u32);
        let g: Vec<GBufferGpu> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                texel(u32::from(x >= 8), [0.0, 0.0, 1.0], 10.0, (x, y) == (1, 11))
            })
            .collect();
        let r = classify_regions(&g, w, h);
        let at = |x: u32, y: u32| r[(y * w + x) as usize];
        // The discontinuity runs between columns 7 and 8: centres within 2 px are
        // columns 6..=9. The emitter zone is within 3 px of (1, 11).
        for y in 0..h {
            for x in 0..w {
                let near_emitter = x <= 4 && y >= 8;
                let want = if near_emitter {
                    Region::Emitter
                } else if (6..=9).contains(&x) {
                    Region::Edge
                } else {
                    Region::Interior
                };
                assert_eq!(at(x, y), want, "({x}, {y})");
            }
        }
        // Normal and depth changes on one object are edges too.
        let mut g2 = g.clone();
        g2[(2 * w + 13) as usize].normal_depth = Vec4::new(0.0, 1.0, 0.0, 10.0);
        let r2 = classify_regions(&g2, w, h);
        // The odd pixel's 4 borders are discontinuities: pixels within 2 px of them
        // are within Chebyshev distance 2 of it.
        for y in 0..h {
            for x in 10..w {
                let near = x.abs_diff(13) <= 2 && y.abs_diff(2) <= 2;
                let want = if near { Region::Edge } else { Region::Interior };
                assert_eq!(r2[(y * w + x) as usize], want, "({x}, {y})");
            }
        }
        let mut g3 = g.clone();
        g3[(7 * w + 2) as usize].normal_depth.w = 12.0;
        let r3 = classify_regions(&g3, w, h);
        assert_eq!(r3[(7 * w + 2) as usize], Region::Edge, "a 20% depth jump");
        assert_eq!(r3[(9 * w + 2) as usize], Region::Emitter, "emitter zone first");
        assert_eq!(r3[(7 * w + 5) as usize], Region::Interior, "3 px from the jump");
        let mut g4 = g;
        g4[(7 * w + 2) as usize].normal_depth.w = 10.5;
        assert_eq!(
            classify_regions(&g4, w, h)[(7 * w + 2) as usize],
            Region::Interior,
            "5% is not an edge"
        );
        let shares = region_shares(&r);
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
}
