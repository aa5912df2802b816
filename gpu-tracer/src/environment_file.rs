//! Environment maps from files: equirectangular OpenEXR (`.exr`) and
//! Radiance (`.hdr`) images of linear radiance, read with the `image`
//! crate ([`load_environment_map`]).

use crate::error::{Error, Result};
use crate::scene::EnvironmentMap;
use std::path::Path;

/// Reads the equirectangular environment map in `path` (`.exr` or `.hdr`,
/// decided by the extension, any case) as linear RGB radiance (alpha
/// ignored), turned by `rotation_degrees` about +Y (see
/// [`EnvironmentMap::rotation_degrees`]), and checks it
/// ([`EnvironmentMap::validate`]).
///
/// # Errors
/// [`Error::InvalidEnvironmentMap`] naming the file: another extension, a
/// file that cannot be opened or decoded, a size over the limit, or a NaN,
/// infinite or negative texel (which HDR files can hold).
pub fn load_environment_map(path: impl AsRef<Path>, rotation_degrees: f32) -> Result<EnvironmentMap> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bad = |reason: String| Error::InvalidEnvironmentMap {
        name: name.clone(),
        reason,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let format = match ext.as_deref() {
        Some("exr") => image::ImageFormat::OpenExr,
        Some("hdr") => image::ImageFormat::Hdr,
        _ => return Err(bad("not an .exr or .hdr file".into())),
    };
    let file = std::fs::File::open(path).map_err(|e| bad(format!("cannot open it: {e}")))?;
    let image = image::ImageReader::with_format(std::io::BufReader::new(file), format)
        .decode()
        .map_err(|e| bad(format!("cannot decode it: {e}")))?
        .into_rgb32f();
    let map = EnvironmentMap {
        name: name.clone(),
        width: image.width(),
        height: image.height(),
        texels: image.pixels().map(|p| p.0).collect(),
        rotation_degrees,
    };
    map.validate()?;
    Ok(map)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_exr(path: &Path, width: u32, height: u32, texel: impl Fn(u32, u32) -> [f32; 3]) {
        let img = image::Rgb32FImage::from_fn(width, height, |x, y| image::Rgb(texel(x, y)));
        image::DynamicImage::ImageRgb32F(img)
            .save(path)
            .expect("write exr");
    }

    #[test]
    fn exr_and_hdr_maps_load_with_their_texels() {
        let dir = tempfile::tempdir().unwrap();
        let exr = dir.path().join("sky.EXR");
        write_exr(&exr, 8, 4, |x, y| [x as f32, y as f32 * 0.5, 2.0]);
        let map = load_environment_map(&exr, 90.0).expect("exr");
        assert_eq!((map.width, map.height, map.rotation_turns()), (8, 4, 0.25));
        assert_eq!(map.texels[2 * 8 + 5], [5.0, 1.0, 2.0]);
        let hdr = dir.path().join("sky.hdr");
        let img = image::Rgb32FImage::from_fn(4, 2, |x, _| image::Rgb([0.25 * x as f32, 1.0, 4.0]));
        image::DynamicImage::ImageRgb32F(img)
            .save(&hdr)
            .expect("write hdr");
        let map = load_environment_map(&hdr, 0.0).expect("hdr");
        assert_eq!((map.width, map.height), (4, 2));
        // RGBE keeps 8 bits of mantissa per channel.
        let t = map.texels[3];
        assert!(
            (t[0] - 0.75).abs() < 0.01 && (t[1] - 1.0).abs() < 0.01 && (t[2] - 4.0).abs() < 0.05,
            "{t:?}"
        );
    }

    #[test]
    fn unusable_files_are_refused_with_the_file_named() {
        let dir = tempfile::tempdir().unwrap();
        let nan = dir.path().join("nan.exr");
        write_exr(&nan, 4, 2, |x, y| {
            if (x, y) == (3, 1) {
                [f32::NAN, 0.0, 0.0]
            } else {
                [1.0; 3]
            }
        });
        let garbage = dir.path().join("garbage.exr");
        std::fs::write(&garbage, b"not an image").unwrap();
        let png = dir.path().join("sky.png");
        for (path, want) in [
            (nan.clone(), "texel (3, 1)"),
            (garbage.clone(), "cannot decode"),
            (dir.path().join("missing.hdr"), "cannot open"),
            (png.clone(), "not an .exr or .hdr"),
        ] {
            let err = load_environment_map(&path, 0.0).unwrap_err();
            let msg = err.to_string();
            assert!(matches!(err, Error::InvalidEnvironmentMap { .. }), "{err:?}");
            assert!(
                msg.contains(want) && msg.contains(path.file_name().unwrap().to_str().unwrap()),
                "{msg}"
            );
        }
    }
}
