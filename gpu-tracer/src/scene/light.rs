//! Punctual lights ([`Light`]): the point, spot and directional lights of
//! glTF's `KHR_lights_punctual`, and a sun disk for outdoor scenes.
//!
//! Units are the extension's, taken as the renderer's radiance unit:
//! candela for point and spot lights, lux for directional lights. A point
//! light of 1 cd gives irradiance 1 on a surface facing it at distance 1; a
//! directional light of 1 lux gives irradiance 1; an emissive surface of
//! radiance 1 (glTF's emissive factor times strength, read as nits) filling
//! the hemisphere above a surface gives irradiance pi.

use crate::error::{Error, Result};
use glam::Vec3;
use kernels::abi::{EmitterGpu, EMITTER_DIRECTIONAL, EMITTER_POINT, EMITTER_SPOT};
use std::f64::consts::FRAC_PI_2;

/// What kind of light, with the parameters of its kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Light from a point, the same intensity in every direction.
    Point,
    /// A point light restricted to a cone around [`Light::direction`]:
    /// full intensity within `inner_cone_angle` of the axis, falling
    /// smoothly to zero at `outer_cone_angle` (radians, `0 <= inner <
    /// outer <= pi/2`; the extension's defaults are 0 and `pi/4`).
    Spot {
        /// Angle from the axis where the falloff begins, radians.
        inner_cone_angle: f32,
        /// Angle from the axis where the light ends, radians.
        outer_cone_angle: f32,
    },
    /// Light from infinitely far away along [`Light::direction`]. With
    /// `angular_radius` 0 (glTF's directional light) a delta light; with a
    /// positive one (radians, `< pi/2`; the real sun's is 0.00465) a disk of
    /// uniform radiance seen under that angle, which casts soft shadows.
    /// The illuminance on a surface facing the light is
    /// [`Light::intensity`] either way.
    Directional {
        /// Half the apparent diameter of the light's disk, radians.
        angular_radius: f32,
    },
}

/// A punctual light in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// Name for messages (the glTF light's name, or its index).
    pub name: String,
    /// Kind and kind-specific parameters.
    pub kind: LightKind,
    /// Position in world units (point and spot lights; ignored for
    /// directional ones).
    pub position: Vec3,
    /// Spot: the cone's axis, the direction the light shines along.
    /// Directional: the direction the light travels (from the light into
    /// the scene). Normalised on use; must be non-zero for these kinds,
    /// ignored for point lights. glTF lights shine along their node's `-z`.
    pub direction: Vec3,
    /// Linear RGB colour, each channel `>= 0` (glTF default white).
    pub color: Vec3,
    /// Candela for point and spot lights, lux for directional lights;
    /// `>= 0`.
    pub intensity: f32,
    /// Distance in world units beyond which the light has no effect
    /// (point and spot lights; windowed smoothly as the extension
    /// recommends); `None` for an unbounded light.
    pub range: Option<f32>,
}

impl Light {
    /// A white point light of `intensity` candela at `position`.
    pub fn point(name: &str, position: Vec3, intensity: f32) -> Light {
        Light {
            name: name.to_string(),
            kind: LightKind::Point,
            position,
            direction: -Vec3::Z,
            color: Vec3::ONE,
            intensity,
            range: None,
        }
    }

    /// A white directional light of `illuminance` lux travelling along
    /// `direction`, with a disk of `angular_radius` radians (0: a delta
    /// light).
    pub fn directional(name: &str, direction: Vec3, illuminance: f32, angular_radius: f32) -> Light {
        Light {
            name: name.to_string(),
            kind: LightKind::Directional { angular_radius },
            position: Vec3::ZERO,
            direction,
            color: Vec3::ONE,
            intensity: illuminance,
            range: None,
        }
    }

    /// Checks the parameters ([`Error::InvalidLight`] says which is at
    /// fault and why).
    pub fn validate(&self) -> Result<()> {
        let bad = |parameter: &'static str, reason: String| {
            Err(Error::InvalidLight {
                name: self.name.clone(),
                parameter,
                reason,
            })
        };
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return bad(
                "intensity",
                format!("{} (it must be finite and >= 0)", self.intensity),
            );
        }
        if !(self.color.is_finite() && self.color.min_element() >= 0.0) {
            return bad(
                "colour",
                format!("{} (channels must be finite and >= 0)", self.color),
            );
        }
        if !self.position.is_finite() {
            return bad("position", format!("{} is not finite", self.position));
        }
        let needs_direction = !matches!(self.kind, LightKind::Point);
        if needs_direction && !(self.direction.is_finite() && self.direction.length() > 0.0) {
            return bad(
                "direction",
                format!("{} (it must be finite and non-zero)", self.direction),
            );
        }
        if let Some(r) = self.range {
            if !(r.is_finite() && r > 0.0) {
                return bad("range", format!("{r} (it must be finite and > 0)"));
            }
        }
        match self.kind {
            LightKind::Point => {}
            LightKind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            } => {
                let ok = inner >= 0.0 && inner < outer && outer as f64 <= FRAC_PI_2;
                if !ok {
                    return bad(
                        "cone",
                        format!(
                            "inner {inner}, outer {outer} (radians; it must be 0 <= inner < outer <= pi/2)"
                        ),
                    );
                }
            }
            LightKind::Directional { angular_radius } => {
                if !(angular_radius >= 0.0 && (angular_radius as f64) < FRAC_PI_2) {
                    return bad(
                        "angular radius",
                        format!("{angular_radius} (radians; it must be in [0, pi/2))"),
                    );
                }
            }
        }
        Ok(())
    }

    /// The light's power in the unit the emitter list compares: power
    /// divided by pi (an emissive triangle's is `area * mean(radiance)`),
    /// with the mean of the RGB intensity. Point: `4 I`. Spot: `2 I (1 -
    /// (cos inner + cos outer) / 2)` (pbrt-v4's estimate of the smooth
    /// falloff). Directional: `r^2 E`, with `r` the radius of the sphere
    /// bounding the scene (`scene_radius`), the power crossing the scene's
    /// disk. Assumes [`Light::validate`] passed.
    pub fn power(&self, scene_radius: f32) -> f64 {
        let mean = (self.color.x as f64 + self.color.y as f64 + self.color.z as f64) / 3.0;
        let i = mean * self.intensity as f64;
        match self.kind {
            LightKind::Point => 4.0 * i,
            LightKind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let c = (inner_cone_angle as f64).cos() + (outer_cone_angle as f64).cos();
                2.0 * i * (1.0 - 0.5 * c)
            }
            LightKind::Directional { .. } => (scene_radius as f64).powi(2) * i,
        }
    }

    /// The light's entry of the emitter list, without its selection
    /// probability (`cdf`, `pdf` 0). Assumes [`Light::validate`] passed.
    pub fn emitter(&self) -> EmitterGpu {
        let rgb = (self.color * self.intensity).extend(0.0);
        let direction = self.direction.normalize_or_zero().extend(0.0);
        let range = self.range.unwrap_or(0.0);
        match self.kind {
            LightKind::Point => EmitterGpu {
                kind: EMITTER_POINT,
                position: self.position.extend(range),
                intensity: rgb,
                ..EmitterGpu::NONE
            },
            LightKind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let (ci, co) = ((inner_cone_angle as f64).cos(), (outer_cone_angle as f64).cos());
                EmitterGpu {
                    kind: EMITTER_SPOT,
                    position: self.position.extend(range),
                    direction,
                    intensity: rgb,
                    shape: glam::Vec4::new(co as f32, (1.0 / (ci - co).max(1e-3)) as f32, 0.0, 0.0),
                    ..EmitterGpu::NONE
                }
            }
            LightKind::Directional { angular_radius } => EmitterGpu {
                kind: EMITTER_DIRECTIONAL,
                direction,
                intensity: rgb,
                // 1 - cos r = 2 sin^2(r / 2), without cancellation.
                shape: glam::Vec4::new(
                    (2.0 * (angular_radius as f64 / 2.0).sin().powi(2)) as f32,
                    0.0,
                    0.0,
                    0.0,
                ),
                ..EmitterGpu::NONE
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_lights_are_refused_with_the_parameter_named() {
        let ok = Light::point("p", Vec3::ZERO, 10.0);
        assert!(ok.validate().is_ok());
        let spot = |inner: f32, outer: f32| Light {
            kind: LightKind::Spot {
                inner_cone_angle: inner,
                outer_cone_angle: outer,
            },
            ..ok.clone()
        };
        assert!(spot(0.0, 0.785).validate().is_ok());
        let cases = [
            (
                Light {
                    intensity: -1.0,
                    ..ok.clone()
                },
                "intensity",
            ),
            (
                Light {
                    intensity: f32::NAN,
                    ..ok.clone()
                },
                "intensity",
            ),
            (
                Light {
                    color: Vec3::new(1.0, -0.5, 1.0),
                    ..ok.clone()
                },
                "colour",
            ),
            (
                Light {
                    position: Vec3::NAN,
                    ..ok.clone()
                },
                "position",
            ),
            (
                Light {
                    range: Some(0.0),
                    ..ok.clone()
                },
                "range",
            ),
            (spot(0.5, 0.5), "cone"),
            (spot(-0.1, 0.5), "cone"),
            (spot(0.1, 1.7), "cone"),
            (spot(0.1, f32::NAN), "cone"),
            (
                Light {
                    direction: Vec3::ZERO,
                    ..spot(0.1, 0.5)
                },
                "direction",
            ),
            (Light::directional("d", Vec3::ZERO, 1.0, 0.0), "direction"),
            (Light::directional("d", -Vec3::Y, 1.0, 2.0), "angular radius"),
            (Light::directional("d", -Vec3::Y, 1.0, f32::NAN), "angular radius"),
        ];
        for (light, parameter) in cases {
            match light.validate() {
                Err(Error::InvalidLight {
                    parameter: p,
                    ref name,
                    ..
                }) => {
                    assert_eq!((p, name.as_str()), (parameter, light.name.as_str()))
                }
                other => panic!("{light:?}: {other:?}"),
            }
        }
        let msg = Light {
            intensity: -2.0,
            ..ok
        }
        .validate()
        .unwrap_err()
        .to_string();
        assert!(
            msg.contains("light 'p'") && msg.contains("intensity") && msg.contains("-2"),
            "{msg}"
        );
    }

    /// Powers in units of power / pi: a point light radiates 4 pi I; a spot
    /// with both angles at pi/2 is half a point light; a sun lights the
    /// scene's disk.
    #[test]
    fn powers_follow_the_kinds() {
        let p = Light::point("p", Vec3::ZERO, 3.0);
        assert!((p.power(1.0) - 12.0).abs() < 1e-9);
        let half = Light {
            kind: LightKind::Spot {
                inner_cone_angle: std::f32::consts::FRAC_PI_2 - 1e-4,
                outer_cone_angle: std::f32::consts::FRAC_PI_2,
            },
            ..p.clone()
        };
        assert!((half.power(1.0) - 6.0).abs() < 1e-3, "{}", half.power(1.0));
        let sun = Light::directional("s", -Vec3::Y, 2.0, 0.0);
        assert!((sun.power(10.0) - 200.0).abs() < 1e-9);
        let e = Light::directional("s", Vec3::new(0.0, -2.0, 0.0), 2.0, 0.001).emitter();
        assert_eq!(e.direction, -glam::Vec4::Y);
        assert!((e.shape.x as f64 - (1.0 - 0.001f64.cos())).abs() < 1e-12);
    }
}
