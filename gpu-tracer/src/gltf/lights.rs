//! `KHR_lights_punctual`: the point, spot and directional lights attached
//! to the scene's nodes, placed by the nodes' rest transforms.

use super::loader::{label, Loader};
use crate::error::Result;
use crate::scene::{Light, LightKind};
use glam::{Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;

impl<'p> Loader<'p> {
    /// The lights of the nodes in `order` (depth first), each placed by
    /// its node's world transform in `world` (parallel to `order`): point
    /// and spot lights at the node's origin, spot and directional lights
    /// shining along the node's `-z`. Intensities in the extension's units
    /// (candela, lux). Each light is checked ([`Light::validate`]): a
    /// negative or non-finite intensity or colour, a non-positive range,
    /// spot angles outside `0 <= inner < outer <= pi/2`, or a transform
    /// that flattens the light's direction is an error naming the light.
    pub(super) fn lights(
        &mut self,
        order: &[(gltf::Node, Option<usize>)],
        world: &[Mat4],
    ) -> Result<Vec<Light>> {
        let mut lights = Vec::new();
        for ((node, _), world) in order.iter().zip(world) {
            let Some(light) = node.light() else { continue };
            let name = format!(
                "{} on {}",
                label("light", light.index(), light.name()),
                label("node", node.index(), node.name())
            );
            let kind = match light.kind() {
                Kind::Point => LightKind::Point,
                Kind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => LightKind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                },
                Kind::Directional => LightKind::Directional { angular_radius: 0.0 },
            };
            let l = Light {
                name,
                kind,
                position: world.transform_point3(Vec3::ZERO),
                direction: world.transform_vector3(-Vec3::Z).normalize_or_zero(),
                color: Vec3::from(light.color()),
                intensity: light.intensity(),
                range: light.range(),
            };
            l.validate()?;
            lights.push(l);
        }
        Ok(lights)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::load_patched;
    use crate::error::Error;
    use crate::scene::LightKind;
    use glam::Vec3;
    use serde_json::{json, Value};

    /// The textured quad with three lights: a point light on a child of a
    /// translated parent, a spot on a node turned to shine along -y, and a
    /// directional light; `edit` changes the lights array.
    fn with_lights(edit: impl FnOnce(&mut Value)) -> crate::error::Result<super::super::GltfScene> {
        load_patched(|doc, _| {
            doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
            doc["extensionsRequired"] = json!(["KHR_lights_punctual"]);
            let mut lights = json!([
                {"name": "bulb", "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 40.0, "range": 12.0},
                {"name": "torch", "type": "spot", "intensity": 5.0,
                 "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.5}},
                {"type": "directional", "intensity": 2.5}
            ]);
            edit(&mut lights);
            doc["extensions"] = json!({"KHR_lights_punctual": {"lights": lights}});
            let nodes = doc["nodes"].as_array_mut().expect("nodes");
            let first = nodes.len();
            // -90 degrees about x turns -z into -y.
            let (s, c) = (
                std::f32::consts::FRAC_PI_4.sin(),
                std::f32::consts::FRAC_PI_4.cos(),
            );
            nodes.push(json!({"name": "lamp", "translation": [1.0, 2.0, 0.0], "children": [first + 1]}));
            nodes.push(
                json!({"translation": [0.0, 0.5, 0.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}),
            );
            nodes.push(
                json!({"name": "down", "translation": [0.0, 3.0, 1.0], "rotation": [-s, 0.0, 0.0, c],
                              "extensions": {"KHR_lights_punctual": {"light": 1}}}),
            );
            nodes.push(json!({"extensions": {"KHR_lights_punctual": {"light": 2}}}));
            let roots = doc["scenes"][0]["nodes"].as_array_mut().expect("roots");
            roots.extend([json!(first), json!(first + 2), json!(first + 3)]);
        })
    }

    #[test]
    fn lights_are_placed_by_their_nodes_in_the_extension_units() {
        let g = with_lights(|_| {}).expect("load");
        let lights = &g.scene.lights;
        assert_eq!(lights.len(), 3, "{lights:?}");
        assert!(
            !g.notices.iter().any(|n| n.contains("KHR_lights_punctual")),
            "{:?}",
            g.notices
        );
        let bulb = &lights[0];
        assert_eq!(bulb.kind, LightKind::Point);
        assert!(bulb.name.contains("bulb"), "{}", bulb.name);
        assert!(
            bulb.position.abs_diff_eq(Vec3::new(1.0, 2.5, 0.0), 1e-6),
            "{}",
            bulb.position
        );
        assert_eq!(
            (bulb.color, bulb.intensity, bulb.range),
            (Vec3::new(1.0, 0.5, 0.25), 40.0, Some(12.0))
        );
        let torch = &lights[1];
        assert_eq!(
            torch.kind,
            LightKind::Spot {
                inner_cone_angle: 0.1,
                outer_cone_angle: 0.5
            }
        );
        assert!(torch.position.abs_diff_eq(Vec3::new(0.0, 3.0, 1.0), 1e-6));
        assert!(torch.direction.abs_diff_eq(-Vec3::Y, 1e-5), "{}", torch.direction);
        // Defaults: white, range unbounded; the directional light shines along -z.
        let sun = &lights[2];
        assert_eq!(sun.kind, LightKind::Directional { angular_radius: 0.0 });
        assert_eq!((sun.color, sun.range), (Vec3::ONE, None));
        assert!(sun.direction.abs_diff_eq(-Vec3::Z, 1e-6));
        // All three join the emitter list beside the emissive quad.
        let gpu = crate::scene::SceneGpu::build(&g.scene).expect("build");
        assert_eq!(gpu.emitter_count, 2 + 3);
    }

    /// The generator's `punctual_lights.gltf` (which requires the
    /// extension and has no emissive material) loads its three lights and
    /// renders lit, not black.
    #[test]
    fn the_lights_fixture_renders_lit() {
        let g = super::super::tests::load(&super::super::tests::fixture("punctual_lights.gltf"));
        let kinds: Vec<_> = g.scene.lights.iter().map(|l| l.kind).collect();
        assert!(matches!(
            kinds[..],
            [
                LightKind::Point,
                LightKind::Spot { .. },
                LightKind::Directional { .. }
            ]
        ));
        assert!(g.scene.materials.iter().all(|m| m.emission == Vec3::ZERO));
        let scene = crate::scene::SceneGpu::build(&g.scene).expect("build");
        assert_eq!(scene.emitter_count, 3);
        let mut settings = crate::scene::TraceSettings::new(32, 32);
        settings.spp = 4;
        let params = scene.trace_params(&settings, 0).expect("params");
        let seeds = crate::cpu::white_seeds(32, 32, 1);
        let mut color = vec![glam::Vec4::ZERO; 32 * 32];
        crate::cpu::render_frame(&scene, &params, &seeds, &mut color).expect("render");
        let lit = color.iter().filter(|c| c.x > 0.01).count();
        assert!(lit > 32 * 32 / 3, "only {lit} of 1024 pixels lit");
    }

    #[test]
    fn bad_lights_are_refused_with_the_light_named() {
        type Edit = fn(&mut Value);
        let cases: [(Edit, &str); 3] = [
            (|l| l[0]["intensity"] = json!(-1.0), "intensity"),
            (
                |l| l[1]["spot"] = json!({"innerConeAngle": 0.6, "outerConeAngle": 0.5}),
                "cone",
            ),
            (
                |l| l[1]["spot"] = json!({"innerConeAngle": 0.1, "outerConeAngle": 2.0}),
                "cone",
            ),
        ];
        for (edit, parameter) in cases {
            match with_lights(edit) {
                Err(Error::InvalidLight {
                    name, parameter: p, ..
                }) => {
                    assert_eq!(p, parameter);
                    assert!(name.contains("light") && name.contains("node"), "{name}");
                }
                other => panic!("{parameter}: {other:?}"),
            }
        }
    }
}
