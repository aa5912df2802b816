//! Vertex attributes (`POSITION`, `NORMAL`, `TEXCOORD_n`, `TANGENT`) read as `f32` vectors from
//! accessors of every component type the specification allows, including
//! the integer types of `KHR_mesh_quantization`.
//!
//! # Component types
//!
//! | attribute | core glTF 2.0 | with `KHR_mesh_quantization` in `extensionsUsed` |
//! |---|---|---|
//! | `POSITION` (`VEC3`) | float | also byte, unsigned byte, short, unsigned short, normalised or not |
//! | `TEXCOORD_n` (`VEC2`) | float, unsigned byte and unsigned short normalised | also byte and short (normalised or not), unsigned byte and unsigned short not normalised |
//! | `NORMAL` (`VEC3`) | float | also byte and short normalised |
//! | `TANGENT` (`VEC4`) | float | also byte and short normalised |
//!
//! Normalised integers map to `[0, 1]` (unsigned) or `[-1, 1]` (signed) as
//! the specification's "Accessor data types" section says: `c / 255`,
//! `c / 65535`, `max(c / 127, -1)`, `max(c / 32767, -1)`; integers that are
//! not normalised are converted to the same value as `f32` (exact: every
//! 8- and 16-bit integer is). Unsigned int (`5125`) is never a valid
//! component type for these attributes. Byte strides, offsets and sparse
//! accessors are honoured (the `gltf` crate's accessor iterator, after
//! [`Loader::check_accessor`] checked the ranges).

use super::loader::{Loader, MESH_QUANTIZATION};
use crate::error::Result;
use gltf::accessor::{DataType, Dimensions, Item, Iter};

/// Which vertex attribute is read (its component-type rules differ).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Attribute {
    /// `POSITION`, `VEC3`.
    Position,
    /// `TEXCOORD_n`, `VEC2`.
    TexCoord,
    /// `TANGENT`, `VEC4` (`w` = bitangent sign).
    Tangent,
    /// `NORMAL`, `VEC3` (vertex normals for smooth shading).
    Normal,
}

impl Attribute {
    /// The accepted component types, for messages.
    fn accepted(self, quantized: bool) -> &'static str {
        match (self, quantized) {
            (Attribute::Position, false) => {
                "F32 (integer positions need KHR_mesh_quantization in extensionsUsed)"
            }
            (Attribute::TexCoord, false) => {
                "F32, or normalized U8 or U16 (other integer types need KHR_mesh_quantization in extensionsUsed)"
            }
            (Attribute::Tangent | Attribute::Normal, false) => {
                "F32 (normalized integers need KHR_mesh_quantization in extensionsUsed)"
            }
            (Attribute::Tangent | Attribute::Normal, true) => "F32, or normalized I8 or I16",
            (_, true) => "F32, or I8, U8, I16 or U16 (normalized or not)",
        }
    }

    /// Whether `(data_type, normalized)` is accepted.
    fn accepts(self, data_type: DataType, normalized: bool, quantized: bool) -> bool {
        if matches!(self, Attribute::Tangent | Attribute::Normal) {
            return match data_type {
                DataType::F32 => !normalized,
                DataType::I8 | DataType::I16 => quantized && normalized,
                _ => false,
            };
        }
        match data_type {
            DataType::F32 => !normalized,
            DataType::U32 => false,
            DataType::U8 | DataType::U16 => quantized || (self == Attribute::TexCoord && normalized),
            DataType::I8 | DataType::I16 => quantized,
        }
    }
}

impl<'p> Loader<'p> {
    /// Whether the file declares `KHR_mesh_quantization`.
    fn mesh_quantization(&self) -> bool {
        self.document.extensions_used().any(|e| e == MESH_QUANTIZATION)
    }

    /// The values of vertex attribute `acc` (`N` = 3 for
    /// [`Attribute::Position`] and [`Attribute::Normal`], 2 for [`Attribute::TexCoord`], 4 for
    /// [`Attribute::Tangent`]) as `f32`
    /// vectors, one per element (module docs for the conversion).
    ///
    /// # Errors
    /// [`Error::GltfContent`](crate::Error::GltfContent) naming `element`
    /// and `what` when the accessor's type is not `VEC{N}` of an accepted
    /// component type (module docs), or [`Loader::check_accessor`] refuses
    /// it, or its data cannot be read.
    pub(super) fn read_attribute<const N: usize>(
        &self,
        acc: &gltf::Accessor,
        element: &str,
        what: &str,
        attribute: Attribute,
    ) -> Result<Vec<[f32; N]>>
    where
        [f32; N]: Item,
        [i8; N]: Item,
        [u8; N]: Item,
        [i16; N]: Item,
        [u16; N]: Item,
    {
        let dimensions = match N {
            2 => Dimensions::Vec2,
            4 => Dimensions::Vec4,
            _ => Dimensions::Vec3,
        };
        let (data_type, normalized) = (acc.data_type(), acc.normalized());
        let quantized = self.mesh_quantization();
        if acc.dimensions() != dimensions || !attribute.accepts(data_type, normalized, quantized) {
            let norm = if normalized && data_type != DataType::F32 {
                "normalized "
            } else if normalized {
                "\"normalized\" "
            } else {
                ""
            };
            return Err(self.content(
                element,
                format!(
                    "{what} (accessor {}): is {:?} of {norm}{data_type:?}, expected {dimensions:?} of {}",
                    acc.index(),
                    acc.dimensions(),
                    attribute.accepted(quantized)
                ),
            ));
        }
        self.check_accessor(acc, element, what, &[(data_type, dimensions)], false)?;
        let values = match (data_type, normalized) {
            (DataType::F32, _) => self.read_components::<f32, N>(acc, |c| c),
            (DataType::I8, true) => self.read_components::<i8, N>(acc, |c| (c as f32 / 127.0).max(-1.0)),
            (DataType::U8, true) => self.read_components::<u8, N>(acc, |c| c as f32 / 255.0),
            (DataType::I16, true) => self.read_components::<i16, N>(acc, |c| (c as f32 / 32767.0).max(-1.0)),
            (DataType::U16, true) => self.read_components::<u16, N>(acc, |c| c as f32 / 65535.0),
            (DataType::I8, false) => self.read_components::<i8, N>(acc, f32::from),
            (DataType::U8, false) => self.read_components::<u8, N>(acc, f32::from),
            (DataType::I16, false) => self.read_components::<i16, N>(acc, f32::from),
            (DataType::U16, false) => self.read_components::<u16, N>(acc, f32::from),
            (DataType::U32, _) => None,
        };
        match values {
            Some(v) if v.len() == acc.count() => Ok(v),
            _ => Err(self.content(element, format!("{what} data cannot be read"))),
        }
    }

    /// Every element of `acc` (checked) with its components of type `T`
    /// converted by `to_f32`.
    fn read_components<T: Copy, const N: usize>(
        &self,
        acc: &gltf::Accessor,
        to_f32: impl Fn(T) -> f32,
    ) -> Option<Vec<[f32; N]>>
    where
        [T; N]: Item,
    {
        let iter = Iter::<[T; N]>::new(acc.clone(), |b: gltf::Buffer| {
            self.buffers.get(b.index()).map(|d| d.0.as_slice())
        })?;
        Some(iter.map(|c| c.map(&to_f32)).collect())
    }
}

#[cfg(test)]
mod tests {
    use crate::gltf::tests::{content_error, load_patched, quad_accessor};
    use glam::{Vec2, Vec3};
    use serde_json::{json, Value};

    /// Replaces accessor `a` by `count` elements of `values` (little-endian
    /// bytes already encoded) in a new buffer view with `stride` (none when
    /// 0), component type `component` and `normalized`.
    fn replace_accessor(
        doc: &mut Value,
        bin: &mut Vec<u8>,
        a: usize,
        bytes: &[u8],
        stride: usize,
        component: u32,
        normalized: bool,
    ) {
        bin.resize(bin.len().next_multiple_of(4), 0);
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        let views = doc["bufferViews"].as_array_mut().expect("views");
        let mut view = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()});
        if stride > 0 {
            view["byteStride"] = json!(stride);
        }
        views.push(view);
        let view = views.len() - 1;
        let acc = doc["accessors"][a].as_object_mut().expect("accessor");
        acc.insert("bufferView".into(), json!(view));
        acc.insert("byteOffset".into(), json!(0));
        acc.insert("componentType".into(), json!(component));
        acc.insert("normalized".into(), json!(normalized));
    }

    fn declare_quantization(doc: &mut Value) {
        doc["extensionsUsed"]
            .as_array_mut()
            .expect("extensionsUsed")
            .push(json!("KHR_mesh_quantization"));
        doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    }

    /// The quad's corners (-1,-1,0), (1,-1,0), (1,1,0), (-1,1,0) as 16-bit
    /// positions padded to 8 bytes per vertex (byteStride 8), normalised
    /// (short: 32767 = 1) with a node scale of 2 or not: the same triangles
    /// as the float fixture.
    #[test]
    fn quantized_positions_give_the_float_twin_triangles() {
        let float = load_patched(|_, _| {}).expect("float");
        let corners: [[i16; 3]; 4] = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]];
        for (component, normalized, unit, scale) in [
            (5122u32, false, 1i32, 1.0f32), // short
            (5122, true, 16383, 2.0),       // normalised short: 16383/32767 * 2 ~ 1
            (5120, false, 1, 1.0),          // byte
            (5120, true, 127, 1.0),         // normalised byte: 127 -> 1, -127 -> -1
        ] {
            let g = load_patched(|doc, bin| {
                declare_quantization(doc);
                let mut bytes = Vec::new();
                for c in corners {
                    for x in c {
                        let v = x as i32 * unit;
                        match component {
                            5122 => bytes.extend_from_slice(&(v as i16).to_le_bytes()),
                            _ => bytes.push(v as i8 as u8),
                        }
                    }
                    bytes.resize(bytes.len().next_multiple_of(8), 0);
                }
                let a = quad_accessor(doc, "POSITION");
                replace_accessor(doc, bin, a, &bytes, 8, component, normalized);
                doc["accessors"][a]["min"] = json!([-unit, -unit, 0]);
                doc["accessors"][a]["max"] = json!([unit, unit, 0]);
                doc["nodes"][0]["scale"] = json!([scale, scale, scale]);
            })
            .unwrap_or_else(|e| panic!("component {component}: {e}"));
            assert_eq!(g.scene.triangles.len(), float.scene.triangles.len());
            let tolerance = if normalized && component == 5122 {
                1e-4
            } else {
                0.0
            };
            for (q, f) in g.scene.triangles.iter().zip(&float.scene.triangles) {
                for (a, b) in q.vertices.iter().zip(f.vertices) {
                    assert!(a.abs_diff_eq(b, tolerance), "component {component}: {a} vs {b}");
                }
                assert_eq!(q.uvs, f.uvs);
            }
        }
    }

    /// Signed normalised texture coordinates: -128 and -127 both read -1
    /// (the `max(c / 127, -1)` rule), 127 reads 1; unsigned shorts not
    /// normalised read as integers.
    #[test]
    fn quantized_texture_coordinates_follow_the_normalisation_rules() {
        let g = load_patched(|doc, bin| {
            declare_quantization(doc);
            let a = quad_accessor(doc, "TEXCOORD_0");
            // 4 vertices, 2 bytes each, stride 4.
            let bytes = [0x80u8, 127, 0, 0, 0x81, 0, 0, 0, 127, 0x80, 0, 0, 0, 64, 0, 0];
            replace_accessor(doc, bin, a, &bytes, 4, 5120, true);
        })
        .expect("i8 UVs load");
        let t = g.scene.triangles[0];
        assert_eq!(t.uvs[0], Vec2::new(-1.0, 1.0));
        assert_eq!(t.uvs[1], Vec2::new(-1.0, 0.0));
        assert_eq!(t.uvs[2], Vec2::new(1.0, -1.0));
        let g = load_patched(|doc, bin| {
            declare_quantization(doc);
            let a = quad_accessor(doc, "TEXCOORD_0");
            let bytes: Vec<u8> = [0u16, 3, 1000, 3, 1000, 0, 0, 0]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect();
            replace_accessor(doc, bin, a, &bytes, 0, 5123, false);
        })
        .expect("u16 UVs load");
        assert_eq!(g.scene.triangles[0].uvs[1], Vec2::new(1000.0, 3.0));
        assert_eq!(g.scene.triangles[0].vertices[1], Vec3::new(1.0, -1.0, 0.0));
    }

    /// Integer positions without the extension, unsigned int positions and
    /// VEC2 positions are refused with the accepted types named.
    #[test]
    fn unsupported_quantized_accessors_are_errors() {
        let bytes = [0u8; 48];
        let (element, reason) = content_error(load_patched(|doc, bin| {
            let a = quad_accessor(doc, "POSITION");
            replace_accessor(doc, bin, a, &bytes[..24], 0, 5122, false);
        }));
        assert_eq!(element, "mesh 'checker_quad' primitive 0");
        assert!(
            reason.contains("POSITION") && reason.contains("need KHR_mesh_quantization"),
            "{reason}"
        );
        let (_, reason) = content_error(load_patched(|doc, bin| {
            declare_quantization(doc);
            let a = quad_accessor(doc, "POSITION");
            replace_accessor(doc, bin, a, &bytes, 0, 5125, false);
        }));
        assert!(
            reason.contains("Vec3 of U32, expected Vec3 of F32, or I8"),
            "{reason}"
        );
        let (_, reason) = content_error(load_patched(|doc, bin| {
            declare_quantization(doc);
            let a = quad_accessor(doc, "POSITION");
            replace_accessor(doc, bin, a, &bytes[..16], 0, 5123, true);
            doc["accessors"][a]["type"] = json!("VEC2");
        }));
        assert!(reason.contains("is Vec2 of normalized U16"), "{reason}");
        let (_, reason) = content_error(load_patched(|doc, bin| {
            let a = quad_accessor(doc, "TEXCOORD_0");
            replace_accessor(doc, bin, a, &bytes[..8], 0, 5120, true);
        }));
        assert!(
            reason.contains("TEXCOORD_0") && reason.contains("need KHR_mesh"),
            "{reason}"
        );
    }
}
