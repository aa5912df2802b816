//! Parsing the SPIR-V and selecting the kept entry points: the naga module
//! of all [`ENTRIES`] ([`permutation_module`]) and of one ([`single_entry`]).

use crate::error::chain;
use crate::loops::spill_break_conditions;
use crate::naming::{name_globals, name_types};
use crate::{Entry, Error, ENTRIES};
use kernels::permute_entry::PERMUTE_WORKGROUP;
use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use naga::{Module, ShaderStage};

/// Validates `module` with every check; `what` names it in the error.
///
/// # Errors
/// [`Error::Validation`] with naga's message and its causes.
pub(crate) fn validate(module: &Module, what: &str) -> Result<ModuleInfo, Error> {
    Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(module)
        .map_err(|e| Error::Validation {
            what: what.to_string(),
            message: chain(e.as_inner()),
        })
}

/// Keeps only the entry points named (by their [`Entry::name`]) in `keep`
/// and drops everything nothing kept uses.
fn retain_entries(module: &mut Module, keep: &[&str]) {
    module.entry_points.retain(|ep| keep.contains(&ep.name.as_str()));
    naga::compact::compact(module, naga::compact::KeepUnused::No);
}

/// The naga module of the sixteen [`ENTRIES`], renamed, compacted and
/// validated: everything the generated files are written from.
///
/// # Errors
/// [`Error::Spirv`], [`Error::MissingEntry`], [`Error::WorkgroupSize`] or
/// [`Error::Validation`].
pub fn permutation_module(spirv: &[u8]) -> Result<(Module, ModuleInfo), Error> {
    let options = naga::front::spv::Options {
        // Compute only: no position to flip.
        adjust_coordinate_space: false,
        // As wgpu parses SPIR-V: capabilities naga does not know are errors.
        strict_capabilities: true,
        block_ctx_dump_prefix: None,
    };
    let mut module = naga::front::spv::parse_u8_slice(spirv, &options).map_err(Error::Spirv)?;
    for entry in &ENTRIES {
        let ep = module
            .entry_points
            .iter_mut()
            .find(|ep| ep.name == entry.spirv)
            .ok_or(Error::MissingEntry(entry.spirv))?;
        if ep.stage != ShaderStage::Compute || ep.workgroup_size != [PERMUTE_WORKGROUP, 1, 1] {
            return Err(Error::WorkgroupSize {
                entry: entry.spirv,
                size: ep.workgroup_size,
            });
        }
        ep.name = entry.name.to_string();
    }
    let names: Vec<&str> = ENTRIES.iter().map(|e| e.name).collect();
    retain_entries(&mut module, &names);
    spill_break_conditions(&mut module);
    let info = validate(&module, "the seed-permutation entry points")?;
    name_globals(&mut module, &info)?;
    name_types(&mut module)?;
    Ok((module, info))
}

/// The module of one entry point: everything else compacted away.
pub(crate) fn single_entry(module: &Module, entry: &Entry) -> Result<(Module, ModuleInfo), Error> {
    let mut single = module.clone();
    retain_entries(&mut single, &[entry.name]);
    // One entry point: its buffers are named after the kernel's parameters.
    for (_, global) in single.global_variables.iter_mut() {
        if let Some(role) = global
            .binding
            .and_then(|b| entry.bindings.get(b.binding as usize))
        {
            global.name = Some(role.to_string());
        }
    }
    let info = validate(&single, entry.name)?;
    Ok((single, info))
}
