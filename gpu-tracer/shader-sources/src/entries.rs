//! The entry points kept in the generated sources ([`ENTRIES`]) and the
//! paths of the files generated for them.

use kernels::permute_entry::{
    INTENSITY_ENTRY, RECORD_SOURCE_ENTRY, RETARGET_ENTRY, RETARGET_FEATURES_ENTRY, SEED_INIT_ENTRY,
    SORT_ENTRY, SORT_FEATURES_ENTRY,
};
use kernels::reproject_entry::{
    CLAIM_ENTRY, CLEAR_CLAIMS_ENTRY, LIST_FREE_ENTRY, RECYCLE_ENTRY, SCAN_ENTRY, TAKE_ENTRY,
};
use kernels::sampler_entry::{SCREEN_SOBOL_ENTRY, ZSOBOL_ENTRY};

/// One entry point kept in the generated sources.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Its name in the SPIR-V: rust-gpu's module path, a constant of
    /// `kernels::permute_entry` or `kernels::reproject_entry`.
    pub spirv: &'static str,
    /// Its name in every generated language: [`Entry::spirv`] with `::`
    /// replaced by `_`. Also the stem of its GLSL file.
    pub name: &'static str,
    /// What binding `i` (group 0) holds, for `i` in `0..bindings.len()`: the
    /// kernel's parameter name. Binding 0 is always `params`, the uniform
    /// `sampler_core::FrameParams` (`kernels::sampler_entry::SamplerParams`
    /// for the samplers).
    pub bindings: &'static [&'static str],
}

/// The entry points kept, in the order a frame dispatches them within each
/// group (permutation, feature-aware permutation, reprojection, then the
/// a-priori samplers). All have 64-wide workgroups
/// (`kernels::permute_entry::PERMUTE_WORKGROUP`).
pub const ENTRIES: [Entry; 15] = [
    Entry {
        spirv: SEED_INIT_ENTRY,
        name: "permute_entry_seed_init_cs",
        bindings: &["params", "seeds_out"],
    },
    Entry {
        spirv: INTENSITY_ENTRY,
        name: "permute_entry_intensity_cs",
        bindings: &["params", "color", "intensity"],
    },
    Entry {
        spirv: SORT_ENTRY,
        name: "permute_entry_sort_cs",
        bindings: &["params", "intensity", "tile", "seeds_in", "seeds_out"],
    },
    Entry {
        spirv: RETARGET_ENTRY,
        name: "permute_entry_retarget_cs",
        bindings: &["params", "table", "seeds_in", "seeds_out"],
    },
    Entry {
        spirv: SORT_FEATURES_ENTRY,
        name: "permute_entry_sort_features_cs",
        bindings: &[
            "params",
            "intensity",
            "features",
            "thresholds",
            "tile",
            "seeds_in",
            "seeds_out",
        ],
    },
    Entry {
        spirv: RECORD_SOURCE_ENTRY,
        name: "permute_entry_record_source_cs",
        bindings: &["params", "table", "sources"],
    },
    Entry {
        spirv: RETARGET_FEATURES_ENTRY,
        name: "permute_entry_retarget_features_cs",
        bindings: &[
            "params",
            "table",
            "sources",
            "features",
            "thresholds",
            "seeds_in",
            "seeds_out",
        ],
    },
    Entry {
        spirv: CLEAR_CLAIMS_ENTRY,
        name: "reproject_entry_clear_claims_cs",
        bindings: &["params", "claims"],
    },
    Entry {
        spirv: CLAIM_ENTRY,
        name: "reproject_entry_claim_cs",
        bindings: &["params", "motion", "claims"],
    },
    Entry {
        spirv: TAKE_ENTRY,
        name: "reproject_entry_take_cs",
        bindings: &["params", "motion", "claims", "seeds_in", "seeds_out", "counts"],
    },
    Entry {
        spirv: SCAN_ENTRY,
        name: "reproject_entry_scan_cs",
        bindings: &["params", "counts"],
    },
    Entry {
        spirv: LIST_FREE_ENTRY,
        name: "reproject_entry_list_free_cs",
        bindings: &["params", "claims", "counts", "free"],
    },
    Entry {
        spirv: RECYCLE_ENTRY,
        name: "reproject_entry_recycle_cs",
        bindings: &[
            "params",
            "motion",
            "claims",
            "counts",
            "free",
            "seeds_in",
            "seeds_out",
        ],
    },
    Entry {
        spirv: SCREEN_SOBOL_ENTRY,
        name: "sampler_entry_screen_sobol_cs",
        bindings: &["params", "keys", "samples"],
    },
    Entry {
        spirv: ZSOBOL_ENTRY,
        name: "sampler_entry_zsobol_cs",
        bindings: &["params", "samples"],
    },
];

impl Entry {
    /// The pass's short name: [`Entry::name`] without the module prefix and
    /// the `_cs` suffix (`sort`, `clear_claims`); prefixes the names of its
    /// buffers in the generated code (`sort_seeds_in`).
    pub fn pass(&self) -> &'static str {
        let name = self.name.strip_suffix("_cs").unwrap_or(self.name);
        name.strip_prefix("permute_entry_")
            .or_else(|| name.strip_prefix("reproject_entry_"))
            .or_else(|| name.strip_prefix("sampler_entry_"))
            .unwrap_or(name)
    }
}

/// Path of the WGSL module (all entry points), relative to
/// [`OUTPUT_DIR`](crate::OUTPUT_DIR).
pub const WGSL_FILE: &str = "wgsl/seed_permutation.wgsl";
/// Path of the GLSL file of `entry` (a compute shader whose function is
/// `main`), relative to [`OUTPUT_DIR`](crate::OUTPUT_DIR).
pub fn glsl_file(entry: &Entry) -> String {
    format!("glsl/{}.comp", entry.name)
}

/// Path of the HLSL file of `entry` (function [`Entry::name`]), relative to
/// [`OUTPUT_DIR`](crate::OUTPUT_DIR).
pub fn hlsl_file(entry: &Entry) -> String {
    format!("hlsl/{}.hlsl", entry.name)
}

/// Path of the MSL file of `entry` (kernel [`Entry::name`]), relative to
/// [`OUTPUT_DIR`](crate::OUTPUT_DIR).
pub fn msl_file(entry: &Entry) -> String {
    format!("msl/{}.metal", entry.name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn names_are_the_spirv_names_with_underscores() {
        for e in &ENTRIES {
            assert_eq!(e.name, e.spirv.replace("::", "_"));
            assert!(e.name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
        }
        let unique: BTreeSet<&str> = ENTRIES.iter().map(|e| e.name).collect();
        assert_eq!(unique.len(), ENTRIES.len());
    }
}
