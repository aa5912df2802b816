//! Names for what rust-gpu's SPIR-V leaves anonymous: the bound buffers
//! ([`name_globals`]) and the uniform and buffer types ([`name_types`]).

use crate::{Error, ENTRIES};
use naga::valid::ModuleInfo;
use naga::Module;
use std::collections::BTreeMap;

/// Names every bound global variable after the kernel parameter it is
/// (rust-gpu's SPIR-V carries no names, so naga would call them `global_N`):
/// `<pass>_<parameter>`, e.g. `sort_seeds_in` for binding 3 of
/// `permute_entry_sort_cs`. rust-gpu may share one variable among entry
/// points that declare the same binding with the same type; such a variable
/// is named after the parameter alone when all users agree (`params`), else
/// after all users joined by `_or_`. Checks that each entry point uses
/// exactly the bindings of [`Entry::bindings`](crate::Entry::bindings).
pub(crate) fn name_globals(module: &mut Module, info: &ModuleInfo) -> Result<(), Error> {
    let mut users: BTreeMap<naga::Handle<naga::GlobalVariable>, Vec<(&str, &str)>> = BTreeMap::new();
    for (i, ep) in module.entry_points.iter().enumerate() {
        let entry = ENTRIES
            .iter()
            .find(|e| e.name == ep.name)
            .expect("only ENTRIES are kept");
        let used = info.get_entry_point(i);
        let mut found = Vec::new();
        for (handle, global) in module.global_variables.iter() {
            if let Some(b) = global.binding.filter(|_| !used[handle].is_empty()) {
                found.push((b.group, b.binding));
                if let Some(role) = entry.bindings.get(b.binding as usize) {
                    users.entry(handle).or_default().push((entry.pass(), role));
                }
            }
        }
        found.sort_unstable();
        let expected: Vec<(u32, u32)> = (0..entry.bindings.len() as u32).map(|b| (0, b)).collect();
        if found != expected {
            return Err(Error::Bindings {
                entry: entry.name,
                found,
            });
        }
    }
    for (handle, users) in users {
        let name = match users.as_slice() {
            [(pass, role)] => format!("{pass}_{role}"),
            [(_, role), ..] if users.len() == ENTRIES.len() && users.iter().all(|u| u.1 == *role) => {
                role.to_string()
            }
            _ => users
                .iter()
                .map(|(pass, role)| format!("{pass}_{role}"))
                .collect::<Vec<_>>()
                .join("_or_"),
        };
        module.global_variables.get_mut(handle).name = Some(name);
    }
    Ok(())
}

/// `sampler_core::FrameParams`'s fields and byte offsets, in order: the
/// members of the uniform at binding 0.
pub const FRAME_PARAMS_FIELDS: [(&str, usize); 8] = {
    use core::mem::offset_of;
    use sampler_core::FrameParams as P;
    [
        ("width", offset_of!(P, width)),
        ("height", offset_of!(P, height)),
        ("padded_width", offset_of!(P, padded_width)),
        ("padded_height", offset_of!(P, padded_height)),
        ("block", offset_of!(P, block)),
        ("tile_log2", offset_of!(P, tile_log2)),
        ("frame", offset_of!(P, frame)),
        ("reserved", offset_of!(P, reserved)),
    ]
};
const _: () = assert!(core::mem::size_of::<sampler_core::FrameParams>() == 32);

/// `kernels::sampler_entry::SamplerParams`'s fields and byte offsets, in
/// order: the uniform of the sampler entry points.
pub const SAMPLER_PARAMS_FIELDS: [(&str, usize); 12] = {
    use core::mem::offset_of;
    use kernels::sampler_entry::SamplerParams as P;
    [
        ("width", offset_of!(P, width)),
        ("height", offset_of!(P, height)),
        ("spp", offset_of!(P, spp)),
        ("sample_index", offset_of!(P, sample_index)),
        ("pair", offset_of!(P, pair)),
        ("frame", offset_of!(P, frame)),
        ("key_side_log2", offset_of!(P, key_side_log2)),
        ("key_pairs", offset_of!(P, key_pairs)),
        ("key_levels", offset_of!(P, key_levels)),
        ("reserved0", offset_of!(P, reserved0)),
        ("reserved1", offset_of!(P, reserved1)),
        ("reserved2", offset_of!(P, reserved2)),
    ]
};

/// A uniform block: name, size in bytes and fields `(name, byte offset)`,
/// all `u32`.
type UniformBlock = (&'static str, usize, &'static [(&'static str, usize)]);

/// The uniform blocks of the kept entry points.
const UNIFORMS: [UniformBlock; 2] = [
    ("FrameParams", 32, &FRAME_PARAMS_FIELDS),
    (
        "SamplerParams",
        core::mem::size_of::<kernels::sampler_entry::SamplerParams>(),
        &SAMPLER_PARAMS_FIELDS,
    ),
];

/// `(name, size in bytes, [(field, byte offset, is f32)])`.
type ElementStruct = (&'static str, usize, &'static [(&'static str, usize, bool)]);

/// The buffer element structs of the feature-aware passes, as
/// `(name, size in bytes, [(field, byte offset, is f32)])`, from
/// `sampler_core::features::surface`: a struct of the SPIR-V with exactly these
/// members gets these names.
const ELEMENT_STRUCTS: [ElementStruct; 2] = {
    use core::mem::{offset_of, size_of};
    use sampler_core::{FeatureThresholds as T, SurfaceFeature as F};
    [
        (
            "SurfaceFeature",
            size_of::<F>(),
            &[
                ("id", offset_of!(F, id), false),
                ("depth", offset_of!(F, depth), true),
                ("normal", offset_of!(F, normal), false),
                ("reserved", offset_of!(F, reserved), false),
            ],
        ),
        (
            "FeatureThresholds",
            size_of::<T>(),
            &[
                ("depth_relative", offset_of!(T, depth_relative), true),
                ("normal_cos", offset_of!(T, normal_cos), true),
            ],
        ),
    ]
};

/// The entry of [`ELEMENT_STRUCTS`] whose layout `ty` has, if any.
fn element_struct(module: &Module, ty: &naga::TypeInner) -> Option<usize> {
    use naga::{Scalar, TypeInner};
    let TypeInner::Struct { members, span } = ty else {
        return None;
    };
    ELEMENT_STRUCTS.iter().position(|(_, size, fields)| {
        *span as usize == *size
            && members.len() == fields.len()
            && members.iter().zip(fields.iter()).all(|(m, (_, offset, is_f32))| {
                let scalar = if *is_f32 { Scalar::F32 } else { Scalar::U32 };
                m.offset as usize == *offset && module.types[m.ty].inner == TypeInner::Scalar(scalar)
            })
    })
}

/// Gives the anonymous types of rust-gpu's SPIR-V names a reader can follow:
/// each uniform's `FrameParamsBlock { value: FrameParams }` with
/// [`FRAME_PARAMS_FIELDS`] or `SamplerParamsBlock { value: SamplerParams }`
/// with [`SAMPLER_PARAMS_FIELDS`], and each storage buffer's
/// `<Element>Array { values: array<Element> }` (`U32Array`, `F32Array`,
/// `Vec2Array`, `Vec4Array`, `AtomicU32Array`, `SurfaceFeatureArray`,
/// `FeatureThresholdsArray`), with the element structs of
/// [`ELEMENT_STRUCTS`] named field by field.
///
/// # Errors
/// [`Error::Validation`] if a uniform is neither `FrameParams` nor
/// `SamplerParams`.
pub(crate) fn name_types(module: &mut Module) -> Result<(), Error> {
    use naga::{ArraySize, Scalar, ScalarKind, TypeInner, VectorSize};
    let bad = |message: String| Error::Validation {
        what: "the uniforms".to_string(),
        message,
    };
    let uniforms: Vec<_> = module
        .global_variables
        .iter()
        .filter(|(_, g)| g.space == naga::AddressSpace::Uniform)
        .map(|(_, g)| g.ty)
        .collect();
    if uniforms.is_empty() {
        return Err(bad("no uniform".to_string()));
    }
    let mut renames = Vec::new();
    for uniform in uniforms {
        let params = match &module.types[uniform].inner {
            TypeInner::Struct { members, .. } if members.len() == 1 => members[0].ty,
            other => return Err(bad(format!("unexpected type {other:?}"))),
        };
        // Every uniform is one of the known parameter blocks, told apart by size.
        let known = UNIFORMS
            .iter()
            .find(|(_, size, fields)| match &module.types[params].inner {
                TypeInner::Struct { members, span } => {
                    *span as usize == *size
                        && members.len() == fields.len()
                        && members.iter().zip(fields.iter()).all(|(m, (_, offset))| {
                            m.offset as usize == *offset
                                && module.types[m.ty].inner == TypeInner::Scalar(Scalar::U32)
                        })
                }
                _ => false,
            });
        let Some((name, _, fields)) = known else {
            let found = &module.types[params].inner;
            return Err(bad(format!("not FrameParams or SamplerParams: {found:?}")));
        };
        renames.push((uniform, format!("{name}Block"), vec!["value".to_string()]));
        renames.push((
            params,
            name.to_string(),
            fields.iter().map(|f| f.0.to_string()).collect(),
        ));
    }
    for (handle, ty) in module.types.iter() {
        if let Some(i) = element_struct(module, &ty.inner) {
            let (name, _, fields) = ELEMENT_STRUCTS[i];
            renames.push((
                handle,
                name.to_string(),
                fields.iter().map(|f| f.0.to_string()).collect(),
            ));
        }
    }
    for (handle, ty) in module.types.iter() {
        let TypeInner::Struct { members, .. } = &ty.inner else {
            continue;
        };
        let [member] = members.as_slice() else {
            continue;
        };
        let TypeInner::Array {
            base,
            size: ArraySize::Dynamic,
            ..
        } = module.types[member.ty].inner
        else {
            continue;
        };
        let element = match module.types[base].inner {
            TypeInner::Scalar(Scalar::U32) => "U32",
            TypeInner::Scalar(Scalar::F32) => "F32",
            TypeInner::Atomic(Scalar {
                kind: ScalarKind::Uint,
                width: 4,
            }) => "AtomicU32",
            TypeInner::Vector {
                size: VectorSize::Bi,
                scalar: Scalar::F32,
            } => "Vec2",
            TypeInner::Vector {
                size: VectorSize::Quad,
                scalar: Scalar::F32,
            } => "Vec4",
            ref inner => match element_struct(module, inner) {
                Some(i) => ELEMENT_STRUCTS[i].0,
                None => continue,
            },
        };
        renames.push((handle, format!("{element}Array"), vec!["values".to_string()]));
    }
    for (handle, name, member_names) in renames {
        let mut ty = module.types[handle].clone();
        ty.name = Some(name);
        if let TypeInner::Struct { members, .. } = &mut ty.inner {
            for (m, n) in members.iter_mut().zip(member_names) {
                m.name = Some(n);
            }
        }
        module.types.replace(handle, ty);
    }
    Ok(())
}
