//! What moves between frames, and the scene of each frame with the motion
//! the G-buffer needs.
//!
//! A [`Timeline`] combines a glTF rig (node animation moving objects and
//! the camera, [`crate::animation::Rig`]) and a [`CameraPath`] (which, when
//! given, moves whatever camera the frame has). Frame `t` is shown at time
//! `start_time + t / fps` seconds of the rig's animation; camera paths count
//! frames. [`SceneSequence`] turns a base [`Scene`] and a timeline into one
//! [`SceneGpu`] per frame: cameras of this frame and the previous one, and,
//! when objects move, vertices at this frame's pose (BVH rebuilt) with their
//! previous positions, so motion vectors cover camera and object motion.

use crate::animation::Rig;
use crate::camera_path::CameraPath;
use crate::error::{Error, Result};
use crate::scene::{Camera, Scene, SceneGpu};
use glam::Vec3;
use std::borrow::Cow;

/// What moves between frames.
#[derive(Clone, Debug)]
pub struct Timeline {
    /// Node animation (glTF), or `None`.
    pub rig: Option<Rig>,
    /// Camera path applied on top of the frame's camera, or `None`.
    pub camera_path: Option<CameraPath>,
    /// Frames per second of the sequence, finite and `> 0`.
    pub fps: f32,
    /// Animation time of frame 0 in seconds, finite.
    pub start_time: f32,
}

/// The camera and, for moving objects, the vertices of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FramePose {
    /// The frame's camera.
    pub camera: Camera,
    /// World-space vertices in [`Scene::triangles`] order when objects move;
    /// `None` when the geometry is the base scene's.
    pub triangles: Option<Vec<[Vec3; 3]>>,
    /// World-space vertex normals parallel to `triangles` (zeros for flat
    /// triangles), present exactly when `triangles` is
    /// ([`crate::animation::RigPose::normals`]).
    pub normals: Option<Vec<[Vec3; 3]>>,
}

impl Default for Timeline {
    fn default() -> Self {
        Self::still()
    }
}

impl Timeline {
    /// Nothing moves (30 fps, start at 0 s).
    pub fn still() -> Self {
        Timeline {
            rig: None,
            camera_path: None,
            fps: 30.0,
            start_time: 0.0,
        }
    }

    /// Animation time of frame `frame` in seconds.
    pub fn time(&self, frame: u32) -> f32 {
        self.start_time + frame as f32 / self.fps
    }

    /// True when objects move (the BVH is rebuilt every frame).
    pub fn moves_geometry(&self) -> bool {
        self.rig.as_ref().is_some_and(Rig::animates_geometry)
    }

    /// True when anything moves: objects, the rig's camera or a camera path
    /// with a non-zero speed.
    pub fn moves(&self) -> bool {
        self.moves_geometry()
            || self.rig.as_ref().is_some_and(Rig::animates_camera)
            || self.camera_path.is_some_and(|p| p.speed != 0.0)
    }

    /// The camera of frame `frame` for an image `height` pixels high, with
    /// `base` the scene's camera when the rig has none: the rig's camera
    /// node (if any), then the camera path. Transforms no triangle, so it is
    /// cheap enough to check a whole sequence up front.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a non-finite or non-positive `fps` or
    /// a non-finite `start_time`; [`Error::InvalidCamera`] when the path
    /// makes the camera degenerate.
    pub fn camera(&self, base: &Camera, frame: u32, height: u32) -> Result<Camera> {
        if !(self.fps.is_finite() && self.fps > 0.0) {
            return Err(Error::InvalidParameter {
                name: "fps",
                value: self.fps as u32,
                expected: "a finite number of frames per second > 0",
            });
        }
        if !self.start_time.is_finite() {
            return Err(Error::InvalidParameter {
                name: "start_time",
                value: 0,
                expected: "a finite time in seconds",
            });
        }
        let rig_camera = self.rig.as_ref().and_then(|rig| rig.camera_at(self.time(frame)));
        let camera = rig_camera.unwrap_or(*base);
        match &self.camera_path {
            Some(path) => path.camera_at(&camera, frame as f32, height),
            None => Ok(camera),
        }
    }

    /// The pose of frame `frame`: [`Timeline::camera`] and, when objects
    /// move, the rig's triangles at the frame's time.
    ///
    /// # Errors
    /// As [`Timeline::camera`].
    pub fn pose(&self, base: &Camera, frame: u32, height: u32) -> Result<FramePose> {
        let camera = self.camera(base, frame, height)?;
        let (triangles, normals) = match &self.rig {
            Some(rig) if rig.animates_geometry() => {
                let pose = rig.pose(self.time(frame));
                (Some(pose.triangles), Some(pose.normals))
            }
            _ => (None, None),
        };
        Ok(FramePose {
            camera,
            triangles,
            normals,
        })
    }
}

/// The scene of each frame of a sequence, with motion (see the module docs).
#[derive(Debug)]
pub struct SceneSequence<'a> {
    base_camera: Camera,
    timeline: Timeline,
    height: u32,
    frame: u32,
    pose: FramePose,
    scene: Cow<'a, SceneGpu>,
}

impl<'a> SceneSequence<'a> {
    /// The sequence of `base` under `timeline` for images `height` pixels
    /// high, positioned at frame 0 (whose previous frame is itself: zero
    /// motion).
    ///
    /// # Errors
    /// As [`SceneGpu::build`] and [`Timeline::pose`].
    pub fn new(base: &Scene, timeline: Timeline, height: u32) -> Result<Self> {
        let mut scene = SceneGpu::build(base)?;
        let pose = timeline.pose(&base.camera, 0, height)?;
        if let Some(t) = &pose.triangles {
            scene.set_positions(t)?;
        }
        if let Some(n) = &pose.normals {
            scene.set_normals(n)?;
        }
        scene.set_cameras(&pose.camera, &pose.camera)?;
        Ok(SceneSequence {
            base_camera: base.camera,
            timeline,
            height,
            frame: 0,
            pose,
            scene: Cow::Owned(scene),
        })
    }

    /// A sequence in which nothing moves: `scene` for every frame.
    pub fn still(scene: &'a SceneGpu, height: u32) -> Self {
        let camera = Camera {
            origin: scene.camera.origin,
            target: scene.camera.origin + scene.camera.forward,
            up: scene.camera.up,
            fov_y_degrees: 2.0 * scene.camera.tan_half_fov_y.atan().to_degrees(),
        };
        SceneSequence {
            base_camera: camera,
            timeline: Timeline::still(),
            height,
            frame: 0,
            pose: FramePose {
                camera,
                triangles: None,
                normals: None,
            },
            scene: Cow::Borrowed(scene),
        }
    }

    /// The current frame's index.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    /// The current frame's scene (cameras of this frame and the previous
    /// one; previous positions of moving objects).
    pub fn scene(&self) -> &SceneGpu {
        &self.scene
    }

    /// The timeline.
    pub fn timeline(&self) -> &Timeline {
        &self.timeline
    }

    /// Moves to the next frame. Returns `true` when the geometry changed
    /// (the scene's buffers, not only its cameras, must be uploaded again).
    ///
    /// # Errors
    /// As [`Timeline::pose`], [`SceneGpu::set_positions`] and
    /// [`SceneGpu::set_normals`]; the sequence
    /// stays at its frame then.
    pub fn advance(&mut self) -> Result<bool> {
        let next = self.frame + 1;
        if !self.timeline.moves() {
            self.frame = next;
            return Ok(false);
        }
        let pose = self.timeline.pose(&self.base_camera, next, self.height)?;
        let mut changed = false;
        if let Some(t) = &pose.triangles {
            let scene = self.scene.to_mut();
            scene.set_positions(t)?;
            if let Some(n) = &pose.normals {
                scene.set_normals(n)?;
            }
            if let Some(prev) = &self.pose.triangles {
                scene.set_previous_positions(prev)?;
            }
            changed = true;
        }
        self.scene.to_mut().set_cameras(&pose.camera, &self.pose.camera)?;
        self.pose = pose;
        self.frame = next;
        Ok(changed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera_path::CameraPathKind;
    use crate::cornell::cornell_box;

    #[test]
    fn a_camera_path_moves_the_cameras_and_keeps_the_geometry() {
        let timeline = Timeline {
            camera_path: Some(CameraPath {
                kind: CameraPathKind::Pan,
                speed: 1.0,
            }),
            ..Timeline::still()
        };
        assert!(timeline.moves() && !timeline.moves_geometry());
        let mut seq = SceneSequence::new(&cornell_box(), timeline, 64).unwrap();
        assert_eq!(seq.scene().camera, seq.scene().prev_camera);
        let nodes = seq.scene().nodes.clone();
        let first = seq.scene().camera;
        assert!(!seq.advance().unwrap());
        assert_eq!(seq.frame(), 1);
        assert_eq!(seq.scene().prev_camera, first);
        assert_ne!(seq.scene().camera, first);
        assert_eq!(seq.scene().nodes, nodes);
    }

    #[test]
    fn a_still_sequence_never_changes() {
        let scene = SceneGpu::build(&cornell_box()).unwrap();
        let mut seq = SceneSequence::still(&scene, 64);
        for _ in 0..3 {
            assert!(!seq.advance().unwrap());
        }
        assert_eq!(seq.scene(), &scene);
        let bad = Timeline {
            fps: 0.0,
            ..Timeline::still()
        };
        assert!(bad.pose(&cornell_box().camera, 1, 64).is_err());
    }
}
