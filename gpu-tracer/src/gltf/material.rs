//! Materials and textures: glTF materials as metallic-roughness
//! [`Material`]s, their textures as [`TextureRef`]s with the sampler's
//! settings, and the images they use decoded and converted to 8-bit RGBA
//! (sRGB for colour textures, linear data for the metallic-roughness
//! texture: the bytes are the file's either way).
//!
//! # Reflectance
//!
//! Every material is the specification's metallic-roughness BRDF
//! ([`Bsdf::MetallicRoughness`]) with its factors and texture, defaults
//! included (metallic 1, roughness 1 when the file omits them), except one
//! case: `metallicFactor` 0 with the `KHR_materials_specular` extension's
//! `specularFactor` 0 is exactly a Lambertian surface (the extension scales
//! the dielectric's Fresnel term by `specularFactor`, so the specular lobe
//! vanishes and the diffuse one keeps weight 1) and becomes
//! [`Bsdf::Lambert`]. The project's fixture generator writes that for its
//! diffuse scenes. Other `KHR_materials_specular` values are ignored (with a
//! notice).
//!
//! # Normal maps
//!
//! `normalTexture` becomes a [`NormalTexture`] with its `scale` (finite;
//! default 1) and sampler, read as linear data. The `gltf` crate does not
//! parse `KHR_texture_transform` on it (it does on the other textures), so
//! [`normal_transform`] reads the extension's JSON itself, with the same
//! defaults and the same `texCoord` override. Occlusion textures are still
//! ignored, with a notice.

use super::loader::{check_uri, label, short_uri, Loader};
use crate::error::{Error, Result};
use crate::scene::{Alpha, Bsdf, Filter, Image, Material, NormalTexture, TextureRef, UvTransform, Wrap};
use glam::{Vec3, Vec4};

/// Base colour of primitives without a material (glTF's default material:
/// base colour factor 1, metallic 1, roughness 1).
pub const DEFAULT_ALBEDO: Vec3 = Vec3::ONE;

impl<'p> Loader<'p> {
    /// Scene materials in file order (texture `image` fields still hold
    /// glTF image indices) and the texture coordinate set of each textured
    /// material.
    pub(super) fn materials(&mut self) -> Result<(Vec<Material>, Vec<Option<u32>>)> {
        let mut materials = Vec::new();
        let mut sets = Vec::new();
        let (mut specular, mut occlusion, mut blend) = (false, false, false);
        for m in self.document.materials() {
            let index = m.index().unwrap_or(materials.len());
            let name = m
                .name()
                .map_or_else(|| format!("material {index}"), str::to_string);
            let element = || label("material", index, m.name());
            let pbr = m.pbr_metallic_roughness();
            occlusion |= m.occlusion_texture().is_some();
            let base_factor = Vec4::from(pbr.base_color_factor());
            let albedo = base_factor.truncate();
            let alpha = match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => Alpha::Opaque,
                gltf::material::AlphaMode::Blend => {
                    blend = true;
                    Alpha::Opaque
                }
                gltf::material::AlphaMode::Mask => {
                    let cutoff = m.alpha_cutoff().unwrap_or(0.5);
                    if !(cutoff.is_finite() && cutoff >= 0.0) {
                        return Err(self.content(
                            element(),
                            format!("alphaCutoff {cutoff} is negative or not finite"),
                        ));
                    }
                    let factor = base_factor.w;
                    if !(0.0..=1.0).contains(&factor) {
                        return Err(self.content(
                            element(),
                            format!("base colour factor alpha {factor} is not in [0, 1]"),
                        ));
                    }
                    Alpha::Mask { cutoff, factor }
                }
            };
            let strength = m.emissive_strength().unwrap_or(1.0);
            let emission = Vec3::from(m.emissive_factor()) * strength;
            for (what, c) in [("base colour factor", albedo), ("emission", emission)] {
                if !c.is_finite() || c.min_element() < 0.0 {
                    return Err(self.content(element(), format!("{what} {c} is NaN, infinite or negative")));
                }
            }
            let base = pbr.base_color_texture();
            let emissive = m.emissive_texture();
            let metal_rough = pbr.metallic_roughness_texture();
            let normal_texture = match m.normal_texture() {
                None => None,
                Some(n) => {
                    let scale = n.scale();
                    if !scale.is_finite() {
                        return Err(
                            self.content(element(), format!("normalTexture scale {scale} is not finite"))
                        );
                    }
                    let (transform, tex_coord) =
                        normal_transform(&n).map_err(|reason| self.content(element(), reason))?;
                    let texture = TextureRef {
                        transform,
                        ..sampled(&n.texture())
                    };
                    Some((
                        NormalTexture { texture, scale },
                        tex_coord.unwrap_or(n.tex_coord()),
                    ))
                }
            };
            let mut set: Option<(&str, u32)> = None;
            for (what, t) in [
                ("base colour", base.as_ref().map(tex_coord)),
                ("emissive", emissive.as_ref().map(tex_coord)),
                ("metallic-roughness", metal_rough.as_ref().map(tex_coord)),
                ("normal", normal_texture.map(|(_, set)| set)),
            ] {
                match (set, t) {
                    (Some((first, a)), Some(b)) if a != b => {
                        return Err(self.content(
                            element(),
                            format!(
                                "{first} texture reads TEXCOORD_{a} but {what} texture reads TEXCOORD_{b}: one set per material is supported"
                            ),
                        ))
                    }
                    (None, Some(b)) => set = Some((what, b)),
                    _ => {}
                }
            }
            let (metallic, roughness) = (pbr.metallic_factor(), pbr.roughness_factor());
            let specular_factor = m.specular().map(|s| s.specular_factor());
            let bsdf = if metallic == 0.0 && specular_factor == Some(0.0) {
                Bsdf::Lambert
            } else {
                specular |= specular_factor.is_some();
                Bsdf::MetallicRoughness {
                    metallic,
                    roughness,
                    texture: metal_rough.as_ref().map(texture_ref),
                }
            };
            materials.push(Material {
                name,
                albedo,
                emission,
                base_color_texture: base.as_ref().map(texture_ref),
                emission_texture: emissive.as_ref().map(texture_ref),
                bsdf,
                alpha,
                normal_texture: normal_texture.map(|(n, _)| n),
            });
            sets.push(set.map(|(_, s)| s));
        }
        if specular {
            self.notices.push(
                "KHR_materials_specular is honoured only as specularFactor 0 on a non-metal (Lambertian); other values are ignored"
                    .into(),
            );
        }
        if occlusion {
            self.notices.push("occlusion textures are ignored".into());
        }
        if blend {
            self.notices
                .push("alphaMode BLEND is not supported: those materials are rendered opaque".into());
        }
        Ok((materials, sets))
    }

    /// Decodes the images the materials use; returns them and the map from
    /// glTF image index to scene image index.
    pub(super) fn images(&self, materials: &[Material]) -> Result<(Vec<Image>, Vec<Option<u32>>)> {
        let mut image_of = vec![None; self.document.images().len()];
        let mut images = Vec::new();
        let used = materials
            .iter()
            .flat_map(|m| {
                let metal_rough = match m.bsdf {
                    Bsdf::MetallicRoughness { texture, .. } => texture,
                    Bsdf::Lambert => None,
                };
                [
                    m.base_color_texture,
                    m.emission_texture,
                    metal_rough,
                    m.normal_texture.map(|n| n.texture),
                ]
            })
            .flatten()
            .map(|t| t.image as usize);
        for i in used {
            if image_of.get(i).is_none_or(|x| x.is_some()) {
                continue;
            }
            let Some(image) = self.document.images().nth(i) else {
                continue;
            };
            let name = match (image.name(), image.source()) {
                (Some(n), _) => n.to_string(),
                (None, gltf::image::Source::Uri { uri, .. }) if !uri.starts_with("data:") => short_uri(uri),
                _ => format!("image {i}"),
            };
            let element = format!("image {i} ('{name}')");
            if let gltf::image::Source::Uri { uri, .. } = image.source() {
                check_uri(self.path, &element, uri)?;
            }
            let data = gltf::image::Data::from_source(image.source(), Some(self.base), &self.buffers)
                .map_err(|source| Error::GltfLoad {
                    path: self.path.to_path_buf(),
                    element: element.clone(),
                    source,
                })?;
            let image = convert_image(name, &data).map_err(|reason| self.content(&element, reason))?;
            image_of[i] = Some(images.len() as u32);
            images.push(image);
        }
        Ok((images, image_of))
    }
}

/// The texture coordinate set a texture reads: `KHR_texture_transform`'s
/// `texCoord` when it has one, the texture info's otherwise.
fn tex_coord(info: &gltf::texture::Info) -> u32 {
    info.texture_transform()
        .and_then(|t| t.tex_coord())
        .unwrap_or(info.tex_coord())
}

/// A [`TextureRef`] with the texture's sampler settings and its
/// `KHR_texture_transform` (offset, rotation, scale); `image` holds the glTF
/// image index until remapped.
fn texture_ref(info: &gltf::texture::Info) -> TextureRef {
    TextureRef {
        transform: info
            .texture_transform()
            .map(|t| UvTransform::from_offset_rotation_scale(t.offset(), t.rotation(), t.scale())),
        ..sampled(&info.texture())
    }
}

/// `KHR_texture_transform` on a normal texture, read from its JSON (module
/// docs): the transform (`None` without the extension) and its `texCoord`
/// override. Missing properties take the extension's defaults (offset `[0,
/// 0]`, rotation 0, scale `[1, 1]`).
///
/// # Errors
/// A message when a property has the wrong type or a non-finite value.
pub(super) fn normal_transform(
    n: &gltf::material::NormalTexture,
) -> std::result::Result<(Option<UvTransform>, Option<u32>), String> {
    use gltf::json::Value;
    let Some(ext) = n.extension_value("KHR_texture_transform") else {
        return Ok((None, None));
    };
    let what = |p: &str| format!("normalTexture KHR_texture_transform {p}");
    let number = |v: &Value, p: &str| match v.as_f64().map(|x| x as f32) {
        Some(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{} is {v}, expected a finite number", what(p))),
    };
    let pair = |p: &str, default: [f32; 2]| match ext.get(p) {
        None => Ok(default),
        Some(Value::Array(a)) if a.len() == 2 => Ok([number(&a[0], p)?, number(&a[1], p)?]),
        Some(v) => Err(format!("{} is {v}, expected two numbers", what(p))),
    };
    let offset = pair("offset", [0.0, 0.0])?;
    let scale = pair("scale", [1.0, 1.0])?;
    let rotation = ext.get("rotation").map_or(Ok(0.0), |v| number(v, "rotation"))?;
    let tex_coord = match ext.get("texCoord") {
        None => None,
        Some(v) => match v.as_u64().and_then(|s| u32::try_from(s).ok()) {
            Some(s) => Some(s),
            None => return Err(format!("{} is {v}, expected a set index", what("texCoord"))),
        },
    };
    Ok((
        Some(UvTransform::from_offset_rotation_scale(offset, rotation, scale)),
        tex_coord,
    ))
}

/// A [`TextureRef`] with `texture`'s image and sampler settings and no
/// coordinate transform; `image` holds the glTF image index until remapped.
fn sampled(texture: &gltf::Texture) -> TextureRef {
    use gltf::texture::{MagFilter, WrappingMode};
    let sampler = texture.sampler();
    let wrap = |m| match m {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    TextureRef {
        image: texture.source().index() as u32,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
        filter: match sampler.mag_filter() {
            Some(MagFilter::Nearest) => Filter::Nearest,
            Some(MagFilter::Linear) | None => Filter::Bilinear,
        },
        transform: None,
    }
}

/// Converts a decoded image to 8-bit sRGB RGBA (see the module docs).
fn convert_image(name: String, data: &gltf::image::Data) -> std::result::Result<Image, String> {
    use gltf::image::Format;
    #[derive(Clone, Copy)]
    enum Kind {
        U8,
        U16,
        F32,
    }
    let (channels, kind) = match data.format {
        Format::R8 => (1, Kind::U8),
        Format::R8G8 => (2, Kind::U8),
        Format::R8G8B8 => (3, Kind::U8),
        Format::R8G8B8A8 => (4, Kind::U8),
        Format::R16 => (1, Kind::U16),
        Format::R16G16 => (2, Kind::U16),
        Format::R16G16B16 => (3, Kind::U16),
        Format::R16G16B16A16 => (4, Kind::U16),
        Format::R32G32B32FLOAT => (3, Kind::F32),
        Format::R32G32B32A32FLOAT => (4, Kind::F32),
    };
    let bytes_per_channel = match kind {
        Kind::U8 => 1,
        Kind::U16 => 2,
        Kind::F32 => 4,
    };
    let texel_bytes = channels * bytes_per_channel;
    let expected = (data.width as usize)
        .checked_mul(data.height as usize)
        .and_then(|n| n.checked_mul(texel_bytes));
    if data.width == 0 || data.height == 0 || expected != Some(data.pixels.len()) {
        return Err(format!(
            "decoded to {}x{} {:?} with {} bytes",
            data.width,
            data.height,
            data.format,
            data.pixels.len()
        ));
    }
    let channel = |c: &[u8]| -> u8 {
        match kind {
            Kind::U8 => c[0],
            Kind::U16 => ((u32::from(u16::from_ne_bytes([c[0], c[1]])) * 255 + 32767) / 65535) as u8,
            Kind::F32 => {
                let v = f32::from_ne_bytes([c[0], c[1], c[2], c[3]]);
                // NaN maps to 0.
                (v.clamp(0.0, 1.0) * 255.0).round().max(0.0) as u8
            }
        }
    };
    let texels = data
        .pixels
        .chunks_exact(texel_bytes)
        .map(|t| {
            let c: Vec<u8> = t.chunks_exact(bytes_per_channel).map(channel).collect();
            match c.as_slice() {
                [l] => [*l, *l, *l, 255],
                [l, a] => [*l, *l, *l, *a],
                [r, g, b] => [*r, *g, *b, 255],
                [r, g, b, a, ..] => [*r, *g, *b, *a],
                [] => [0, 0, 0, 255],
            }
        })
        .collect();
    Ok(Image {
        name,
        width: data.width,
        height: data.height,
        texels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn images_of_every_decoded_format_become_srgb_rgba8() {
        use gltf::image::{Data, Format};
        let img = |format, pixels: Vec<u8>| Data {
            pixels,
            format,
            width: 1,
            height: 1,
        };
        let cases = [
            (img(Format::R8, vec![7]), [7, 7, 7, 255]),
            (img(Format::R8G8, vec![7, 9]), [7, 7, 7, 9]),
            (img(Format::R8G8B8, vec![1, 2, 3]), [1, 2, 3, 255]),
            (img(Format::R8G8B8A8, vec![1, 2, 3, 4]), [1, 2, 3, 4]),
            (
                img(Format::R16, 65535u16.to_ne_bytes().to_vec()),
                [255, 255, 255, 255],
            ),
            (
                img(
                    Format::R16G16B16A16,
                    [0u16, 257, 32768, 65535]
                        .iter()
                        .flat_map(|v| v.to_ne_bytes())
                        .collect(),
                ),
                [0, 1, 128, 255],
            ),
            (
                img(
                    Format::R32G32B32FLOAT,
                    [0.5f32, -1.0, 2.0].iter().flat_map(|v| v.to_ne_bytes()).collect(),
                ),
                [128, 0, 255, 255],
            ),
            (
                img(
                    Format::R32G32B32A32FLOAT,
                    [f32::NAN, 1.0, 0.0, 0.25]
                        .iter()
                        .flat_map(|v| v.to_ne_bytes())
                        .collect(),
                ),
                [0, 255, 0, 64],
            ),
        ];
        for (data, texel) in cases {
            let format = data.format;
            let image = convert_image("t".into(), &data).unwrap_or_else(|e| panic!("{format:?}: {e}"));
            assert_eq!(image.texels, vec![texel], "{format:?}");
        }
        assert!(convert_image("t".into(), &img(Format::R8G8B8, vec![1, 2])).is_err());
    }
}
