//! The trace kernel's two variants: **full** (every material, light and
//! surface feature the tracer knows) and **basic** (what the Cornell box
//! and other plain triangle scenes use), and which scenes the basic one
//! renders exactly as the full one.
//!
//! # Why two
//!
//! A GPU skips the code of an `if` that no invocation of a wave takes;
//! llvmpipe (lavapipe, the Vulkan driver every test here runs on) does not:
//! its 8-wide SIMD programs run every side of every branch under a lane
//! mask, so each texture lookup, cut-out test, normal map, GGX lobe and
//! light type in the path loop costs every path vertex of every scene,
//! used or not (`BENCHMARKS.md` measured the 720p Cornell frame growing
//! 3.8x as those features arrived). The basic variant is the same source
//! with those features removed at compile time (a `const FULL: bool`
//! parameter of [`crate::trace::trace_pixel_variant`]), so the driver never
//! sees them.
//!
//! # What the basic variant assumes
//!
//! A scene fits it when every material passes [`material_fits_basic`],
//! every triangle's attributes pass [`attr_fits_basic`], every emitter
//! passes [`emitter_fits_basic`] and the environment passes
//! [`environment_fits_basic`]: Lambertian untextured materials without cut-outs,
//! flat-shaded triangles, emissive triangles as the only lights, and no
//! environment map (a constant sky is fine). On such a scene both variants
//! return the same radiance, bit for bit (the integrator skips exactly the
//! steps that would have returned their input unchanged); on any other
//! scene only the full variant is correct. The host picks
//! (`SceneGpu::fits_basic_trace` in `gpu-tracer`).

use crate::abi::{
    EmitterGpu, MaterialGpu, TriangleAttrGpu, TriangleGpu, CUT_OUT, EMITTER_TRIANGLE, MODEL_LAMBERT,
    TEXTURE_NONE,
};
use crate::surface::has_textures;
use crate::vertex_normal::has_vertex_normals;
use sampler_core::EnvironmentParams;

/// The full variant's `FULL` argument.
pub const FULL: bool = true;

/// The basic variant's `FULL` argument.
pub const BASIC: bool = false;

/// Whether `material` is one the basic variant shades exactly: Lambertian,
/// no texture (base colour, emission, metallic-roughness or normal map),
/// no alpha cut-out.
#[inline]
pub fn material_fits_basic(material: &MaterialGpu) -> bool {
    material.model.x == MODEL_LAMBERT
        && !has_textures(material)
        && material.normal.x == TEXTURE_NONE
        && material.alpha.x <= 0.0
}

/// Whether a triangle (its geometry and attributes) is one the basic
/// variant intersects and shades exactly: not flagged [`CUT_OUT`], no
/// vertex normals.
#[inline]
pub fn attr_fits_basic(triangle: &TriangleGpu, attr: &TriangleAttrGpu) -> bool {
    triangle.v2.w != CUT_OUT && !has_vertex_normals(attr)
}

/// Whether an emitter is one the basic variant samples: an emissive
/// triangle.
#[inline]
pub fn emitter_fits_basic(emitter: &EmitterGpu) -> bool {
    emitter.kind == EMITTER_TRIANGLE
}

/// Whether the environment fits the basic variant: no map
/// ([`crate::abi::TraceParams::environment_map`]`.width == 0`; the constant environment
/// is read as usual).
#[inline]
pub fn environment_fits_basic(map: &EnvironmentParams) -> bool {
    map.width == 0
}
