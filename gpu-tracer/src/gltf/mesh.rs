//! Mesh primitives: the triangles of one primitive in its node's space,
//! with their texture coordinates, tangents and normals (triangles, strips
//! and fans, indexed or not, sparse accessors included).

use super::attribute::Attribute;
use super::loader::Loader;
use crate::error::{Error, Result};
use glam::{Vec2, Vec3, Vec4};
use gltf::accessor::{DataType, Dimensions};

impl<'p> Loader<'p> {
    /// The triangles of a primitive in its node's space: corners, their
    /// texture coordinates (zero when `set` is `None`), when `tangents`
    /// is set and the primitive has a `TANGENT` attribute, the corners'
    /// tangents (node space, `w` = bitangent sign), and when it has a
    /// `NORMAL` attribute the corners' normals (node space, as stored: NaN
    /// or zero ones are left for the caller to drop).
    pub(super) fn primitive(
        &self,
        primitive: &gltf::Primitive,
        element: &str,
        set: Option<u32>,
        tangents: bool,
    ) -> Result<Vec<PrimitiveTriangle>> {
        use gltf::mesh::Mode;
        let strip_or_fan = match primitive.mode() {
            Mode::Triangles => false,
            Mode::TriangleStrip | Mode::TriangleFan => true,
            other => {
                return Err(self.content(
                    element,
                    format!("mode {other:?} is not supported (only triangles, triangle strips and fans)"),
                ))
            }
        };
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            return Err(self.content(element, "has no POSITION attribute"));
        };
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        let points: Vec<Vec3> = self
            .read_attribute::<3>(&positions, element, "POSITION", Attribute::Position)?
            .into_iter()
            .map(Vec3::from)
            .collect();
        if let Some(vertex) = points.iter().position(|p| !p.is_finite()) {
            return Err(Error::NonFiniteVertex {
                path: self.path.to_path_buf(),
                model: element.to_string(),
                vertex,
            });
        }

        let uvs: Vec<Vec2> = match set {
            None => vec![Vec2::ZERO; points.len()],
            Some(set) => {
                let what = format!("TEXCOORD_{set}");
                let Some(acc) = primitive.get(&gltf::Semantic::TexCoords(set)) else {
                    return Err(self.content(
                        element,
                        format!("its material is textured but the primitive has no {what}"),
                    ));
                };
                let uvs: Vec<Vec2> = self
                    .read_attribute::<2>(&acc, element, &what, Attribute::TexCoord)?
                    .into_iter()
                    .map(Vec2::from)
                    .collect();
                if uvs.len() != points.len() {
                    return Err(self.content(
                        element,
                        format!("{what} has {} values for {} positions", acc.count(), points.len()),
                    ));
                }
                if let Some(k) = uvs.iter().position(|uv| !uv.is_finite()) {
                    return Err(self.content(element, format!("{what} value {k} is NaN or infinite")));
                }
                uvs
            }
        };

        let tangents: Option<Vec<Vec4>> = match primitive.get(&gltf::Semantic::Tangents) {
            Some(acc) if tangents => {
                let values: Vec<Vec4> = self
                    .read_attribute::<4>(&acc, element, "TANGENT", Attribute::Tangent)?
                    .into_iter()
                    .map(Vec4::from)
                    .collect();
                if values.len() != points.len() {
                    return Err(self.content(
                        element,
                        format!(
                            "TANGENT has {} values for {} positions",
                            acc.count(),
                            points.len()
                        ),
                    ));
                }
                if let Some(k) = values.iter().position(|t| !t.is_finite()) {
                    return Err(self.content(element, format!("TANGENT value {k} is NaN or infinite")));
                }
                Some(values)
            }
            _ => None,
        };

        let normals: Option<Vec<Vec3>> = match primitive.get(&gltf::Semantic::Normals) {
            Some(acc) => {
                let values: Vec<Vec3> = self
                    .read_attribute::<3>(&acc, element, "NORMAL", Attribute::Normal)?
                    .into_iter()
                    .map(Vec3::from)
                    .collect();
                if values.len() != points.len() {
                    return Err(self.content(
                        element,
                        format!("NORMAL has {} values for {} positions", acc.count(), points.len()),
                    ));
                }
                Some(values)
            }
            None => None,
        };

        let indices: Vec<u32> = match primitive.indices() {
            Some(acc) => {
                let int_types = [DataType::U8, DataType::U16, DataType::U32].map(|t| (t, Dimensions::Scalar));
                self.check_accessor(&acc, element, "indices", &int_types, false)?;
                let indices: Vec<u32> = reader
                    .read_indices()
                    .map(|it| it.into_u32().collect())
                    .unwrap_or_default();
                if indices.len() != acc.count() {
                    return Err(self.content(element, "index data cannot be read"));
                }
                if let Some(k) = indices.iter().position(|&i| i as usize >= points.len()) {
                    return Err(self.content(
                        element,
                        format!(
                            "index {k} is {}, out of range: the primitive has {} vertices",
                            indices[k],
                            points.len()
                        ),
                    ));
                }
                indices
            }
            None => (0..points.len() as u32).collect(),
        };
        let corners: Vec<[u32; 3]> = match primitive.mode() {
            Mode::TriangleStrip => (0..indices.len().saturating_sub(2))
                .map(|i| {
                    let odd = i % 2;
                    [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
                })
                .collect(),
            Mode::TriangleFan => (1..indices.len().saturating_sub(1))
                .map(|i| [indices[i], indices[i + 1], indices[0]])
                .collect(),
            _ => {
                if !indices.chunks_exact(3).remainder().is_empty() {
                    return Err(self.content(
                        element,
                        format!("{} vertices do not make whole triangles", indices.len()),
                    ));
                }
                indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
            }
        };
        Ok(corners
            .into_iter()
            .filter(|[a, b, c]| !strip_or_fan || (a != b && b != c && a != c))
            .map(|c| {
                let c = c.map(|i| i as usize);
                PrimitiveTriangle {
                    corners: c.map(|i| points[i]),
                    uvs: c.map(|i| uvs[i]),
                    tangents: tangents.as_ref().map(|t| c.map(|i| t[i])),
                    normals: normals.as_ref().map(|n| c.map(|i| n[i])),
                }
            })
            .collect())
    }
}

/// One triangle of a primitive, in its node's space.
pub(super) struct PrimitiveTriangle {
    /// Corner positions.
    pub corners: [Vec3; 3],
    /// The corners' texture coordinates (zero without a set).
    pub uvs: [Vec2; 3],
    /// The corners' `TANGENT`s when read (`w` = bitangent sign).
    pub tangents: Option<[Vec4; 3]>,
    /// The corners' `NORMAL`s when the primitive has them, as stored.
    pub normals: Option<[Vec3; 3]>,
}

#[cfg(test)]
mod tests {
    use crate::error::Error;
    use crate::gltf::tests::{accessor_offset, content_error, load_patched, quad_accessor};
    use crate::scene::Triangle;
    use glam::{Vec2, Vec3};
    use serde_json::{json, Value};

    /// Makes the quad's POSITION accessor sparse with one replaced vertex:
    /// u16 index `index` (padded to 4 bytes) and `value`, appended to `bin`
    /// with two new buffer views. Returns the accessor's index.
    fn sparse_position(doc: &mut Value, bin: &mut Vec<u8>, index: u16, value: [f32; 3]) -> usize {
        let offset = bin.len();
        bin.extend_from_slice(&index.to_le_bytes());
        bin.extend_from_slice(&[0, 0]);
        for v in value {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        let views = doc["bufferViews"].as_array_mut().expect("views");
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 2}));
        views.push(json!({"buffer": 0, "byteOffset": offset + 4, "byteLength": 12}));
        let n = views.len();
        let a = quad_accessor(doc, "POSITION");
        doc["accessors"][a]["sparse"] = json!({
            "count": 1,
            "indices": {"bufferView": n - 2, "componentType": 5123},
            "values": {"bufferView": n - 1}
        });
        a
    }

    #[test]
    fn non_finite_data_and_bad_indices_are_errors() {
        let err = load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "POSITION")) + 3 * 4 + 4; // vertex 1, y
            bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        })
        .expect_err("NaN");
        match &err {
            Error::NonFiniteVertex { model, vertex, .. } => {
                assert_eq!((model.as_str(), *vertex), ("mesh 'checker_quad' primitive 0", 1));
            }
            other => panic!("{other:?}"),
        }
        assert!(err.to_string().contains("textured_quad.gltf"), "{err}");
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "TEXCOORD_0")) + 2 * 8;
            bin[at..at + 4].copy_from_slice(&f32::INFINITY.to_le_bytes());
        }));
        assert!(reason.contains("TEXCOORD_0 value 2"), "{reason}");
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let at = accessor_offset(doc, quad_accessor(doc, "indices")) + 2 * 4;
            bin[at..at + 2].copy_from_slice(&200u16.to_le_bytes());
        }));
        assert!(reason.contains("index 4 is 200, out of range"), "{reason}");
    }

    #[test]
    fn sparse_accessors_strips_fans_and_normalized_uvs_are_read() {
        // Sparse: vertex 0 of the quad replaced by (-1, -1, 5).
        let g = load_patched(|doc, bin| {
            let a = sparse_position(doc, bin, 0, [-1.0, -1.0, 5.0]);
            doc["accessors"][a]["max"][2] = json!(5.0);
        })
        .expect("sparse loads");
        assert_eq!(g.scene.triangles[0].vertices[0], Vec3::new(-1.0, -1.0, 5.0));
        assert_eq!(g.scene.triangles[0].vertices[1], Vec3::new(1.0, -1.0, 0.0));
        // A sparse index out of range.
        let (_, reason) = content_error(load_patched(|doc, bin| {
            sparse_position(doc, bin, 9, [0.0; 3]);
        }));
        assert!(reason.contains("sparse index 0 is 9"), "{reason}");
        // Sparse without a base view: a huge count is refused, not allocated.
        let (_, reason) = content_error(load_patched(|doc, _| {
            let a = quad_accessor(doc, "POSITION");
            let acc = doc["accessors"][a].as_object_mut().expect("accessor");
            acc.remove("bufferView");
            acc.insert("count".into(), json!(1u64 << 40));
            acc.insert(
                "sparse".into(),
                json!({"count": 1, "indices": {"bufferView": 2, "componentType": 5123}, "values": {"bufferView": 0}}),
            );
        }));
        assert!(reason.contains("without a buffer view"), "{reason}");

        // Strip [0, 1, 3, 2] and fan [0, 1, 2, 3]: the same quad, front +Z.
        for (mode, order) in [(5, [0u16, 1, 3, 2]), (6, [0, 1, 2, 3])] {
            let g = load_patched(|doc, bin| {
                let a = quad_accessor(doc, "indices");
                let at = accessor_offset(doc, a);
                for (k, i) in order.iter().enumerate() {
                    bin[at + 2 * k..at + 2 * k + 2].copy_from_slice(&i.to_le_bytes());
                }
                doc["accessors"][a]["count"] = json!(4);
                doc["meshes"][0]["primitives"][0]["mode"] = json!(mode);
            })
            .expect("loads");
            let quad: Vec<&Triangle> = g.scene.triangles.iter().filter(|t| t.object == 0).collect();
            assert_eq!(quad.len(), 2, "mode {mode}");
            let area: f32 = quad
                .iter()
                .map(|t| {
                    (t.vertices[1] - t.vertices[0])
                        .cross(t.vertices[2] - t.vertices[0])
                        .z
                        * 0.5
                })
                .sum();
            assert!((area - 4.0).abs() < 1e-5, "mode {mode}: signed area {area}");
        }

        // Normalised u8 texture coordinates: 255 -> 1.
        let g = load_patched(|doc, bin| {
            let offset = bin.len();
            bin.extend_from_slice(&[0, 255, 255, 255, 255, 0, 0, 0]);
            let views = doc["bufferViews"].as_array_mut().expect("views");
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 8}));
            let view = views.len() - 1;
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a] = json!({
                "bufferView": view, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"
            });
        })
        .expect("u8 UVs load");
        assert_eq!(
            g.scene.triangles[0].uvs,
            [Vec2::new(0.0, 1.0), Vec2::ONE, Vec2::new(1.0, 0.0)]
        );
        // Not normalised: rejected.
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let offset = bin.len();
            bin.extend_from_slice(&[0; 8]);
            let views = doc["bufferViews"].as_array_mut().expect("views");
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": 8}));
            let view = views.len() - 1;
            let a = quad_accessor(doc, "TEXCOORD_0");
            doc["accessors"][a] =
                json!({"bufferView": view, "componentType": 5121, "count": 4, "type": "VEC2"});
        }));
        assert!(reason.contains("normalized"), "{reason}");
    }
}
