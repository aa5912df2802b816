//! Image output: tone-mapped 8-bit sRGB PNG and linear float EXR.
//!
//! Every write is atomic: the image is encoded into a temporary file in the
//! destination's directory (`.<name>.<pid>.<n>.tmp`), flushed and synced,
//! then renamed over the destination. A failure at any step (unwritable
//! directory, full disk, encoder error) removes the temporary file and
//! leaves the destination as it was: absent, or the previous complete image.

use crate::error::{Error, ImageWriteError, Result};
use glam::{Vec3, Vec4};
use image::codecs::openexr::OpenExrEncoder;
use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use std::fs::{self, File, OpenOptions};
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// How linear radiance becomes display values before sRGB encoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ToneMap {
    /// Clamp each channel to `[0, 1]`.
    Clamp,
    /// Reinhard's `x / (1 + x)` on each channel: compresses any range into
    /// `[0, 1)`, keeps bright lights from clipping.
    #[default]
    Reinhard,
}

/// sRGB transfer function (IEC 61966-2-1) of a linear value in `[0, 1]`.
#[inline]
pub fn srgb_encode(linear: f32) -> f32 {
    if linear <= 0.003_130_8 {
        12.92 * linear
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// 8-bit sRGB RGB bytes (`3 * pixels.len()`) of linear pixels (`w`
/// ignored). Non-finite and negative values become 0.
pub fn tone_map_srgb8(pixels: &[Vec4], tone: ToneMap) -> Vec<u8> {
    let mut out = Vec::with_capacity(pixels.len() * 3);
    for p in pixels {
        let c = p.truncate();
        let c = Vec3::select(c.cmpge(Vec3::ZERO) & c.is_finite_mask(), c, Vec3::ZERO);
        let mapped = match tone {
            ToneMap::Clamp => c.min(Vec3::ONE),
            ToneMap::Reinhard => c / (Vec3::ONE + c),
        };
        for v in mapped.to_array() {
            out.push((srgb_encode(v) * 255.0 + 0.5).clamp(0.0, 255.0) as u8);
        }
    }
    out
}

/// Writes `pixels` (`width * height` linear RGB, row-major, top row first)
/// as an 8-bit sRGB PNG after `tone`, atomically.
///
/// # Errors
/// [`Error::BufferSize`] when `pixels.len() != width * height`,
/// [`Error::FrameSize`] for a zero size, [`Error::ImageWrite`] when the file
/// cannot be written; no file is left at `path` then.
pub fn write_png(
    path: impl AsRef<Path>,
    width: u32,
    height: u32,
    pixels: &[Vec4],
    tone: ToneMap,
) -> Result<()> {
    check_size(width, height, pixels.len())?;
    let bytes = tone_map_srgb8(pixels, tone);
    write_atomic(path.as_ref(), |w| {
        PngEncoder::new(w)
            .write_image(&bytes, width, height, ExtendedColorType::Rgb8)
            .map_err(ImageWriteError::Encode)
    })
}

/// Writes `pixels` (`width * height` linear RGB, `w` dropped) as a 32-bit
/// float RGB OpenEXR image, atomically.
///
/// # Errors
/// As [`write_png`].
pub fn write_exr(path: impl AsRef<Path>, width: u32, height: u32, pixels: &[Vec4]) -> Result<()> {
    check_size(width, height, pixels.len())?;
    let floats: Vec<f32> = pixels.iter().flat_map(|p| p.truncate().to_array()).collect();
    write_atomic(path.as_ref(), |w| {
        OpenExrEncoder::new(w)
            .write_image(
                bytemuck::cast_slice(&floats),
                width,
                height,
                ExtendedColorType::Rgb32F,
            )
            .map_err(ImageWriteError::Encode)
    })
}

fn check_size(width: u32, height: u32, len: usize) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(Error::FrameSize {
            width,
            height,
            padded_width: width,
        });
    }
    let expected = width as usize * height as usize;
    if len != expected {
        return Err(Error::BufferSize {
            buffer: "image pixels",
            expected,
            actual: len,
        });
    }
    Ok(())
}

/// Writes a file atomically: `write` fills a temporary file next to `path`,
/// which is then synced and renamed to `path`. On any error the temporary
/// file is removed and `path` is untouched.
///
/// # Errors
/// [`Error::ImageWrite`] with the first failure.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::result::Result<(), ImageWriteError>,
) -> Result<()> {
    static COUNTER: AtomicU32 = AtomicU32::new(0);
    let wrap = |source| Error::ImageWrite {
        path: path.to_path_buf(),
        source,
    };
    let name = path
        .file_name()
        .ok_or_else(|| {
            wrap(ImageWriteError::Io(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "path has no file name",
            )))
        })?
        .to_string_lossy()
        .into_owned();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let temp = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp)
        .map_err(|e| wrap(ImageWriteError::Io(e)))?;
    let result = (|| {
        let mut w = BufWriter::new(file);
        write(&mut w)?;
        let file = w.into_inner().map_err(|e| ImageWriteError::Io(e.into_error()))?;
        file.sync_all().map_err(ImageWriteError::Io)?;
        drop(file);
        fs::rename(&temp, path).map_err(ImageWriteError::Io)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&temp);
        return Err(wrap(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    struct TempDir(PathBuf);
    impl TempDir {
        fn new(tag: &str) -> Self {
            let p = std::env::temp_dir().join(format!("gpu-tracer-img-{tag}-{}", std::process::id()));
            let _ = fs::remove_dir_all(&p);
            fs::create_dir_all(&p).expect("temp dir");
            TempDir(p)
        }
        fn entries(&self) -> Vec<String> {
            let mut v: Vec<String> = fs::read_dir(&self.0)
                .expect("read dir")
                .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                .collect();
            v.sort();
            v
        }
    }
    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    fn gradient(w: u32, h: u32) -> Vec<Vec4> {
        (0..w * h)
            .map(|i| {
                Vec4::new(
                    (i % w) as f32 / w as f32 * 4.0,
                    (i / w) as f32 / h as f32,
                    0.25,
                    1.0,
                )
            })
            .collect()
    }

    #[test]
    fn srgb_and_tone_mapping() {
        assert_eq!(srgb_encode(0.0), 0.0);
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-6);
        assert!((srgb_encode(0.5) - 0.735_356_7).abs() < 1e-5);
        let px = [
            Vec4::new(0.0, 1.0, 3.0, 1.0),
            Vec4::new(f32::NAN, -1.0, f32::INFINITY, 1.0),
        ];
        assert_eq!(tone_map_srgb8(&px, ToneMap::Clamp), vec![0, 255, 255, 0, 0, 0]);
        // Reinhard: 1 -> 0.5 -> 188 in sRGB; 3 -> 0.75 -> 225.
        assert_eq!(tone_map_srgb8(&px[..1], ToneMap::Reinhard), vec![0, 188, 225]);
    }

    #[test]
    fn png_and_exr_round_trip() {
        let dir = TempDir::new("roundtrip");
        let px = gradient(7, 5);
        let png = dir.0.join("a.png");
        write_png(&png, 7, 5, &px, ToneMap::Clamp).expect("png");
        let back = image::open(&png).expect("decode png").to_rgb8();
        assert_eq!(back.dimensions(), (7, 5));
        assert_eq!(back.as_raw(), &tone_map_srgb8(&px, ToneMap::Clamp));
        let exr = dir.0.join("a.exr");
        write_exr(&exr, 7, 5, &px).expect("exr");
        let back = image::open(&exr).expect("decode exr").to_rgb32f();
        let want: Vec<f32> = px.iter().flat_map(|p| p.truncate().to_array()).collect();
        assert_eq!(back.as_raw(), &want);
        // Only the two images: no temporary files left.
        assert_eq!(dir.entries(), ["a.exr", "a.png"]);
    }

    #[test]
    fn failed_writes_leave_nothing_behind() {
        let dir = TempDir::new("fail");
        let px = gradient(4, 4);
        // Unwritable (missing) directory.
        let missing = dir.0.join("no-such-dir").join("x.png");
        let err = write_png(&missing, 4, 4, &px, ToneMap::Clamp).expect_err("missing dir");
        assert!(matches!(err, Error::ImageWrite { .. }), "{err}");
        assert!(std::error::Error::source(&err).is_some());
        assert!(!missing.exists());
        // A writer that fails half-way (as a full disk would): no file, no temp file.
        let target = dir.0.join("half.png");
        let err = write_atomic(&target, |w| {
            w.write_all(b"partial image data").map_err(ImageWriteError::Io)?;
            Err(ImageWriteError::Io(std::io::Error::other("disk full")))
        })
        .expect_err("fails");
        assert!(err.to_string().contains("disk full"), "{err}");
        assert!(dir.entries().is_empty(), "{:?}", dir.entries());
        // A failed overwrite keeps the previous complete image.
        write_png(&target, 4, 4, &px, ToneMap::Clamp).expect("first write");
        let before = fs::read(&target).expect("read");
        let _ = write_atomic(&target, |w| {
            w.write_all(b"garbage").map_err(ImageWriteError::Io)?;
            Err(ImageWriteError::Io(std::io::Error::other("disk full")))
        });
        assert_eq!(fs::read(&target).expect("read"), before);
        assert_eq!(dir.entries(), ["half.png"]);
        // Size mismatches are caught before touching the disk.
        assert!(matches!(
            write_exr(dir.0.join("b.exr"), 4, 5, &px),
            Err(Error::BufferSize {
                expected: 20,
                actual: 16,
                ..
            })
        ));
        assert!(write_png(dir.0.join("c.png"), 0, 4, &[], ToneMap::Clamp).is_err());
        assert_eq!(dir.entries(), ["half.png"]);
    }
}
