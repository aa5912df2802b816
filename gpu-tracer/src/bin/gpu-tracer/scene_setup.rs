//! The scene a render traces: `--scene` loaded (built-in, glTF or OBJ), with
//! the command line's environment, camera and motion applied, every frame's
//! camera checked before any work.

use crate::args::{CameraPathArg, EnvArg, RenderArgs};
use anyhow::{bail, Context, Result};
use gpu_tracer::animation::Rig;
use gpu_tracer::camera_path::{CameraPath, CameraPathKind};
use gpu_tracer::scene::{Camera, Scene};
use gpu_tracer::timeline::{SceneSequence, Timeline};
use gpu_tracer::{cornell, gltf, obj};
use std::path::Path;

/// The frames' scenes of the render `args` asks for and its constant
/// environment radiance (linear RGB; zero: none, or an environment map in
/// the scene). Warns on stderr when nothing in the scene emits light.
pub(crate) fn prepare_scene(args: &RenderArgs) -> Result<(SceneSequence<'static>, glam::Vec3)> {
    // Fail on bad input before any work: scene, motion, output directory.
    let (mut scene, mut rig) = load_scene(args)?;
    let mut environment = if args.scene == "sun-sky" {
        gpu_tracer::outdoor::SKY
    } else {
        glam::Vec3::ZERO
    };
    match &args.env {
        Some(EnvArg::Constant(radiance)) => environment = *radiance,
        Some(EnvArg::Map(path)) => {
            let rotation = args.env_rotation.unwrap_or(0.0);
            scene.environment_map = Some(
                gpu_tracer::environment_file::load_environment_map(path, rotation)
                    .context("cannot use --env")?,
            );
            environment = glam::Vec3::ZERO;
        }
        None => {}
    }
    if args.env_rotation.is_some() && !matches!(args.env, Some(EnvArg::Map(_))) {
        bail!("--env-rotation applies to an environment map (--env FILE.exr|.hdr)");
    }
    if let (Some(from), Some(at)) = (args.camera_from, args.camera_at) {
        scene.camera = Camera {
            origin: from,
            target: at,
            up: glam::Vec3::Y,
            fov_y_degrees: args.fov,
        };
        scene
            .camera
            .basis()
            .context("--camera-from/--camera-at/--fov give a degenerate camera")?;
        if let Some(rig) = rig.as_mut() {
            rig.camera = None; // the command line's camera replaces the file's
        }
    }
    if !(args.fps.is_finite() && args.fps > 0.0 && args.start_time.is_finite()) {
        bail!("--fps must be a finite number > 0 and --start-time finite");
    }
    let timeline = Timeline {
        rig,
        camera_path: args.camera_path.map(|kind| CameraPath {
            kind: match kind {
                CameraPathArg::Orbit => CameraPathKind::Orbit,
                CameraPathArg::Dolly => CameraPathKind::Dolly,
                CameraPathArg::Pan => CameraPathKind::Pan,
            },
            speed: args.camera_speed,
        }),
        fps: args.fps,
        start_time: args.start_time,
    };
    // Every frame's camera is checked before rendering (a path can make the
    // camera degenerate later in the sequence).
    for t in 0..args.frames {
        timeline
            .camera(&scene.camera, t, args.height)
            .with_context(|| format!("frame {t} of the camera path or animation"))?;
    }
    let sequence = SceneSequence::new(&scene, timeline, args.height).context("cannot prepare the scene")?;
    if sequence.scene().emitter_count == 0 && environment == glam::Vec3::ZERO {
        eprintln!(
            "warning: scene {} has no emitter (no emissive material, no light) and no --env: the image will be black",
            args.scene
        );
    }

    Ok((sequence, environment))
}

/// Loads `--scene`: a built-in Cornell box, a glTF file (with its rig) or
/// an OBJ file. glTF notices (approximated features) go to stderr.
pub(crate) fn load_scene(args: &RenderArgs) -> Result<(Scene, Option<Rig>)> {
    let path = Path::new(&args.scene);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if args.camera_index.is_some() && !matches!(ext.as_deref(), Some("gltf" | "glb")) {
        bail!("--camera-index applies to glTF scenes only");
    }
    if args.scene == "cornell" {
        return Ok((cornell::cornell_box(), None));
    }
    if args.scene == "cornell-glossy" {
        return Ok((cornell::cornell_glossy(), None));
    }
    if args.scene == "sun-sky" {
        return Ok((gpu_tracer::outdoor::sun_and_sky(), None));
    }
    match ext.as_deref() {
        Some("gltf" | "glb") => {
            let loaded = gltf::load_gltf(path, args.camera_index)
                .with_context(|| format!("cannot load scene {}", args.scene))?;
            for notice in &loaded.notices {
                eprintln!("notice: {}: {notice}", args.scene);
            }
            Ok((loaded.scene, Some(loaded.rig)))
        }
        _ => Ok((
            obj::load_obj(path).with_context(|| format!("cannot load scene {}", args.scene))?,
            None,
        )),
    }
}
