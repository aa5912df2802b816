//! Materials, textures and images: what a [`Material`] looks like and the
//! [`Image`]s its [`TextureRef`]s name.

use glam::Vec3;

/// How a texture is sampled along one axis outside `[0, 1]` (glTF's
/// sampler wrap modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// Tile (glTF `REPEAT`, the default).
    #[default]
    Repeat,
    /// Clamp to the edge texel (`CLAMP_TO_EDGE`).
    Clamp,
    /// Tile, mirrored every other repetition (`MIRRORED_REPEAT`).
    Mirror,
}

/// Texture filtering (glTF's magnification filter; mipmaps are not used).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation of the four nearest texels (after sRGB
    /// decoding), the glTF default.
    #[default]
    Bilinear,
}

/// An RGBA8 image in sRGB encoding (colour textures: glTF base colour and
/// emissive textures are sRGB).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Name for messages (file name or glTF image name/index).
    pub name: String,
    /// Width in texels, `>= 1`.
    pub width: u32,
    /// Height in texels, `>= 1`.
    pub height: u32,
    /// `width * height` texels, row-major from the top row, `[r, g, b, a]`
    /// sRGB-encoded (alpha is ignored).
    pub texels: Vec<[u8; 4]>,
}

/// A texture: an image of [`Scene::images`](super::Scene::images) and how to
/// sample it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureRef {
    /// Index into [`Scene::images`](super::Scene::images).
    pub image: u32,
    /// Wrap mode along `u`.
    pub wrap_u: Wrap,
    /// Wrap mode along `v`.
    pub wrap_v: Wrap,
    /// Filter.
    pub filter: Filter,
}

/// A Lambertian material with optional emission and textures.
///
/// Albedo at a surface point = `albedo * decode(base_color_texture(uv))`,
/// emitted radiance = `emission * decode(emission_texture(uv))` (sRGB
/// decoding per texel; the texture factor is 1 without a texture).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name (from the MTL or glTF file, or descriptive for built-in scenes).
    pub name: String,
    /// Diffuse albedo, linear RGB; each channel is clamped to `[0, 1]` when
    /// the GPU form is built.
    pub albedo: Vec3,
    /// Emitted radiance from the front side, linear RGB, `>= 0` (for glTF:
    /// emissive factor x `KHR_materials_emissive_strength`).
    pub emission: Vec3,
    /// Texture multiplying the albedo.
    pub base_color_texture: Option<TextureRef>,
    /// Texture multiplying the emission.
    pub emission_texture: Option<TextureRef>,
}

impl Material {
    /// An untextured material.
    pub fn new(name: impl Into<String>, albedo: Vec3, emission: Vec3) -> Self {
        Material {
            name: name.into(),
            albedo,
            emission,
            base_color_texture: None,
            emission_texture: None,
        }
    }
}
