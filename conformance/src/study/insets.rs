//! Flat insets: square regions of a study scene's image on one flat surface, where the
//! low-frequency power of the error is measured (see [`crate::study`], "Flat
//! insets"), and the checks that they see their surface.

use super::scene::StudyScene;
use crate::Grid;
use anyhow::{bail, ensure, Context, Result};
use glam::Vec2;
use gpu_tracer::cornell::{GREEN, RED};
use gpu_tracer::outdoor;
use gpu_tracer::scene::SceneGpu;
use kernels::abi::TraceParams;

/// Which surface an inset must show.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Surface {
    /// The back wall (`z = 559.2`).
    BackWall,
    /// The floor (`y = 0`).
    Floor,
    /// The red (left) wall.
    RedWall,
    /// The green (right) wall.
    GreenWall,
    /// `sun-sky`: the ground where the sun's centre is visible.
    SunlitGround,
    /// `sun-sky`: the ground where the sun's whole disk is hidden (umbra).
    ShadowedGround,
    /// `sun-sky`: the wall's face towards the camera (lit by the sky only).
    ShadedWall,
}

/// A square region of the image on one flat surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Inset {
    /// Name used in reports.
    pub name: &'static str,
    /// Surface every pixel of the inset sees.
    pub surface: Surface,
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Side in pixels.
    pub side: u32,
    /// Largest relative central-difference gradient of the reference luma inside the
    /// inset, `max |grad L| / mean L` per pixel (set by [`crate::study::Study::new`]).
    pub max_gradient: f64,
}

/// The insets for an image of `size` pixels: (name, surface, x0, y0, side) as
/// fractions of the size, read off a map of the surfaces the centre rays hit (the
/// back wall right of the tall block, both side walls at mid height);
/// [`check_inset`] verifies them at every size. [`Surface::Floor`] is kept for callers
/// that place their own insets.
pub(crate) fn inset_layout(scene: StudyScene, size: u32) -> Vec<Inset> {
    let f = |v: f64| (v * size as f64).round() as u32;
    let big = (size * 3 / 16).max(4);
    let small = (size / 8).max(4);
    let mk = |name, surface, x: f64, y: f64, side| Inset {
        name,
        surface,
        x0: f(x),
        y0: f(y),
        side,
        max_gradient: f64::NAN,
    };
    if scene == StudyScene::SunSky {
        return vec![
            mk("sunlit ground", Surface::SunlitGround, 0.04, 0.74, big),
            mk(
                "shadowed ground",
                Surface::ShadowedGround,
                0.55,
                0.69,
                (size / 16).max(4),
            ),
            mk("shaded wall", Surface::ShadedWall, 0.47, 0.26, small),
        ];
    }
    vec![
        mk("back wall", Surface::BackWall, 0.54, 0.25, big),
        mk("red wall", Surface::RedWall, 0.05, 0.4, small),
        mk("green wall", Surface::GreenWall, 0.8, 0.4, small),
    ]
}

/// Whether the ray from `p` (on the ground) towards the sun's disk at angle
/// `offset` (radians) off its centre, in the plane of the sun and `y`, is
/// unoccluded.
fn sees_sun(scene: &SceneGpu, p: glam::Vec3, offset: f32) -> bool {
    let sun = outdoor::sun_direction();
    let side = sun.cross(glam::Vec3::Y).normalize();
    let dir = glam::Quat::from_axis_angle(side, offset) * sun;
    let origin = p + glam::Vec3::Y * 1e-3;
    let ray = kernels::intersect::Ray::new(origin, dir);
    !scene.occluded(&ray, f32::MAX)
}

pub(crate) fn check_inset(scene: &SceneGpu, params: &TraceParams, inset: &Inset) -> Result<()> {
    ensure!(
        inset.x0 + inset.side <= params.width && inset.y0 + inset.side <= params.height,
        "inset {} lies outside the image",
        inset.name
    );
    for y in inset.y0..inset.y0 + inset.side {
        for x in inset.x0..inset.x0 + inset.side {
            let ray = kernels::camera::primary_ray(params, x, y, Vec2::splat(0.5));
            let hit = scene
                .closest_hit(&ray)
                .with_context(|| format!("inset {}: pixel ({x}, {y}) sees nothing", inset.name))?;
            let tri = scene.triangles[hit.triangle as usize];
            let p = ray.origin + ray.dir * hit.t;
            let material = tri.v0.w as u32;
            let ok = match inset.surface {
                Surface::BackWall => p.z >= 559.0,
                Surface::Floor => p.y <= 0.5,
                Surface::RedWall => material == RED,
                Surface::GreenWall => material == GREEN,
                Surface::SunlitGround => material == outdoor::GROUND && sees_sun(scene, p, 0.0),
                Surface::ShadowedGround => {
                    let r = outdoor::SUN_ANGULAR_RADIUS;
                    material == outdoor::GROUND && [-r, 0.0, r].iter().all(|&o| !sees_sun(scene, p, o))
                }
                Surface::ShadedWall => material == outdoor::WALL && p.z > -2.01,
            };
            if !ok {
                bail!(
                    "inset {} ({}, {}, side {}): pixel ({x}, {y}) sees {p} (material {material}), not the {:?}",
                    inset.name,
                    inset.x0,
                    inset.y0,
                    inset.side,
                    inset.surface
                );
            }
        }
    }
    Ok(())
}

pub(crate) fn max_gradient(luma: &[f32], size: u32, inset: &Inset) -> f64 {
    let s = size as usize;
    let at = |x: u32, y: u32| luma[y as usize * s + x as usize] as f64;
    let mut worst: f64 = 0.0;
    for y in inset.y0 + 1..inset.y0 + inset.side - 1 {
        for x in inset.x0 + 1..inset.x0 + inset.side - 1 {
            let gx = (at(x + 1, y) - at(x - 1, y)) / 2.0;
            let gy = (at(x, y + 1) - at(x, y - 1)) / 2.0;
            worst = worst.max(gx.hypot(gy) / at(x, y).max(1e-6));
        }
    }
    worst
}

/// The inset's part of a `size x size` row-major image.
pub fn crop(image: &[f32], size: usize, inset: &Inset) -> Grid {
    let s = inset.side as usize;
    Grid::from_fn(s, s, |x, y| {
        image[(inset.y0 as usize + y) * size + inset.x0 as usize + x]
    })
    .expect("inset size")
}
