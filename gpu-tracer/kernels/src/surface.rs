//! What a path sees at a hit point: texture coordinates, albedo and
//! emission after the material's textures, and the metallic-roughness
//! parameters after theirs.

use crate::abi::{MaterialGpu, TriangleAttrGpu, UvTransformGpu, TEXEL_LINEAR, TEXTURE_NONE, UV_TRANSFORM};
use crate::texture::sample_alpha;
use crate::texture_filter::sample_image_filtered;
use glam::{Vec2, Vec3};

/// Texture coordinates at barycentrics `(u, v)` of a triangle (the point
/// `v0 + (v1 - v0) u + (v2 - v0) v`, as `crate::intersect` reports hits).
#[inline]
pub fn triangle_uv(attr: &TriangleAttrGpu, u: f32, v: f32) -> Vec2 {
    let uv0 = Vec2::new(attr.uv01.x, attr.uv01.y);
    let uv1 = Vec2::new(attr.uv01.z, attr.uv01.w);
    let uv2 = Vec2::new(attr.uv2.x, attr.uv2.y);
    uv0 + (uv1 - uv0) * u + (uv2 - uv0) * v
}

/// Albedo (linear RGB, each in `[0, 1]`) of `material` at texture
/// coordinates `uv` (the surface's, before any texture transform): the
/// material's albedo times its base colour texture (at its transformed
/// coordinates, [`texture_uv`]),
/// or the albedo alone (bit for bit) without a texture.
#[inline]
pub fn surface_albedo(material: &MaterialGpu, images: &[u32], image_count: u32, uv: Vec2) -> Vec3 {
    surface_albedo_filtered(material, images, image_count, uv, 0.0)
}

/// [`surface_albedo`] with the texture filtered over a footprint of side
/// `width` in the surface's texture coordinates
/// ([`crate::texture_filter`]; 0: a point lookup, exactly
/// [`surface_albedo`]).
#[inline]
pub fn surface_albedo_filtered(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
    width: f32,
) -> Vec3 {
    let t = material.textures;
    let w = texture_width(t.y, &material.base_color_uv, width);
    let uv = texture_uv(t.y, &material.base_color_uv, uv);
    textured(material.albedo.truncate(), images, image_count, t.x, t.y, uv, w)
}

/// Emitted radiance (linear RGB, `>= 0`) of `material` at `uv`: the
/// emission times its emission texture, or the emission alone (bit for bit)
/// without a texture.
#[inline]
pub fn surface_emission(material: &MaterialGpu, images: &[u32], image_count: u32, uv: Vec2) -> Vec3 {
    surface_emission_filtered(material, images, image_count, uv, 0.0)
}

/// [`surface_emission`] with the texture filtered over a footprint of side
/// `width` (as [`surface_albedo_filtered`]).
#[inline]
pub fn surface_emission_filtered(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
    width: f32,
) -> Vec3 {
    let t = material.textures;
    let w = texture_width(t.w, &material.emission_uv, width);
    let uv = texture_uv(t.w, &material.emission_uv, uv);
    textured(material.emission.truncate(), images, image_count, t.z, t.w, uv, w)
}

/// Base colour alpha (linear, `>= 0`) of `material` at `uv`: the base
/// colour factor's alpha ([`MaterialGpu::alpha`]`.y`) times the base
/// colour texture's alpha at its transformed coordinates, or the factor
/// alone without a texture. What an alpha cut-out compares with its cutoff.
#[inline]
pub fn surface_alpha(material: &MaterialGpu, images: &[u32], image_count: u32, uv: Vec2) -> f32 {
    let t = material.textures;
    let factor = material.alpha.y;
    if t.x == TEXTURE_NONE {
        factor
    } else {
        let uv = texture_uv(t.y, &material.base_color_uv, uv);
        factor * sample_alpha(images, image_count, t.x, t.y, uv)
    }
}

/// `(metallic, roughness)` of `material` at `uv`: [`MaterialGpu::pbr`]'s
/// factors times the metallic-roughness texture's blue (metallic) and green
/// (roughness) channels, always read as linear data ([`TEXEL_LINEAR`] is
/// implied), or the factors alone (bit for
/// bit) without a texture. Each in `[0, 1]` for valid factors.
#[inline]
pub fn surface_metallic_roughness(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
) -> Vec2 {
    surface_metallic_roughness_filtered(material, images, image_count, uv, 0.0)
}

/// [`surface_metallic_roughness`] with the texture filtered over a
/// footprint of side `width` (as [`surface_albedo_filtered`]).
#[inline]
pub fn surface_metallic_roughness_filtered(
    material: &MaterialGpu,
    images: &[u32],
    image_count: u32,
    uv: Vec2,
    width: f32,
) -> Vec2 {
    let factors = Vec2::new(material.pbr.x, material.pbr.y);
    let m = material.model;
    if m.y == TEXTURE_NONE {
        factors
    } else {
        let w = texture_width(m.z, &material.metal_rough_uv, width);
        let uv = texture_uv(m.z, &material.metal_rough_uv, uv);
        let t = sample_image_filtered(images, image_count, m.y, m.z | TEXEL_LINEAR, uv, w);
        factors * Vec2::new(t.z, t.y)
    }
}

/// Whether `material` reads any colour texture (base colour, emission,
/// metallic-roughness): only then does a footprint matter.
#[inline]
pub fn has_textures(material: &MaterialGpu) -> bool {
    material.textures.x != TEXTURE_NONE
        || material.textures.z != TEXTURE_NONE
        || material.model.y != TEXTURE_NONE
}

/// A footprint side `width` in the surface's texture coordinates, in the
/// texture's own coordinates: scaled by `sqrt(|det|)` of the transform's
/// linear part when `flags` carry [`UV_TRANSFORM`].
#[inline]
fn texture_width(flags: u32, transform: &UvTransformGpu, width: f32) -> f32 {
    if flags & UV_TRANSFORM != 0 {
        let det = transform.u.x * transform.v.y - transform.u.y * transform.v.x;
        width * libm::sqrtf(libm::fabsf(det))
    } else {
        width
    }
}

/// The coordinates a texture with sampler flags `flags` reads at the
/// surface's `uv`: `transform` applied when `flags` carry [`UV_TRANSFORM`]
/// (glTF `KHR_texture_transform`), `uv` itself (bit for bit) otherwise.
#[inline]
pub fn texture_uv(flags: u32, transform: &UvTransformGpu, uv: Vec2) -> Vec2 {
    if flags & UV_TRANSFORM != 0 {
        transform.apply(uv)
    } else {
        uv
    }
}

/// `factor` times image `image` sampled with `flags` at `uv` over a
/// footprint of side `width` (0: a point lookup), or `factor` itself when
/// `image` is [`TEXTURE_NONE`].
#[inline]
fn textured(
    factor: Vec3,
    images: &[u32],
    image_count: u32,
    image: u32,
    flags: u32,
    uv: Vec2,
    width: f32,
) -> Vec3 {
    if image == TEXTURE_NONE {
        factor
    } else {
        factor * sample_image_filtered(images, image_count, image, flags, uv, width)
    }
}
