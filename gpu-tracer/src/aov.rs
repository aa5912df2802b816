//! Arbitrary output variables: the G-buffer as images a compositor or a
//! denoiser reads (float EXR, one file per quantity, written atomically).
//!
//! | file | channels (R, G, B) | no-hit pixels |
//! |---|---|---|
//! | `*.motion.exr` | backward motion in pixels `(dx, dy, 0)`: the pixel's point was at `(x + 0.5 + dx, y + 0.5 + dy)` in the previous frame (raster `y` down) | motion of the view direction |
//! | `*.depth.exr` | linear depth along the camera's forward axis, world units, in all three channels | 0 |
//! | `*.normal.exr` | unit world-space normal facing the camera | 0 |
//! | `*.albedo.exr` | linear albedo (material x texture) | 0 |
//! | `*.id.exr` | object id, material index, flags (`kernels::abi::GBUFFER_HIT` ...) as exact floats below 2^24 | `(-1, -1, 0)` |

use crate::error::Result;
use crate::image_out::write_exr;
use glam::Vec4;
use kernels::abi::{GBufferGpu, GBUFFER_HIT};
use std::path::{Path, PathBuf};

/// How an AOV's pixel is made from a G-buffer texel.
pub type AovValue = fn(&GBufferGpu) -> Vec4;

/// The quantities [`write_aovs`] writes, as `(file suffix, value of a texel)`.
pub const AOVS: [(&str, AovValue); 5] = [
    ("motion", |g| Vec4::new(g.motion.x, g.motion.y, 0.0, 1.0)),
    ("depth", |g| {
        Vec4::new(g.normal_depth.w, g.normal_depth.w, g.normal_depth.w, 1.0)
    }),
    ("normal", |g| g.normal_depth.truncate().extend(1.0)),
    ("albedo", |g| g.albedo.truncate().extend(1.0)),
    ("id", |g| {
        if g.ids.w & GBUFFER_HIT == 0 {
            Vec4::new(-1.0, -1.0, 0.0, 1.0)
        } else {
            Vec4::new(g.ids.x as f32, g.ids.y as f32, g.ids.w as f32, 1.0)
        }
    }),
];

/// Writes the AOVs of a `width x height` G-buffer as `<dir>/<stem>.<aov>.exr`
/// for every entry of [`AOVS`], each atomically; returns the paths written.
///
/// # Errors
/// As [`write_exr`]: a wrong buffer size or a failed write (files written
/// before the failure stay, complete).
pub fn write_aovs(
    dir: &Path,
    stem: &str,
    width: u32,
    height: u32,
    gbuffer: &[GBufferGpu],
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::with_capacity(AOVS.len());
    for (name, value) in AOVS {
        let pixels: Vec<Vec4> = gbuffer.iter().map(value).collect();
        let path = dir.join(format!("{stem}.{name}.exr"));
        write_exr(&path, width, height, &pixels)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::UVec4;
    use kernels::abi::GBUFFER_NO_HIT;

    #[test]
    fn aovs_round_trip_through_exr() {
        let dir = std::env::temp_dir().join(format!("aov-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let hit = GBufferGpu {
            normal_depth: Vec4::new(0.0, 1.0, 0.0, 12.5),
            albedo: Vec4::new(0.25, 0.5, 0.75, 0.0),
            motion: Vec4::new(-1.5, 0.25, 12.0, 0.0),
            ids: UVec4::new(7, 3, 42, GBUFFER_HIT),
        };
        let miss = GBufferGpu {
            ids: UVec4::new(GBUFFER_NO_HIT, GBUFFER_NO_HIT, GBUFFER_NO_HIT, 0),
            ..Default::default()
        };
        let files = write_aovs(&dir, "f", 2, 1, &[hit, miss]).unwrap();
        assert_eq!(files.len(), 5);
        let read = |name: &str| {
            image::open(dir.join(format!("f.{name}.exr")))
                .unwrap()
                .into_rgb32f()
                .pixels()
                .map(|p| [p[0], p[1], p[2]])
                .collect::<Vec<_>>()
        };
        assert_eq!(read("motion"), vec![[-1.5, 0.25, 0.0], [0.0, 0.0, 0.0]]);
        assert_eq!(read("depth")[0], [12.5; 3]);
        assert_eq!(read("normal")[0], [0.0, 1.0, 0.0]);
        assert_eq!(read("albedo")[0], [0.25, 0.5, 0.75]);
        assert_eq!(read("id"), vec![[7.0, 3.0, 1.0], [-1.0, -1.0, 0.0]]);
        std::fs::remove_dir_all(&dir).ok();
    }
}
