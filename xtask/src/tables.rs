//! `cargo xtask tables`: every algorithm of the facade on `bunny.off` and
//! `armadillo.obj` from vertex 0, in the layout of Tables 1 and 3 of Qin et
//! al. 2016: time, window propagations and peak window memory, each as a
//! ratio to VTP measured in the same run.

use anyhow::Result;
use geodesics::Algorithm;

use crate::report::{Cell, Column, JsonFile, Report};
use crate::{best_of, build_renumbered, data_dir, read};

/// One table per mesh. `only`: a comma-separated subset of the algorithm
/// names (all if `None`).
pub fn table(runs: usize, only: Option<&str>, json: Option<JsonFile>) -> Result<()> {
    let names: Vec<&str> = match only {
        Some(list) => list.split(',').map(str::trim).collect(),
        None => Algorithm::NAMES.to_vec(),
    };
    for name in &names {
        name.parse::<Algorithm>()?;
    }
    let dir = data_dir()?;
    let mut report = Report::new("tables", Some(runs), &dir, json)?;
    report.note(&format!(
        "Every algorithm from vertex 0, best of {runs} runs (solve only)\n"
    ));
    for file in ["bunny.off", "armadillo.obj"] {
        let mesh = build_renumbered(read(&dir.join(file))?, false)?;
        report.table(
            Some(format!("{file} ({} faces)", mesh.face_count())),
            [
                vec![Column::left("algorithm")],
                Column::rights(&[
                    "s",
                    "× VTP time",
                    "propagations",
                    "× VTP propagations",
                    "peak windows",
                    "peak window KiB",
                ]),
            ]
            .concat(),
        );
        let (vtp_s, _, vtp) = best_of(&mesh, &Algorithm::default(), runs)?;
        for &name in &names {
            let algorithm: Algorithm = name.parse()?;
            let (s, st) = if name == "vtp" {
                (vtp_s, vtp.clone())
            } else {
                {
                    let (s, _, st) = best_of(&mesh, &algorithm, runs)?;
                    (s, st)
                }
            };
            report.row(vec![
                Cell::text(name),
                Cell::fixed(s, 3),
                Cell::fixed(s / vtp_s, 2),
                Cell::shown(st.window_propagations),
                Cell::fixed(
                    st.window_propagations as f64 / vtp.window_propagations.max(1) as f64,
                    2,
                ),
                Cell::shown(st.peak_live_windows),
                Cell::fixed(st.peak_window_bytes as f64 / 1024.0, 0),
            ]);
        }
        report.note("");
    }
    report.finish()
}
