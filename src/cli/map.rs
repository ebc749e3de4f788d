//! `fem2rbd map model.toml -o bodies.csv`: the rigid-body table of a model (paper §3.1),
//! written atomically, with a one-line summary on stdout.
use anyhow::{bail, Context, Result};
use clap::Args;
use fem2rbd::mapping::{self, table, MapOptions};
use fem2rbd::model::Model;
use fem2rbd::output::atomic::write_atomic;
use std::path::PathBuf;

/// Options of `map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// Model file (.toml or .json).
    pub model: PathBuf,
    /// Output CSV (name, group, type, material, element, kind, centre, quaternion w x y z,
    /// half extents, mass, principal inertia).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Largest overlap volume left between two boxes after trimming (m³).
    #[arg(long, default_value_t = 1e-9)]
    pub overlap_tolerance: f64,
    /// Keep the boxes untrimmed (no overlap removal).
    #[arg(long)]
    pub no_trim: bool,
}

/// Runs `map`.
pub fn run(args: &MapArgs, quiet: bool, allow_unusual: bool) -> Result<()> {
    if !(args.overlap_tolerance >= 0.0 && args.overlap_tolerance.is_finite()) {
        bail!(
            "--overlap-tolerance must be a finite volume ≥ 0 m³, got {}",
            args.overlap_tolerance
        );
    }
    fem2rbd::output::location::check_output_file(&args.output, "--output")?;
    fem2rbd::output::location::check_not_an_input(&args.output, &[&args.model], "--output")?;
    let model = Model::load(&args.model)?;
    super::plausible(&model, &args.model, allow_unusual)?;
    let input =
        mapping::from_model(&model).with_context(|| format!("mapping {}", args.model.display()))?;
    let opts = MapOptions {
        remove_overlaps: !args.no_trim,
        overlap_tolerance_m3: args.overlap_tolerance,
    };
    let m = mapping::map_to_boxes(&input, &opts)
        .with_context(|| format!("mapping {}", args.model.display()))?;
    write_atomic(&args.output, table::bodies_csv(&m.bodies).as_bytes())
        .with_context(|| format!("writing {}", args.output.display()))?;
    if !quiet {
        let total: f64 = m.bodies.iter().map(|b| b.mass_kg).sum();
        let (overlap, _) = mapping::overlap::max_pairwise_overlap(&m.bodies);
        println!(
            "{}: {} rigid bodies in {} groups, total mass {:.6} kg, {} boxes trimmed, \
             max pairwise overlap {:.3e} m³ -> {}",
            args.model.display(),
            m.bodies.len(),
            mapping::groups(&m.bodies).len(),
            total,
            m.trim.trimmed_boxes,
            overlap,
            args.output.display()
        );
    }
    Ok(())
}
