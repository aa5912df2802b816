//! `bake defaults`: regenerates the files of `sampler-core/data` (or a set of
//! them) with the committed parameters.

use anyhow::Result;
use bake::{bake_default_set, create_dir, create_file, write_all, DefaultSet};
use std::path::Path;
use std::time::Instant;

use crate::progress::bar;

pub(crate) fn defaults(out: &Path, only: &[DefaultSet]) -> Result<()> {
    create_dir(out)?;
    let sets = if only.is_empty() {
        DefaultSet::ALL.to_vec()
    } else {
        only.to_vec()
    };
    for set in sets {
        // Check writability before baking.
        let files = set
            .files()
            .iter()
            .map(|name| Ok((out.join(name), create_file(&out.join(name))?)))
            .collect::<Result<Vec<_>>>()?;
        let pb = bar(0, &format!("{set:?}"));
        let start = Instant::now();
        let (outputs, bakes) = bake_default_set(set, &mut |d, t| {
            pb.set_length(t);
            pb.set_position(d)
        })?;
        pb.finish_and_clear();
        println!("{set:?}: baked in {:.3} s", start.elapsed().as_secs_f64());
        for t in &bakes {
            println!(
                "  table {}: energy identity {} -> {} (ratio {:.5})",
                t.index,
                t.energy_identity,
                t.energy,
                t.energy_ratio()
            );
        }
        for ((path, file), (_, bytes)) in files.into_iter().zip(outputs) {
            write_all(file, &path, &bytes)?;
            println!("  wrote {} ({} bytes)", path.display(), bytes.len());
        }
    }
    Ok(())
}
