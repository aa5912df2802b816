//! The moving sequences of the motion study ([`crate::motion`]): the built-in
//! Cornell box with a swaying orbit of the camera, or with its short block moving, as a
//! `gpu_tracer::timeline::Timeline` for `gpu_tracer::render::render_sequence_cpu`.
//!
//! # The sway
//!
//! Every moving case follows a triangle wave of integer **steps**: one step per frame,
//! up for a quarter period, down for half a period, up for the last quarter
//! (`s(t) = 0, 1, ..., P/4, P/4 - 1, ..., -P/4, ..., -1, 0, ...`, [`sway_steps`]), so
//! every frame moves by the same amount and the sequence can run for any number of
//! frames without leaving the room. The period is `P = size / 4` frames rounded down to
//! a multiple of 4 ([`sway_period`]; 64 at 256x256): the amplitude is then `v * size /
//! 16` pixels at `v` pixels per frame (32 px, an eighth of the image, at 2 px/frame;
//! 8 px at 0.5), the same angle at every image size. Poses repeat (`P / 2 + 1` distinct
//! ones for the orbit), which the pose-keyed reference cache exploits. The poses are
//! set by keys at every frame with step interpolation, so a repeated pose is
//! bit-identical.
//!
//! # Camera orbit ([`MotionCase::Orbit`])
//!
//! The camera turns about the vertical axis through its target by `s(t) * theta`,
//! where `theta` makes the point seen at the image centre move `v` pixels in the first
//! frame ([`orbit_degrees_per_frame`]). With the eye at distance `d` from the target,
//! the centre's point at `r = depth - d` beyond the target (depth: the centre ray's hit
//! depth along the view axis), `H` the image height and `phi` half the vertical field
//! of view, the point's raster offset after a turn by `theta` is
//! `x = r sin(theta) / (d + r cos(theta)) * H / (2 tan(phi))`. Setting `x = v` and
//! `k = 2 v tan(phi) / H`:
//!
//! `theta = atan(k) + asin(k d / (r sqrt(1 + k^2)))`.
//!
//! For the Cornell box (eye `(278, 273, -800)`, target `(278, 273, 0)` in the open
//! front, so `d = 800`; 39.3 degrees) the centre ray hits the tall block's front face
//! at `z = 292` (depth 1092, `r = 292`): at 256x256 the orbit turns 0.299 degrees per
//! frame for 0.5 px/frame and 1.195 for 2 px/frame (sway amplitude +-4.8 and +-19.1
//! degrees). Points further back move faster (the back wall, `r = 559`, about 1.5x),
//! points nearer than the target the other way; the study reports the measured speed
//! at the image centre and over the image.

//! # Camera pan ([`MotionCase::Pan`])
//!
//! The camera slides along its right axis by `s(t) * step`, eye and target together
//! (no turn), where `step = v * 2 depth tan(phi) / H` moves the point seen at the image
//! centre (depth: its depth along the view axis) `v` pixels a frame. Every point moves
//! horizontally by `v * depth_centre / depth` pixels: the back wall slower, the blocks'
//! fronts faster (parallax), with no rotation of the picture.
//!
//! # Object motion ([`MotionCase::Object`])
//!
//! The short block (object 6) rises and sinks: its height above the floor is
//! `|s(t)| * lift`, where `lift` makes its centre move `v` pixels per frame on screen
//! (`lift = v * 2 depth tan(phi) / H`, depth: the block centre's depth). The camera
//! stays still; the floor and wall behind and under the block are disoccluded and
//! occluded in turn, and its shadow moves.

use anyhow::{bail, Context, Result};
use glam::{Mat3, Quat, Vec2, Vec3, Vec4};
use gpu_tracer::animation::{Channel, Interpolation, MeshInstance, Node, Property, Rig, RigCamera, Trs};
use gpu_tracer::scene::{CameraBasis, Scene, SceneGpu, TraceSettings};
use gpu_tracer::timeline::Timeline;

/// Object id of the Cornell box's short block (`gpu_tracer::cornell`).
pub const SHORT_BLOCK_OBJECT: u32 = 6;
/// Frames per second of the study's timelines (only names the key times).
const FPS: f32 = 30.0;

/// What moves in a sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotionCase {
    /// Nothing: the static reference run of the same methods.
    Still,
    /// The camera sways about its target; `px_per_frame` at the image centre.
    Orbit {
        /// Speed of the image centre's point in pixels per frame.
        px_per_frame: f32,
    },
    /// The camera slides sideways, eye and target together; `px_per_frame` at the
    /// image centre.
    Pan {
        /// Speed of the image centre's point in pixels per frame.
        px_per_frame: f32,
    },
    /// The short block rises and sinks; `px_per_frame` at its centre.
    Object {
        /// Speed of the block's centre in pixels per frame.
        px_per_frame: f32,
    },
}

impl MotionCase {
    /// Name used in tables and cache files.
    pub fn name(&self) -> String {
        match self {
            MotionCase::Still => "still".into(),
            MotionCase::Orbit { px_per_frame } => format!("orbit {px_per_frame} px/frame"),
            MotionCase::Pan { px_per_frame } => format!("pan {px_per_frame} px/frame"),
            MotionCase::Object { px_per_frame } => format!("block {px_per_frame} px/frame"),
        }
    }
}

/// The sway period in frames for a `size`-pixel image: `size / 4` rounded down to a
/// multiple of 4, at least 4 (module docs).
pub fn sway_period(size: u32) -> u32 {
    (size / 16 * 4).max(4)
}

/// The sway's step count at frame `t` for period `period` (a multiple of 4; module
/// docs): a triangle wave between `-period / 4` and `period / 4`, changing by exactly
/// one every frame.
pub fn sway_steps(t: u32, period: u32) -> i32 {
    let (q, p) = ((t % period) as i32, period as i32);
    if q <= p / 4 {
        q
    } else if q <= 3 * p / 4 {
        p / 2 - q
    } else {
        q - p
    }
}

/// The raster position and linear depth of the point the centre ray of a `size x size`
/// frame of `scene` (as built, frame 0) hits.
fn centre_hit(scene: &SceneGpu, size: u32) -> Result<(Vec3, f32)> {
    let params = scene.trace_params(&TraceSettings::new(size, size), 0)?;
    let ray = kernels::camera::primary_ray(&params, size / 2, size / 2, Vec2::ZERO);
    let hit = scene.closest_hit(&ray).context("the centre ray sees nothing")?;
    let p = ray.origin + ray.dir * hit.t;
    Ok((p, (p - scene.camera.origin).dot(scene.camera.forward)))
}

/// The orbit angle per frame (degrees) that moves the point at the image centre of a
/// `size x size` frame of `scene` by `px_per_frame` pixels (module docs).
///
/// # Errors
/// A bad camera, a centre ray that sees nothing or lies in front of the target, or a
/// speed too large for the geometry.
pub fn orbit_degrees_per_frame(scene: &Scene, size: u32, px_per_frame: f32) -> Result<f32> {
    let built = SceneGpu::build(scene)?;
    let (_, depth) = centre_hit(&built, size)?;
    let d = (scene.camera.target - scene.camera.origin).length();
    let r = depth - d;
    if r <= 0.0 {
        bail!("the image centre's point (depth {depth}) is not behind the orbit's target (distance {d})");
    }
    let tan_phi = (scene.camera.fov_y_degrees.to_radians() * 0.5).tan();
    let k = 2.0 * px_per_frame.abs() * tan_phi / size as f32;
    let s = k * d / (r * (1.0 + k * k).sqrt());
    if s > 1.0 {
        bail!("{px_per_frame} px/frame is too fast for an orbit of this scene");
    }
    Ok((k.atan() + s.asin()).to_degrees() * px_per_frame.signum())
}

/// Lift per step (scene units) of the short block that moves its centre by
/// `px_per_frame` pixels on a `size`-pixel-high image (module docs).
fn block_lift(scene: &Scene, size: u32, px_per_frame: f32) -> Result<(f32, std::ops::Range<usize>)> {
    let tris: Vec<usize> = (0..scene.triangles.len())
        .filter(|&i| scene.triangles[i].object == SHORT_BLOCK_OBJECT)
        .collect();
    let (Some(&first), Some(&last)) = (tris.first(), tris.last()) else {
        bail!("the scene has no object {SHORT_BLOCK_OBJECT}");
    };
    if last + 1 - first != tris.len() {
        bail!("object {SHORT_BLOCK_OBJECT}'s triangles are not contiguous");
    }
    let centre = tris
        .iter()
        .flat_map(|&i| scene.triangles[i].vertices)
        .fold(Vec3::ZERO, |a, v| a + v)
        / (3 * tris.len()) as f32;
    let basis = scene.camera.basis()?;
    let depth = (centre - basis.origin).dot(basis.forward);
    let lift = px_per_frame * 2.0 * depth * basis.tan_half_fov_y / size as f32;
    Ok((lift, first..last + 1))
}

/// Step-interpolated keys at every frame time `t / FPS`, `t < frames`.
fn keys(frames: u32, value: impl Fn(u32) -> Vec4) -> (Vec<f32>, Vec<Vec4>) {
    (0..frames).map(|t| (t as f32 / FPS, value(t))).unzip()
}

/// The rotation of a camera node that looks along `basis.forward` with `basis.up` up
/// (a camera node looks along its local -Z with +Y up).
fn look_rotation(basis: &CameraBasis) -> Quat {
    Quat::from_mat3(&Mat3::from_cols(basis.right, basis.up, -basis.forward))
}

/// A rig of `nodes` whose node 0 follows the step keys `(times, values)` of
/// `property`, and whose camera is node `camera_node` with the scene's field of view.
fn camera_rig(
    nodes: Vec<Node>,
    property: Property,
    (times, values): (Vec<f32>, Vec<Vec4>),
    camera_node: usize,
    fov_y_degrees: f32,
) -> Rig {
    Rig {
        nodes,
        channels: vec![Channel {
            node: 0,
            property,
            interpolation: Interpolation::Step,
            times,
            values,
        }],
        instances: Vec::new(),
        local: Vec::new(),
        local_normals: Vec::new(),
        camera: Some(RigCamera {
            node: camera_node,
            fov_y_degrees,
        }),
    }
}

/// The timeline of `case` for `frames` frames of `size x size` images of `scene` (the
/// Cornell box) with a sway of `period` frames (a multiple of 4; `None`:
/// [`sway_period`]), and a description of the motion for reports (degrees per frame or
/// lift per frame).
///
/// # Errors
/// A period that is not a positive multiple of 4; as [`orbit_degrees_per_frame`]; a
/// scene without the short block for [`MotionCase::Object`].
pub fn timeline(
    case: MotionCase,
    scene: &Scene,
    size: u32,
    frames: u32,
    period: Option<u32>,
) -> Result<(Timeline, String)> {
    let period = period.unwrap_or_else(|| sway_period(size));
    if period == 0 || !period.is_multiple_of(4) {
        bail!("the sway period must be a positive multiple of 4 frames, not {period}");
    }
    let mut timeline = Timeline {
        fps: FPS,
        ..Timeline::still()
    };
    let frames = frames.max(1);
    let describe = match case {
        MotionCase::Still => "camera and objects still".to_string(),
        MotionCase::Orbit { px_per_frame } => {
            let degrees = orbit_degrees_per_frame(scene, size, px_per_frame)?;
            let cam = scene.camera;
            let basis = cam.basis()?;
            // Pivot at the target (turned about world up), camera node at the eye's
            // offset looking along its local -Z with +Y up.
            let look = look_rotation(&basis);
            let nodes = vec![
                Node {
                    name: "pivot".into(),
                    parent: None,
                    rest: Trs {
                        translation: cam.target,
                        ..Trs::default()
                    },
                },
                Node {
                    name: "camera".into(),
                    parent: Some(0),
                    rest: Trs {
                        translation: cam.origin - cam.target,
                        rotation: look,
                        ..Trs::default()
                    },
                },
            ];
            let axis = cam.up.normalize();
            let turns = keys(frames, |t| {
                let angle = (sway_steps(t, period) as f32 * degrees).to_radians();
                Vec4::from(Quat::from_axis_angle(axis, angle))
            });
            timeline.rig = Some(camera_rig(nodes, Property::Rotation, turns, 1, cam.fov_y_degrees));
            format!(
                "camera orbit {degrees:.3} deg/frame about the target, sway period {period} frames (+-{:.2} deg)",
                degrees * (period / 4) as f32
            )
        }
        MotionCase::Pan { px_per_frame } => {
            let built = SceneGpu::build(scene)?;
            let (_, depth) = centre_hit(&built, size)?;
            let basis = scene.camera.basis()?;
            let step = px_per_frame * 2.0 * depth * basis.tan_half_fov_y / size as f32;
            let origin = scene.camera.origin;
            let slides = keys(frames, |t| {
                (origin + basis.right * (sway_steps(t, period) as f32 * step)).extend(0.0)
            });
            let camera = Node {
                name: "camera".into(),
                parent: None,
                rest: Trs {
                    translation: origin,
                    rotation: look_rotation(&basis),
                    ..Trs::default()
                },
            };
            let fov = scene.camera.fov_y_degrees;
            timeline.rig = Some(camera_rig(vec![camera], Property::Translation, slides, 0, fov));
            format!(
                "camera pan {step:.3} units/frame along its right axis, sway period {period} frames (+-{:.1} units)",
                step * (period / 4) as f32
            )
        }
        MotionCase::Object { px_per_frame } => {
            let (lift, range) = block_lift(scene, size, px_per_frame)?;
            let (times, values) = keys(frames, |t| {
                Vec4::new(0.0, sway_steps(t, period).unsigned_abs() as f32 * lift, 0.0, 0.0)
            });
            timeline.rig = Some(Rig {
                nodes: vec![Node {
                    name: "short block".into(),
                    parent: None,
                    rest: Trs::default(),
                }],
                channels: vec![Channel {
                    node: 0,
                    property: Property::Translation,
                    interpolation: Interpolation::Step,
                    times,
                    values,
                }],
                instances: vec![MeshInstance {
                    node: 0,
                    first_triangle: range.start,
                    triangle_count: range.len(),
                }],
                local: scene.triangles.iter().map(|t| t.vertices).collect(),
                local_normals: Vec::new(),
                camera: None,
            });
            format!(
                "short block lifted {lift:.2} units/frame, sway period {period} frames (up to {:.1} units)",
                lift * (period / 4) as f32
            )
        }
    };
    Ok((timeline, describe))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gpu_tracer::cornell::cornell_box;
    use gpu_tracer::timeline::SceneSequence;

    #[test]
    fn sway_moves_one_step_per_frame_and_repeats() {
        let p = 16;
        let s: Vec<i32> = (0..=2 * p).map(|t| sway_steps(t, p)).collect();
        assert_eq!(&s[..9], &[0, 1, 2, 3, 4, 3, 2, 1, 0]);
        assert_eq!(s[12], -4);
        assert!(s.windows(2).all(|w| (w[0] - w[1]).abs() == 1));
        assert_eq!(s[p as usize], 0);
        assert_eq!(sway_period(256), 64);
        assert_eq!(sway_period(96), 24);
    }

    /// Frame 0 of `case` at 256x256 has the scene's camera; returns the built scene's
    /// camera, frame 1's camera and where frame 1 sees the point frame 0 saw at the
    /// image centre.
    fn centre_after_one_frame(case: MotionCase) -> (CameraBasis, CameraBasis, Vec2) {
        let scene = cornell_box();
        let (timeline, _) = timeline(case, &scene, 256, 4, None).unwrap();
        let mut seq = SceneSequence::new(&scene, timeline, 256).unwrap();
        let built = SceneGpu::build(&scene).unwrap();
        let (p, _) = centre_hit(&built, 256).unwrap();
        let f0 = seq.scene().camera;
        assert!((f0.origin - built.camera.origin).length() < 1e-3);
        assert!((f0.forward - built.camera.forward).length() < 1e-5);
        seq.advance().unwrap();
        let params = seq
            .scene()
            .trace_params(&TraceSettings::new(256, 256), 1)
            .unwrap();
        let raster = kernels::camera::project_point(&params, p).unwrap();
        (built.camera, seq.scene().camera, raster)
    }

    #[test]
    fn orbit_speed_matches_the_formula_and_the_cornell_figures() {
        let deg = orbit_degrees_per_frame(&cornell_box(), 256, 2.0).unwrap();
        assert!((deg - 1.195).abs() < 0.003, "{deg}");
        // Frame 1 of the orbit: the centre's point moves 2 px.
        let (_, _, raster) = centre_after_one_frame(MotionCase::Orbit { px_per_frame: 2.0 });
        assert!(((raster.x - 128.0).abs() - 2.0).abs() < 0.01, "{raster}");
    }

    #[test]
    fn the_pan_moves_the_centre_by_its_speed_without_turning() {
        let (f0, f1, raster) = centre_after_one_frame(MotionCase::Pan { px_per_frame: 2.0 });
        assert!((f1.forward - f0.forward).length() < 1e-5, "the pan turned");
        assert!((f1.origin - f0.origin).dot(f0.forward).abs() < 1e-3);
        assert!(((raster.x - 128.0).abs() - 2.0).abs() < 0.01, "{raster}");
        assert!((raster.y - 128.0).abs() < 0.01, "{raster}");
    }

    #[test]
    fn the_block_lifts_by_whole_steps() {
        let scene = cornell_box();
        let (timeline, _) = timeline(MotionCase::Object { px_per_frame: 1.0 }, &scene, 64, 8, None).unwrap();
        assert!(timeline.moves_geometry());
        let lo = |t: u32| {
            let pose = timeline.pose(&scene.camera, t, 64).unwrap();
            let tris = pose.triangles.unwrap();
            let y = tris[12..22]
                .iter()
                .flat_map(|t| t.map(|v| v.y))
                .fold(f32::MAX, f32::min);
            (y, tris[0] == scene.triangles[0].vertices)
        };
        let (y0, floor_still) = lo(0);
        assert!(y0.abs() < 1e-4 && floor_still);
        let (y1, _) = lo(1);
        let (y3, _) = lo(3);
        assert!(y1 > 1.0 && (y3 - 3.0 * y1).abs() < 1e-3, "{y1} {y3}");
    }
}
