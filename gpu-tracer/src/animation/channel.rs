//! Keyframe channels: one animated property of one node ([`Channel`]),
//! sampled with glTF's STEP, LINEAR and CUBICSPLINE interpolation.

use glam::Vec4;

/// How a [`Channel`] interpolates between keys (glTF sampler
/// `interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// The value of the last key at or before the time.
    Step,
    /// Linear interpolation; rotations use the shortest-arc spherical
    /// interpolation.
    Linear,
    /// Cubic Hermite spline with per-key in- and out-tangents (glTF
    /// `CUBICSPLINE`).
    CubicSpline,
}

/// The node property a [`Channel`] animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    /// [`Trs::translation`](super::Trs::translation) (values: xyz).
    Translation,
    /// [`Trs::rotation`](super::Trs::rotation) (values: quaternion xyzw).
    Rotation,
    /// [`Trs::scale`](super::Trs::scale) (values: xyz).
    Scale,
}

/// One animated property of one node: keys and their values.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Index into [`Rig::nodes`](super::Rig::nodes).
    pub node: usize,
    /// The animated property.
    pub property: Property,
    /// Interpolation between keys.
    pub interpolation: Interpolation,
    /// Key times in seconds, finite and strictly increasing, at least one.
    pub times: Vec<f32>,
    /// Key values: one per key for [`Interpolation::Step`] and
    /// [`Interpolation::Linear`], three per key for
    /// [`Interpolation::CubicSpline`] (in-tangent, value, out-tangent, as
    /// glTF stores them; tangents in units per second). xyz (w unused) for
    /// translation and scale, a quaternion xyzw for rotation.
    pub values: Vec<Vec4>,
}

impl Channel {
    /// Values per key: 3 for cubic splines, else 1.
    fn stride(&self) -> usize {
        match self.interpolation {
            Interpolation::CubicSpline => 3,
            Interpolation::Step | Interpolation::Linear => 1,
        }
    }

    /// What is wrong with the channel's data, `None` when it is valid: no
    /// key, a non-finite or non-increasing time, a non-finite value, or a
    /// value count other than `keys` (`3 * keys` for cubic splines).
    pub fn problem(&self) -> Option<String> {
        if self.times.is_empty() {
            return Some("has no keyframe".into());
        }
        if let Some(k) = self.times.iter().position(|t| !t.is_finite()) {
            return Some(format!("key time {k} is NaN or infinite"));
        }
        if let Some(k) = self.times.windows(2).position(|w| w[1] <= w[0]) {
            return Some(format!(
                "key times are not strictly increasing (key {} at {} s, key {} at {} s)",
                k,
                self.times[k],
                k + 1,
                self.times[k + 1]
            ));
        }
        let expected = self.times.len() * self.stride();
        if self.values.len() != expected {
            return Some(format!(
                "has {} output values for {} keys, expected {expected}",
                self.values.len(),
                self.times.len()
            ));
        }
        if let Some(k) = self.values.iter().position(|v| !v.is_finite()) {
            return Some(format!("output value {k} is NaN or infinite"));
        }
        None
    }

    /// Value of key `k` (the middle one of the three of a cubic spline);
    /// zero when missing.
    fn key_value(&self, k: usize) -> Vec4 {
        let i = match self.interpolation {
            Interpolation::CubicSpline => 3 * k + 1,
            Interpolation::Step | Interpolation::Linear => k,
        };
        self.values.get(i).copied().unwrap_or(Vec4::ZERO)
    }

    /// The value at `time` seconds.
    ///
    /// Before the first key the first key's value, after the last key the
    /// last key's value (glTF clamps). Between keys: [`Interpolation::Step`]
    /// holds the earlier key; [`Interpolation::Linear`] interpolates
    /// linearly, rotations along the shortest arc (spherical, normalised);
    /// [`Interpolation::CubicSpline`] evaluates glTF's Hermite spline
    /// `(2s³-3s²+1)v₀ + d(s³-2s²+s)b₀ + (-2s³+3s²)v₁ + d(s³-s²)a₁` with `d`
    /// the key interval and `s` the fraction of it, rotations normalised.
    ///
    /// A channel without keys gives zero; missing values (see
    /// [`Channel::problem`]) read as zero. A NaN `time` gives the first key.
    pub fn sample(&self, time: f32) -> Vec4 {
        let n = self.times.len();
        if n == 0 {
            return Vec4::ZERO;
        }
        // Keys at or before `time`; NaN compares false and clamps to the start.
        let at_or_before = self.times.partition_point(|&t| t <= time);
        let value = if at_or_before == 0 {
            self.key_value(0)
        } else if at_or_before >= n {
            self.key_value(n - 1)
        } else {
            let k = at_or_before - 1;
            let (t0, t1) = (self.times[k], self.times[k + 1]);
            let d = t1 - t0;
            let s = if d > 0.0 {
                ((time - t0) / d).clamp(0.0, 1.0)
            } else {
                0.0
            };
            match self.interpolation {
                Interpolation::Step => self.key_value(k),
                Interpolation::Linear => {
                    let (a, b) = (self.key_value(k), self.key_value(k + 1));
                    match self.property {
                        Property::Rotation => slerp_shortest(a, b, s),
                        Property::Translation | Property::Scale => a.lerp(b, s),
                    }
                }
                Interpolation::CubicSpline => {
                    let get = |i: usize| self.values.get(i).copied().unwrap_or(Vec4::ZERO);
                    let (v0, b0) = (get(3 * k + 1), get(3 * k + 2));
                    let (a1, v1) = (get(3 * k + 3), get(3 * k + 4));
                    let (s2, s3) = (s * s, s * s * s);
                    v0 * (2.0 * s3 - 3.0 * s2 + 1.0)
                        + b0 * (d * (s3 - 2.0 * s2 + s))
                        + v1 * (-2.0 * s3 + 3.0 * s2)
                        + a1 * (d * (s3 - s2))
                }
            }
        };
        match self.property {
            Property::Rotation => normalize_quat(value),
            Property::Translation | Property::Scale => value,
        }
    }
}

/// `q / |q|`, or the identity for a zero or non-finite quaternion.
fn normalize_quat(q: Vec4) -> Vec4 {
    let len = q.length();
    if len.is_finite() && len > 0.0 {
        q / len
    } else {
        Vec4::W
    }
}

/// Spherical interpolation from `a` to `b` (quaternions xyzw) along the
/// shortest arc, normalised.
fn slerp_shortest(a: Vec4, b: Vec4, s: f32) -> Vec4 {
    let a = normalize_quat(a);
    let mut b = normalize_quat(b);
    let mut dot = a.dot(b);
    if dot < 0.0 {
        b = -b;
        dot = -dot;
    }
    if dot > 0.9995 {
        // Nearly parallel: normalised linear interpolation is exact enough.
        return normalize_quat(a.lerp(b, s));
    }
    let theta = dot.clamp(-1.0, 1.0).acos();
    let sin_theta = theta.sin();
    let wa = ((1.0 - s) * theta).sin() / sin_theta;
    let wb = (s * theta).sin() / sin_theta;
    normalize_quat(a * wa + b * wb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;
    use std::f32::consts::FRAC_PI_2;

    fn close(a: Vec4, b: Vec4) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    fn channel(property: Property, interpolation: Interpolation, times: &[f32], values: &[Vec4]) -> Channel {
        Channel {
            node: 0,
            property,
            interpolation,
            times: times.to_vec(),
            values: values.to_vec(),
        }
    }

    #[test]
    fn step_holds_the_earlier_key_and_clamps() {
        let c = channel(
            Property::Translation,
            Interpolation::Step,
            &[1.0, 2.0, 4.0],
            &[Vec4::X, Vec4::Y, Vec4::Z],
        );
        assert_eq!(c.problem(), None);
        assert_eq!(c.sample(0.0), Vec4::X); // before the first key
        assert_eq!(c.sample(1.0), Vec4::X);
        assert_eq!(c.sample(1.999), Vec4::X);
        assert_eq!(c.sample(2.0), Vec4::Y); // at a key: that key
        assert_eq!(c.sample(3.5), Vec4::Y);
        assert_eq!(c.sample(4.0), Vec4::Z);
        assert_eq!(c.sample(100.0), Vec4::Z); // after the last key
        assert_eq!(c.sample(f32::NAN), Vec4::X);
    }

    #[test]
    fn linear_translation_interpolates() {
        let c = channel(
            Property::Translation,
            Interpolation::Linear,
            &[0.0, 2.0],
            &[Vec4::new(0.0, 0.0, 0.0, 0.0), Vec4::new(2.0, 4.0, -6.0, 0.0)],
        );
        assert!(close(c.sample(-1.0), Vec4::ZERO));
        assert!(close(c.sample(0.5), Vec4::new(0.5, 1.0, -1.5, 0.0)));
        assert!(close(c.sample(2.0), Vec4::new(2.0, 4.0, -6.0, 0.0)));
        assert!(close(c.sample(3.0), Vec4::new(2.0, 4.0, -6.0, 0.0)));
    }

    #[test]
    fn linear_rotation_is_a_shortest_arc_slerp() {
        let q0 = Quat::IDENTITY;
        let q1 = Quat::from_rotation_y(FRAC_PI_2);
        // The second key stored negated: the same rotation, the long way round
        // in 4D; shortest-arc slerp must not take the long way.
        let c = channel(
            Property::Rotation,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[Vec4::from(q0), -Vec4::from(q1)],
        );
        let mid = Quat::from_vec4(c.sample(0.5));
        let expected = Quat::from_rotation_y(FRAC_PI_2 * 0.5);
        assert!(mid.angle_between(expected) < 1e-4, "{mid:?}");
        assert!((mid.length() - 1.0).abs() < 1e-6);
        // A quarter of the way: a quarter of the angle (not linear blending).
        let q = Quat::from_vec4(c.sample(0.25));
        assert!(q.angle_between(Quat::from_rotation_y(FRAC_PI_2 * 0.25)) < 1e-4);
        // At the keys.
        assert!(Quat::from_vec4(c.sample(0.0)).angle_between(q0) < 1e-4);
        assert!(Quat::from_vec4(c.sample(1.0)).angle_between(q1) < 1e-4);
    }

    #[test]
    fn cubic_spline_follows_the_hermite_formula() {
        // Keys at t = 1 and 3 (interval 2) with values 0 and 1, out-tangent
        // of key 0 = 1 per second, in-tangent of key 1 = 0.5 per second.
        let z = Vec4::ZERO;
        let c = channel(
            Property::Translation,
            Interpolation::CubicSpline,
            &[1.0, 3.0],
            &[
                Vec4::splat(9.0), // in-tangent of key 0: unused
                z,
                Vec4::new(1.0, 0.0, 0.0, 0.0),
                Vec4::new(0.5, 0.0, 0.0, 0.0),
                Vec4::new(1.0, 2.0, 0.0, 0.0),
                Vec4::splat(9.0), // out-tangent of key 1: unused
            ],
        );
        assert_eq!(c.problem(), None);
        assert!(close(c.sample(0.0), z));
        assert!(close(c.sample(1.0), z));
        assert!(close(c.sample(3.0), Vec4::new(1.0, 2.0, 0.0, 0.0)));
        assert!(close(c.sample(5.0), Vec4::new(1.0, 2.0, 0.0, 0.0)));
        // s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = -0.125; d = 2.
        let x = 0.5 * 0.0 + 0.125 * 2.0 * 1.0 + 0.5 * 1.0 - 0.125 * 2.0 * 0.5;
        let y = 0.5 * 2.0;
        assert!(
            close(c.sample(2.0), Vec4::new(x, y, 0.0, 0.0)),
            "{}",
            c.sample(2.0)
        );
        // Rotations come out normalised.
        let r = Channel {
            property: Property::Rotation,
            values: vec![z, Vec4::W, z, z, Vec4::from(Quat::from_rotation_x(1.0)), z],
            ..c.clone()
        };
        assert!((r.sample(2.0).length() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn invalid_channels_are_reported() {
        let ok = channel(
            Property::Scale,
            Interpolation::Linear,
            &[0.0, 1.0],
            &[Vec4::ONE; 2],
        );
        assert_eq!(ok.problem(), None);
        let cases = [
            Channel {
                times: vec![],
                values: vec![],
                ..ok.clone()
            },
            Channel {
                times: vec![1.0, 1.0],
                ..ok.clone()
            },
            Channel {
                times: vec![0.0, f32::NAN],
                ..ok.clone()
            },
            Channel {
                values: vec![Vec4::ONE; 3],
                ..ok.clone()
            },
            Channel {
                values: vec![Vec4::ONE, Vec4::splat(f32::INFINITY)],
                ..ok.clone()
            },
            Channel {
                interpolation: Interpolation::CubicSpline,
                ..ok.clone()
            },
        ];
        for c in cases {
            assert!(c.problem().is_some(), "{c:?}");
            let _ = c.sample(0.5); // never panics
        }
        assert_eq!(
            Channel {
                times: vec![],
                values: vec![],
                ..ok
            }
            .sample(1.0),
            Vec4::ZERO
        );
    }
}
