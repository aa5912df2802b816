//! The trace kernel's three variants: **full** (every material, light and
//! surface feature the tracer knows), **untextured** (everything but
//! texture lookups: glossy, lit and smooth-shaded scenes without textures,
//! normal maps or cut-outs) and **basic** (what the Cornell box and other
//! plain triangle scenes use), and which scenes each renders exactly as
//! the full one.
//!
//! # Why two
//!
//! A GPU skips the code of an `if` that no invocation of a wave takes;
//! llvmpipe (lavapipe, the Vulkan driver every test here runs on) does not:
//! its 8-wide SIMD programs run every side of every branch under a lane
//! mask, so each texture lookup, cut-out test, normal map, GGX lobe and
//! light type in the path loop costs every path vertex of every scene,
//! used or not (`BENCHMARKS.md` measured the 720p Cornell frame growing
//! 3.8x as those features arrived). The smaller variants are the same
//! source with features removed at compile time (a `const FEATURES: u32`
//! parameter of [`crate::trace::trace_pixel_variant`], a set of
//! [`TEXTURES`] and [`SHADING`]), so the driver never sees them.
//!
//! # What each variant assumes
//!
//! A scene fits the variant of a feature set when every material passes
//! [`material_fits`], every triangle [`triangle_fits`], every emitter
//! [`emitter_fits`] and the environment [`environment_fits`]: without
//! [`TEXTURES`] no material has a texture, a normal map or an alpha
//! cut-out; without [`SHADING`] every material is Lambertian, no triangle
//! has vertex normals, every emitter is an emissive triangle and there is
//! no environment map (a constant sky is fine). On such a scene the variant
//! returns the full variant's radiance, bit for bit (the integrator skips
//! exactly the steps that would have returned their input unchanged); on
//! any other scene it is wrong. The host picks the smallest that fits
//! (`SceneGpu::trace_variant` in `gpu-tracer`).

use crate::abi::{
    EmitterGpu, MaterialGpu, TriangleAttrGpu, TriangleGpu, CUT_OUT, EMITTER_TRIANGLE, MODEL_LAMBERT,
    TEXTURE_NONE,
};
use crate::surface::has_textures;
use crate::vertex_normal::has_vertex_normals;
use sampler_core::EnvironmentParams;

/// Feature: texture lookups (base colour, emission, metallic-roughness
/// and normal-map textures, ray-cone footprints) and alpha cut-outs.
pub const TEXTURES: u32 = 1;

/// Feature: the metallic-roughness model, vertex normals, punctual and
/// directional lights, and the environment map.
pub const SHADING: u32 = 2;

/// The full variant's feature set: everything.
pub const FULL: u32 = TEXTURES | SHADING;

/// The untextured variant's feature set.
pub const UNTEXTURED: u32 = SHADING;

/// The basic variant's feature set: none.
pub const BASIC: u32 = 0;

/// Whether `material` is one the variant of `features` shades exactly:
/// without [`TEXTURES`], no texture (base colour, emission,
/// metallic-roughness or normal map) and no alpha cut-out; without
/// [`SHADING`], Lambertian.
#[inline]
pub fn material_fits(features: u32, material: &MaterialGpu) -> bool {
    let untextured = !has_textures(material) && material.normal.x == TEXTURE_NONE && material.alpha.x <= 0.0;
    (features & TEXTURES != 0 || untextured) && (features & SHADING != 0 || material.model.x == MODEL_LAMBERT)
}

/// Whether a triangle (its geometry and attributes) is one the variant of
/// `features` intersects and shades exactly: without [`TEXTURES`], not
/// flagged [`CUT_OUT`]; without [`SHADING`], no vertex normals.
#[inline]
pub fn triangle_fits(features: u32, triangle: &TriangleGpu, attr: &TriangleAttrGpu) -> bool {
    (features & TEXTURES != 0 || triangle.v2.w != CUT_OUT)
        && (features & SHADING != 0 || !has_vertex_normals(attr))
}

/// Whether an emitter is one the variant of `features` samples: without
/// [`SHADING`], an emissive triangle.
#[inline]
pub fn emitter_fits(features: u32, emitter: &EmitterGpu) -> bool {
    features & SHADING != 0 || emitter.kind == EMITTER_TRIANGLE
}

/// Whether the environment fits the variant of `features`: without
/// [`SHADING`], no map ([`crate::abi::TraceParams::environment_map`]`.width
/// == 0`; the constant environment is read as usual).
#[inline]
pub fn environment_fits(features: u32, map: &EnvironmentParams) -> bool {
    features & SHADING != 0 || map.width == 0
}
