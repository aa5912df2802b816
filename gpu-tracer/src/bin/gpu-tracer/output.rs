//! What a render writes: the output directories, each frame's images and
//! AOVs when asked, and the last frame, the mean and the last filtered frame
//! at the end.

use crate::args::RenderArgs;
use anyhow::{bail, Context, Result};
use gpu_tracer::aov::write_aovs;
use gpu_tracer::filter::SequenceFilter;
use gpu_tracer::image_out::{write_exr, write_png, ToneMap};
use gpu_tracer::{FrameView, RenderOutput};
use std::path::{Path, PathBuf};

/// Writes `last.png|exr` and `mean.png|exr` of `output`, and
/// `last_filtered.png|exr` when `last_filtered` holds a filtered frame, into
/// `--out`; returns the paths written.
pub(crate) fn write_results(
    args: &RenderArgs,
    output: &RenderOutput,
    last_filtered: Option<&[glam::Vec4]>,
) -> Result<Vec<PathBuf>> {
    let (w, h) = (args.width, args.height);
    let files = [
        (args.out.join("last.png"), Some(false), false),
        (args.out.join("mean.png"), Some(true), false),
        (args.out.join("last.exr"), Some(false), true),
        (args.out.join("mean.exr"), Some(true), true),
        (args.out.join("last_filtered.png"), None, false),
        (args.out.join("last_filtered.exr"), None, true),
    ];
    for (path, mean, exr) in &files {
        let pixels = match mean {
            Some(true) => &output.mean,
            Some(false) => &output.last,
            None => match last_filtered {
                Some(pixels) => pixels,
                None => continue,
            },
        };
        if *exr {
            write_exr(path, w, h, pixels)
        } else {
            write_png(path, w, h, pixels, ToneMap::Reinhard)
        }
        .with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(files
        .iter()
        .filter(|f| f.1.is_some() || last_filtered.is_some())
        .map(|f| f.0.clone())
        .collect())
}

/// Writes frame `f`'s colour and/or AOVs as `--save-frames` / `--save-aovs` ask.
pub(crate) fn save_frame(
    args: &RenderArgs,
    frames_dir: &Path,
    aovs_dir: &Path,
    w: u32,
    h: u32,
    f: &FrameView<'_>,
) -> Result<()> {
    let stem = format!("frame_{:05}", f.index);
    if args.save_frames {
        let exr = frames_dir.join(format!("{stem}.exr"));
        write_exr(&exr, w, h, f.color).with_context(|| format!("cannot write {}", exr.display()))?;
        let png = frames_dir.join(format!("{stem}.png"));
        write_png(&png, w, h, f.color, ToneMap::Reinhard)
            .with_context(|| format!("cannot write {}", png.display()))?;
    }
    if args.save_aovs {
        let gbuffer = f.gbuffer.context("the renderer returned no G-buffer")?;
        write_aovs(aovs_dir, &stem, w, h, gbuffer)
            .with_context(|| format!("cannot write the AOVs of frame {}", f.index))?;
    }
    Ok(())
}

/// Filters frame `f` (the filter keeps the history between calls) and, with
/// `--save-frames`, writes it as `filtered_NNNNN.exr|png`; returns it.
pub(crate) fn filter_frame(
    args: &RenderArgs,
    filter: &mut SequenceFilter,
    frames_dir: &Path,
    w: u32,
    h: u32,
    f: &FrameView<'_>,
) -> Result<Vec<glam::Vec4>> {
    let gbuffer = f.gbuffer.context("the renderer returned no G-buffer")?;
    let out = filter
        .next(f.color, gbuffer)
        .with_context(|| format!("filtering frame {}", f.index))?;
    if args.save_frames {
        let stem = format!("filtered_{:05}", f.index);
        let exr = frames_dir.join(format!("{stem}.exr"));
        write_exr(&exr, w, h, &out).with_context(|| format!("cannot write {}", exr.display()))?;
        let png = frames_dir.join(format!("{stem}.png"));
        write_png(&png, w, h, &out, ToneMap::Reinhard)
            .with_context(|| format!("cannot write {}", png.display()))?;
    }
    Ok(out)
}

/// Creates `dir` and checks it is writable, so a bad path fails before rendering.
pub(crate) fn prepare_out_dir(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("output path {} exists and is not a directory", dir.display());
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let probe = dir.join(".gpu-tracer-write-probe");
    std::fs::write(&probe, b"")
        .with_context(|| format!("output directory {} is not writable", dir.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}
