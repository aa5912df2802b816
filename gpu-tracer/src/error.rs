//! The error type of the crate: every failure is a value carrying the path or
//! the numbers involved, with the underlying cause behind
//! [`std::error::Error::source`].

use std::fmt;
use std::path::PathBuf;

/// Result with the crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong when loading a scene, building its GPU
/// form, rendering on the CPU or writing images.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// An OBJ or MTL file could not be read or parsed (missing file,
    /// malformed statements, bad face indices).
    ObjLoad {
        /// The OBJ file.
        path: PathBuf,
        /// tobj's reason.
        source: tobj::LoadError,
    },
    /// The material library (MTL) an OBJ file names could not be read or
    /// parsed.
    MtlLoad {
        /// The OBJ file naming the library.
        path: PathBuf,
        /// tobj's reason.
        source: tobj::LoadError,
    },
    /// A glTF file, or a buffer or image it refers to, could not be read,
    /// parsed or validated by the `gltf` crate (missing or truncated file,
    /// malformed JSON or GLB container, missing `.bin`, undecodable image,
    /// index out of range, unsupported required extension).
    GltfLoad {
        /// The glTF file (`.gltf` or `.glb`).
        path: PathBuf,
        /// What was being read: `"file"`, `"buffer 0 ('scene.bin')"`,
        /// `"image 2 ('wood.png')"`, ...
        element: String,
        /// gltf's reason.
        source: gltf::Error,
    },
    /// A glTF file parsed but its content cannot be used: bad accessor data
    /// (wrong type, out of range, NaN), an unsupported primitive mode or
    /// camera, invalid animation data, no triangle in the scene, ...
    GltfContent {
        /// The glTF file.
        path: PathBuf,
        /// The element at fault, e.g. `"mesh 'floor' primitive 0"`,
        /// `"animation 'walk' channel 3"`, `"material 'lamp'"`.
        element: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The OBJ file parsed but contains no triangle.
    NoTriangles {
        /// The OBJ file.
        path: PathBuf,
    },
    /// A vertex coordinate is NaN or infinite.
    NonFiniteVertex {
        /// The OBJ file (or `<scene>` for scenes built in code).
        path: PathBuf,
        /// Name of the model (OBJ object or group) holding the vertex.
        model: String,
        /// Index of the vertex within the model, 0-based.
        vertex: usize,
    },
    /// A material colour is NaN, infinite or negative (albedo or emission).
    InvalidMaterial {
        /// Name of the material.
        name: String,
    },
    /// A material parameter is out of its range: metallic or roughness NaN
    /// or outside `[0, 1]` (glTF's schema bounds both factors to `[0, 1]`;
    /// such values are refused, not clamped, so a broken file or scene is
    /// reported rather than silently rendered as something else), or an MTL
    /// `Ns` NaN or infinite.
    InvalidMaterialParameter {
        /// Name of the material.
        name: String,
        /// `"metallic"`, `"roughness"`, `"shininess (Ns)"`, `"alpha cutoff"`
        /// or `"alpha factor"`.
        parameter: &'static str,
        /// The value.
        value: f32,
        /// What it must be, for the message.
        expected: &'static str,
    },
    /// A light's parameter is unusable: a negative, NaN or infinite
    /// intensity or colour channel, a non-finite position, a zero or
    /// non-finite direction, a range that is not positive, spot cone angles
    /// outside `0 <= inner < outer <= pi/2`, or an angular radius outside
    /// `[0, pi/2)`. Refused, not clamped.
    InvalidLight {
        /// Name of the light.
        name: String,
        /// The parameter at fault (`"intensity"`, `"outer cone angle"`, ...).
        parameter: &'static str,
        /// What is wrong, for the message.
        reason: String,
    },
    /// An environment map is unusable: a side of 0 or over
    /// `sampler_core::limits::MAX_DISTRIBUTION_SIDE`, the wrong number of
    /// texels, a NaN, infinite or negative texel, a non-finite rotation, or
    /// a file that cannot be read or decoded as one.
    InvalidEnvironmentMap {
        /// The map's name (its file's path).
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A material names a texture image that does not exist.
    InvalidTexture {
        /// Name of the material.
        material: String,
        /// What is wrong.
        reason: String,
    },
    /// An image's size does not match its texels, or is zero.
    InvalidImage {
        /// Name of the image.
        name: String,
        /// Declared width.
        width: u32,
        /// Declared height.
        height: u32,
        /// Texels present.
        texels: usize,
    },
    /// A triangle refers to a material that does not exist.
    MaterialIndex {
        /// Index of the triangle.
        triangle: usize,
        /// The material index it holds.
        material: u32,
        /// Number of materials in the scene.
        count: usize,
    },
    /// The scene has more triangles or materials than the GPU form can index
    /// (material indices are stored as exact `f32` integers, `< 2^24`).
    SceneTooLarge {
        /// What overflowed: `"triangles"` or `"materials"`.
        what: &'static str,
        /// How many there are.
        count: usize,
        /// The limit.
        limit: usize,
    },
    /// The camera is degenerate: zero or non-finite direction, `up` parallel
    /// to the view direction, or a field of view outside `(0, 180)` degrees.
    InvalidCamera,
    /// The BVH is deeper than the kernels' traversal stack allows.
    BvhTooDeep {
        /// Depth of the deepest leaf (root = 0).
        depth: usize,
        /// Largest depth the traversal supports (`kernels::bvh::STACK_SIZE`).
        limit: usize,
    },
    /// Frame size is zero in one dimension, or the seed stride is smaller
    /// than the width.
    FrameSize {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
        /// Requested seed-buffer stride in seeds.
        padded_width: u32,
    },
    /// A render parameter is outside its range.
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// Its value.
        value: u32,
        /// What is allowed.
        expected: &'static str,
    },
    /// A real-valued setting is outside its range (or NaN).
    InvalidSetting {
        /// Name of the setting.
        name: &'static str,
        /// Its value.
        value: f32,
        /// What is allowed.
        expected: &'static str,
    },
    /// A caller-provided buffer has the wrong length.
    BufferSize {
        /// Which buffer.
        buffer: &'static str,
        /// Required number of elements.
        expected: usize,
        /// Number of elements passed.
        actual: usize,
    },
    /// Writing an image failed (unwritable directory, full disk, ...). No
    /// file was left at `path` by the failed write.
    ImageWrite {
        /// The image file that was to be written.
        path: PathBuf,
        /// The cause.
        source: ImageWriteError,
    },
    /// A smaller trace kernel variant (`kernels::trace_variant`) was asked
    /// for a scene that uses what it leaves out.
    UnfitTraceVariant {
        /// The variant's name (`TraceVariant::name`).
        variant: &'static str,
    },
}

/// Cause of an [`Error::ImageWrite`].
#[derive(Debug)]
#[non_exhaustive]
pub enum ImageWriteError {
    /// Creating, writing, syncing or renaming the file failed.
    Io(std::io::Error),
    /// The encoder failed.
    Encode(image::ImageError),
}

impl fmt::Display for ImageWriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageWriteError::Io(e) => write!(f, "{e}"),
            ImageWriteError::Encode(e) => write!(f, "encoding failed: {e}"),
        }
    }
}

impl std::error::Error for ImageWriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ImageWriteError::Io(e) => Some(e),
            ImageWriteError::Encode(e) => Some(e),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::ObjLoad { path, source } => {
                write!(f, "cannot load OBJ file {}: {source}", path.display())
            }
            Error::MtlLoad { path, source } => {
                write!(f, "cannot load the material library of {}: {source}", path.display())
            }
            Error::GltfLoad { path, element, source } => {
                write!(f, "cannot load glTF file {} ({element}): {source}", path.display())
            }
            Error::GltfContent { path, element, reason } => {
                write!(f, "glTF file {}: {element}: {reason}", path.display())
            }
            Error::NoTriangles { path } => write!(f, "OBJ file {} contains no triangles", path.display()),
            Error::NonFiniteVertex { path, model, vertex } => write!(
                f,
                "{}: vertex {vertex} of model '{model}' has a NaN or infinite coordinate",
                path.display()
            ),
            Error::InvalidMaterial { name } => write!(
                f,
                "material '{name}' has a NaN, infinite or negative colour"
            ),
            Error::InvalidMaterialParameter {
                name,
                parameter,
                value,
                expected,
            } => write!(f, "material '{name}' has {parameter} {value}: it must be {expected}"),
            Error::InvalidLight {
                name,
                parameter,
                reason,
            } => write!(f, "light '{name}' has an invalid {parameter}: {reason}"),
            Error::InvalidEnvironmentMap { name, reason } => {
                write!(f, "environment map '{name}' is unusable: {reason}")
            }
            Error::InvalidTexture { material, reason } => {
                write!(f, "material '{material}' has an invalid texture: {reason}")
            }
            Error::InvalidImage {
                name,
                width,
                height,
                texels,
            } => write!(
                f,
                "image '{name}' is {width}x{height} but has {texels} texels (sizes must be >= 1 and match)"
            ),
            Error::MaterialIndex {
                triangle,
                material,
                count,
            } => write!(
                f,
                "triangle {triangle} uses material {material}, but the scene has {count} materials"
            ),
            Error::SceneTooLarge { what, count, limit } => {
                write!(f, "scene has {count} {what}, more than the limit of {limit}")
            }
            Error::InvalidCamera => write!(
                f,
                "degenerate camera (zero direction, up parallel to the view, or field of view outside (0, 180) degrees)"
            ),
            Error::BvhTooDeep { depth, limit } => write!(
                f,
                "BVH has depth {depth}, deeper than the {limit} levels the GPU traversal stack supports"
            ),
            Error::FrameSize {
                width,
                height,
                padded_width,
            } => write!(
                f,
                "invalid frame size {width}x{height} with seed stride {padded_width} (sizes must be >= 1 and the stride >= the width)"
            ),
            Error::UnfitTraceVariant { variant } => write!(
                f,
                "the {variant} trace kernel cannot render this scene: it uses features that kernel leaves out \
                 (textures, cut-outs, vertex normals, glossy materials, punctual lights or an environment map); \
                 the full kernel renders any scene"
            ),
            Error::InvalidParameter { name, value, expected } => {
                write!(f, "invalid {name} = {value}: expected {expected}")
            }
            Error::InvalidSetting { name, value, expected } => {
                write!(f, "invalid {name} = {value}: expected {expected}")
            }
            Error::BufferSize {
                buffer,
                expected,
                actual,
            } => write!(f, "{buffer} has {actual} elements, expected {expected}"),
            Error::ImageWrite { path, source } => {
                write!(f, "cannot write image {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::ObjLoad { source, .. } | Error::MtlLoad { source, .. } => Some(source),
            Error::ImageWrite { source, .. } => Some(source),
            Error::GltfLoad { source, .. } => Some(source),
            _ => None,
        }
    }
}
