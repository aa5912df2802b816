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
    /// with sRGB-encoded colour and linear alpha.
    pub texels: Vec<[u8; 4]>,
}

/// An affine map of texture coordinates, `uv' = rows * (u, v, 1)`: glTF
/// `KHR_texture_transform` (the GPU form is `kernels::abi::UvTransformGpu`,
/// applied by `kernels::surface::texture_uv`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// The first two rows of the 3x3 matrix: `u' = rows[0] . (u, v, 1)`,
    /// `v' = rows[1] . (u, v, 1)`. Finite (the GPU form refuses others).
    pub rows: [[f32; 3]; 2],
}

impl UvTransform {
    /// The identity map.
    pub const IDENTITY: UvTransform = UvTransform {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    };

    /// `KHR_texture_transform`'s `translation * rotation * scale`: scale by
    /// `scale`, rotate by `rotation` radians (counter-clockwise as the
    /// image is seen, `v` pointing down: `(1, 0)` turns towards `(0, -1)`),
    /// then add `offset` (in texture widths and heights). Computed in f64,
    /// rounded once per entry. The extension's example (offset `(0, 1)`,
    /// rotation `pi / 2`, scale `0.5`) maps the unit square onto the lower
    /// left quadrant of the image.
    pub fn from_offset_rotation_scale(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Self {
        let (sin, cos) = f64::from(rotation).sin_cos();
        let (sx, sy) = (f64::from(scale[0]), f64::from(scale[1]));
        UvTransform {
            rows: [
                [(sx * cos) as f32, (sy * sin) as f32, offset[0]],
                [(-sx * sin) as f32, (sy * cos) as f32, offset[1]],
            ],
        }
    }

    /// `uv` mapped (in f32, the kernels' arithmetic).
    pub fn apply(&self, uv: glam::Vec2) -> glam::Vec2 {
        let [a, b] = self.rows;
        glam::Vec2::new(a[0] * uv.x + a[1] * uv.y + a[2], b[0] * uv.x + b[1] * uv.y + b[2])
    }
}

/// A texture: an image of [`Scene::images`](super::Scene::images) and how to
/// sample it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Scene::images`](super::Scene::images).
    pub image: u32,
    /// Wrap mode along `u`.
    pub wrap_u: Wrap,
    /// Wrap mode along `v`.
    pub wrap_v: Wrap,
    /// Filter.
    pub filter: Filter,
    /// Transform of the surface's texture coordinates before the lookup
    /// (glTF `KHR_texture_transform`); `None` reads them as they are.
    pub transform: Option<UvTransform>,
}

/// A normal map (glTF `normalTexture`): the texture's `rgb`, read as linear
/// data (`c / 255`, not sRGB), is a unit normal in the triangle's tangent
/// frame, `(2r - 1, 2g - 1, 2b - 1)` = (tangent, bitangent, normal)
/// components (`kernels::normal_map`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalTexture {
    /// The texture (image, sampler, coordinate transform).
    pub texture: TextureRef,
    /// glTF `scale`: multiplies the tangent and bitangent components of each
    /// texel's normal (1: as stored, 0: flat; negative inverts the relief).
    /// Finite; anything else is refused when the GPU form is built.
    pub scale: f32,
}

/// How a [`Material`] reflects light.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Bsdf {
    /// Lambertian: BRDF `albedo / pi`, two-sided. What OBJ materials without
    /// `Ks`, the built-in Cornell box and glTF materials with
    /// `KHR_materials_specular` `specularFactor` 0 and no metal use.
    #[default]
    Lambert,
    /// The glTF 2.0 metallic-roughness BRDF
    /// (`kernels::bsdf::MetallicRoughness`) with base colour
    /// [`Material::albedo`] (times its texture), two-sided. It is the
    /// specification's model, kept as written: its Fresnel mix of a
    /// dielectric's diffuse and specular lobes is not energy conserving and
    /// reflects more than it receives at grazing angles and low roughness
    /// (a white dielectric of roughness 0.1 seen at 78 degrees from the
    /// normal reflects 1.3 times the incident light; the specification,
    /// appendix B, "Coupling Diffuse and Specular Reflection", says so).
    MetallicRoughness {
        /// glTF `metallicFactor`, in `[0, 1]` (0 dielectric, 1 metal);
        /// anything else is refused when the GPU form is built.
        metallic: f32,
        /// glTF `roughnessFactor` (perceptual; GGX `alpha = roughness^2`),
        /// in `[0, 1]`; anything else is refused.
        roughness: f32,
        /// glTF `metallicRoughnessTexture`: blue multiplies `metallic`,
        /// green `roughness` (linear data, not sRGB).
        texture: Option<TextureRef>,
    },
}

/// Where a material's surface exists (glTF `alphaMode`): everywhere, or
/// only where its base colour alpha reaches a cutoff.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Alpha {
    /// Opaque everywhere: glTF `OPAQUE`, and `BLEND`, which is rendered as
    /// opaque (the glTF loader says so in a notice).
    #[default]
    Opaque,
    /// A cut-out (glTF `MASK`): where the base colour alpha, `factor` times
    /// the base colour texture's alpha (linear, `a / 255`; 1 without a
    /// texture), is below `cutoff`, there is no surface: camera,
    /// continuation and shadow rays pass through. Elsewhere the surface is
    /// opaque.
    Mask {
        /// glTF `alphaCutoff` (default 0.5), finite and `>= 0` (0: nothing
        /// is cut; above 1: everything is); anything else is refused when
        /// the GPU form is built.
        cutoff: f32,
        /// The base colour factor's alpha, in `[0, 1]`; anything else is
        /// refused.
        factor: f32,
    },
}

/// A Lambertian or metallic-roughness material with optional emission and
/// textures.
///
/// Albedo (base colour) at a surface point = `albedo * decode(base_color_texture(uv))`,
/// emitted radiance = `emission * decode(emission_texture(uv))` (sRGB
/// decoding per texel; the texture factor is 1 without a texture); an
/// optional [`NormalTexture`] tilts the shading normal.
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
    /// The reflectance model ([`Bsdf::Lambert`] by default).
    pub bsdf: Bsdf,
    /// Opaque or cut out by the base colour alpha ([`Alpha::Opaque`] by
    /// default).
    pub alpha: Alpha,
    /// Normal map tilting the shading normal; `None` (the default) shades
    /// with the geometric normal.
    pub normal_texture: Option<NormalTexture>,
}

impl Material {
    /// An untextured Lambertian material.
    pub fn new(name: impl Into<String>, albedo: Vec3, emission: Vec3) -> Self {
        Material {
            name: name.into(),
            albedo,
            emission,
            base_color_texture: None,
            emission_texture: None,
            bsdf: Bsdf::Lambert,
            alpha: Alpha::Opaque,
            normal_texture: None,
        }
    }

    /// An untextured, non-emissive metallic-roughness material: base colour
    /// `base_color` (linear RGB in `[0, 1]`), `metallic` and `roughness` in
    /// `[0, 1]`.
    pub fn metallic_roughness(
        name: impl Into<String>,
        base_color: Vec3,
        metallic: f32,
        roughness: f32,
    ) -> Self {
        Material {
            bsdf: Bsdf::MetallicRoughness {
                metallic,
                roughness,
                texture: None,
            },
            ..Material::new(name, base_color, Vec3::ZERO)
        }
    }
}
