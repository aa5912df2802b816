//! Placement of the motion study's flat insets: anchored on a world point at frame 0,
//! moved every frame to its projection, and shrunk until they stay on their surface.

use super::case::{self as motion_case, MotionCase};
use super::config::MotionConfig;
use crate::study::insets::{check_inset, inset_layout, Inset};
use anyhow::{ensure, Context, Result};
use glam::{Vec2, Vec3};
use gpu_tracer::cornell::cornell_box;
use gpu_tracer::timeline::SceneSequence;
use kernels::abi::TraceParams;

/// A flat inset of the motion study: the static study's inset (`insets::inset_layout`),
/// possibly smaller, centred every frame on the projection of the world point under its
/// frame-0 centre.
#[derive(Clone, Debug, PartialEq)]
pub struct InsetAnchor {
    /// The inset (its position is frame 0's).
    pub inset: Inset,
    /// The world point under its centre in frame 0.
    pub point: Vec3,
}

/// The insets of a frame with camera `params`: each centred on its anchor's projection
/// (rounded to whole pixels).
pub(crate) fn place_insets(anchors: &[InsetAnchor], params: &TraceParams, size: u32) -> Result<Vec<Inset>> {
    anchors
        .iter()
        .map(|a| {
            let side = a.inset.side;
            let raster = kernels::camera::project_point(params, a.point)
                .with_context(|| format!("inset {}: its point is behind the camera", a.inset.name))?;
            let x0 = (raster.x - side as f32 / 2.0).round();
            let y0 = (raster.y - side as f32 / 2.0).round();
            ensure!(
                x0 >= 0.0 && y0 >= 0.0 && x0 + side as f32 <= size as f32 && y0 + side as f32 <= size as f32,
                "inset {} moved out of the image (to ({x0}, {y0}))",
                a.inset.name
            );
            Ok(Inset {
                x0: x0 as u32,
                y0: y0 as u32,
                ..a.inset.clone()
            })
        })
        .collect()
}

/// Smallest inset side the study accepts.
pub const MIN_INSET_SIDE: u32 = 8;

/// The insets of the study for `config` and `cases`: the static study's three insets,
/// each shrunk about its centre's world point (in steps of 2 pixels) until it stays on
/// its surface in every frame of every case, so that every sequence (the still one
/// included) is measured on the same insets. An inset that would have to shrink below
/// [`MIN_INSET_SIDE`] is left out (a side wall seen at a grazing angle on a small image:
/// the orbit narrows the wall it turns towards).
///
/// # Errors
/// Bad settings, or no inset left.
pub fn fit_insets(config: &MotionConfig, cases: &[MotionCase]) -> Result<Vec<InsetAnchor>> {
    let size = config.size;
    let scene = cornell_box();
    let settings = config.settings();
    let still = gpu_tracer::SceneGpu::build(&scene)?;
    let params = still.trace_params(&settings, 0)?;
    let mut anchors = Vec::new();
    for inset in inset_layout(crate::study::StudyScene::Cornell, size) {
        let (cx, cy) = (inset.x0 + inset.side / 2, inset.y0 + inset.side / 2);
        let ray = kernels::camera::primary_ray(&params, cx, cy, Vec2::ZERO);
        let hit = still
            .closest_hit(&ray)
            .with_context(|| format!("inset {}: centre sees nothing", inset.name))?;
        anchors.push(Some(InsetAnchor {
            point: ray.origin + ray.dir * hit.t,
            inset,
        }));
    }
    for &case in cases {
        let (timeline, _) = motion_case::timeline(case, &scene, size, config.frames, config.sway_period)?;
        let mut sequence = SceneSequence::new(&scene, timeline, size)?;
        for t in 0..config.frames {
            if t > 0 {
                sequence.advance()?;
            }
            let params = sequence.scene().trace_params(&settings, t)?;
            for slot in anchors.iter_mut() {
                let Some(a) = slot else { continue };
                loop {
                    let fits = place_insets(std::slice::from_ref(a), &params, size)
                        .and_then(|i| check_inset(sequence.scene(), &params, &i[0]));
                    match fits {
                        Ok(()) => break,
                        Err(_) if a.inset.side < MIN_INSET_SIDE + 2 => {
                            *slot = None;
                            break;
                        }
                        Err(_) => a.inset.side -= 2,
                    }
                }
            }
        }
    }
    let mut anchors: Vec<InsetAnchor> = anchors.into_iter().flatten().collect();
    ensure!(
        !anchors.is_empty(),
        "no inset of at least {MIN_INSET_SIDE} pixels stays on its surface in every frame"
    );
    // Frame-0 positions of the shrunk insets.
    let placed = place_insets(&anchors, &params, size)?;
    for (a, p) in anchors.iter_mut().zip(placed) {
        a.inset = p;
    }
    Ok(anchors)
}
