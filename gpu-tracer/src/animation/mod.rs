//! Node hierarchies and keyframe animation (host only): the [`Rig`] of a
//! glTF scene ([`crate::gltf`]) turns a time in seconds into world
//! matrices, world-space triangles and a camera.
//!
//! A [`Rig`] holds the nodes (parent links and rest transforms), the
//! animation [`Channel`]s (glTF's STEP, LINEAR and CUBICSPLINE samplers on
//! translation, rotation and scale), the mesh instances with their
//! triangles in local space and the camera node. [`Rig::pose`] is what an
//! animation renderer calls once per frame.
//!
//! - `channel`: [`Channel`], keyframes of one property of one node, sampled
//!   at any time by [`Channel::sample`];
//! - `rig`: [`Rig`], the node hierarchy ([`Node`], [`Trs`]) with its mesh
//!   instances and camera node, posed by [`Rig::pose`].

mod channel;
mod rig;

pub use channel::{Channel, Interpolation, Property};
pub use rig::{camera_from_matrix, normal_matrix, MeshInstance, Node, Rig, RigCamera, RigPose, Trs};
