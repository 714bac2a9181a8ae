//! The library's front door, end to end: read offsets (a file, or the built-in Series 60
//! sample), fit one surface, print its true error and validity, the hydrostatics at a draft,
//! and write the surface as IGES.
//!
//! ```sh
//! cargo run --release -p hullskin-hull --example fit_and_export -- [OFFSETS.csv [DRAFT [OUT.igs]]]
//! ```

use std::error::Error;
use std::fs::File;
use std::io::BufWriter;

use hull::{
    fit_offsets, iges_timestamp, read_offsets, series60_sample, write_iges, FitConfig, Hydrostatics,
    HydrostaticsOptions, IgesMeta, Units,
};

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let offsets = match args.first() {
        Some(path) => read_offsets(path.as_ref(), Units::Metre)?,
        None => series60_sample(),
    };
    let fit = fit_offsets(&offsets, &FitConfig::default())?;
    let e = &fit.error.overall;
    println!(
        "{}: {} sections, {}x{} control points, true error max {:.4} m, RMS {:.4} m",
        offsets.source,
        offsets.sections.len(),
        fit.surface.n_u(),
        fit.surface.n_v(),
        e.max,
        e.rms
    );
    for finding in &fit.validity {
        println!("validity: {}", finding.message(offsets.units.symbol()));
    }
    // The draft: given, else 0.6 of the offsets' height (the sample's design draft is 6.5 m).
    let draft = match args.get(1) {
        Some(t) => t.parse()?,
        None => {
            let zs = offsets.sections.iter().flat_map(|s| s.points.iter().map(|p| p.z));
            0.6 * zs.fold(f64::NEG_INFINITY, f64::max)
        }
    };
    let options = HydrostaticsOptions { perpendiculars: offsets.perpendiculars, ..HydrostaticsOptions::default() };
    let row = Hydrostatics::new(&fit.surface, &options)?.at(draft)?;
    println!("at draft {draft:.3} m: volume {:.1} m3, displacement {:.1} t, CB {:.4}", row.vol, row.displ, row.cb);
    let out = args.get(2).map_or("hull.igs", String::as_str);
    let meta = IgesMeta::new(offsets.units.into(), out, &iges_timestamp(0));
    write_iges(&mut BufWriter::new(File::create(out)?), &fit.surface, &meta)?;
    println!("wrote {out}");
    Ok(())
}
