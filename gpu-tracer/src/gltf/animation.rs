//! Animation: the translation, rotation and scale channels of every
//! animation, read into [`Channel`]s of the rig.

use super::loader::{label, Loader};
use crate::animation::{Channel, Interpolation, Property};
use crate::error::Result;
use glam::{Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};

impl<'p> Loader<'p> {
    /// Translation, rotation and scale channels of every animation.
    pub(super) fn channels(&mut self, rig_index: &[Option<usize>]) -> Result<Vec<Channel>> {
        let document = self.document.clone();
        let mut channels = Vec::new();
        let (mut weights, mut outside) = (false, 0usize);
        let animation_count = document.animations().len();
        for animation in document.animations() {
            let anim_label = label("animation", animation.index(), animation.name());
            for (c, channel) in animation.channels().enumerate() {
                let element = format!("{anim_label} channel {c}");
                let target = channel.target();
                let property = match target.property() {
                    gltf::animation::Property::Translation => Property::Translation,
                    gltf::animation::Property::Rotation => Property::Rotation,
                    gltf::animation::Property::Scale => Property::Scale,
                    gltf::animation::Property::MorphTargetWeights => {
                        weights = true;
                        continue;
                    }
                };
                let Some(node) = rig_index.get(target.node().index()).copied().flatten() else {
                    outside += 1;
                    continue;
                };
                let sampler = channel.sampler();
                let interpolation = match sampler.interpolation() {
                    gltf::animation::Interpolation::Step => Interpolation::Step,
                    gltf::animation::Interpolation::Linear => Interpolation::Linear,
                    gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
                };
                self.check_accessor(
                    &sampler.input(),
                    &element,
                    "input (times)",
                    &[(DataType::F32, Dimensions::Scalar)],
                    false,
                )?;
                let outputs: &[(DataType, Dimensions)] = match property {
                    Property::Rotation => &[
                        (DataType::F32, Dimensions::Vec4),
                        (DataType::I8, Dimensions::Vec4),
                        (DataType::U8, Dimensions::Vec4),
                        (DataType::I16, Dimensions::Vec4),
                        (DataType::U16, Dimensions::Vec4),
                    ],
                    Property::Translation | Property::Scale => &[(DataType::F32, Dimensions::Vec3)],
                };
                self.check_accessor(&sampler.output(), &element, "output (values)", outputs, true)?;
                let reader = channel.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
                let times: Vec<f32> = reader.read_inputs().map(|it| it.collect()).unwrap_or_default();
                let values: Vec<Vec4> = match reader.read_outputs() {
                    Some(gltf::animation::util::ReadOutputs::Translations(it))
                    | Some(gltf::animation::util::ReadOutputs::Scales(it)) => {
                        it.map(|v| Vec3::from(v).extend(0.0)).collect()
                    }
                    Some(gltf::animation::util::ReadOutputs::Rotations(r)) => {
                        r.into_f32().map(Vec4::from).collect()
                    }
                    _ => Vec::new(),
                };
                let channel = Channel {
                    node,
                    property,
                    interpolation,
                    times,
                    values,
                };
                if let Some(reason) = channel.problem() {
                    return Err(self.content(element, reason));
                }
                channels.push(channel);
            }
        }
        if weights {
            self.notices
                .push("morph-target weight animation is not supported: ignored".into());
        }
        if outside > 0 {
            self.notices.push(format!(
                "{outside} animation channel(s) target nodes outside the loaded scene: ignored"
            ));
        }
        if animation_count > 1 && !channels.is_empty() {
            self.notices.push(format!(
                "the file's {animation_count} animations are played together"
            ));
        }
        Ok(channels)
    }
}

#[cfg(test)]
mod tests {
    use crate::error::Result;
    use crate::gltf::tests::{accessor_offset, content_error, load_fixture_patched};
    use crate::gltf::GltfScene;
    use serde_json::{json, Value};

    /// `animated_room.gltf` after `edit`.
    fn load_room_patched(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Result<GltfScene> {
        load_fixture_patched("animated_room", edit)
    }

    fn sampler_accessor(doc: &Value, sampler: usize, which: &str) -> usize {
        doc["animations"][0]["samplers"][sampler][which]
            .as_u64()
            .expect("accessor") as usize
    }

    #[test]
    fn invalid_animation_data_is_an_error() {
        // Times 0, 2, 1: not increasing.
        let (element, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 0, "input")) + 4;
            bin[at..at + 4].copy_from_slice(&2.0f32.to_le_bytes());
        }));
        assert_eq!(element, "animation 'walkthrough' channel 0");
        assert!(reason.contains("strictly increasing"), "{reason}");
        // A NaN time.
        let (_, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 0, "input"));
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        }));
        assert!(reason.contains("NaN"), "{reason}");
        // A NaN value.
        let (element, reason) = content_error(load_room_patched(|doc, bin| {
            let at = accessor_offset(doc, sampler_accessor(doc, 2, "output")) + 16;
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        }));
        assert_eq!(element, "animation 'walkthrough' channel 2");
        assert!(reason.contains("output value 1"), "{reason}");
        // Too few values.
        let (_, reason) = content_error(load_room_patched(|doc, _| {
            let a = sampler_accessor(doc, 1, "output");
            doc["accessors"][a]["count"] = json!(2);
        }));
        assert!(reason.contains("2 output values for 3 keys"), "{reason}");
        // CUBICSPLINE needs three values per key.
        let (_, reason) = content_error(load_room_patched(|doc, _| {
            doc["animations"][0]["samplers"][0]["interpolation"] = json!("CUBICSPLINE");
        }));
        assert!(reason.contains("expected 9"), "{reason}");
        // Morph weights: a notice, not an error.
        let g = load_room_patched(|doc, _| {
            let channels = doc["animations"][0]["channels"].as_array_mut().expect("channels");
            channels.push(json!({"sampler": 0, "target": {"node": 7, "path": "weights"}}));
        })
        .expect("loads");
        assert_eq!(g.rig.channels.len(), 3);
        assert!(
            g.notices.iter().any(|n| n.contains("morph-target weight")),
            "{:?}",
            g.notices
        );
    }
}
