//! `data/measurements/rig_export_example.csv`, a rig logger's export of model data (see its
//! README), read with the command line documented there; and sample rates other than 1 kHz.

use crate::common;

use damper_engine::measurement::Mapping;
use damper_engine::units::Column;
use std::path::Path;

/// The `--map` options of the README's command.
const MAPS: [&str; 8] = [
    "Timestamp=time",
    "Velocity=v_damper",
    "Force demand=F_demand",
    "Load cell=F_damper",
    "Spool=x_spool",
    "Valve current=i_sol",
    "p rebound=p_ext",
    "p compression=p_comp",
];

fn example() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/measurements/rig_export_example.csv")
}

/// NRMSE against the noise floor, as in round_trip.rs.
fn assert_at_floor(c: &damper_engine::comparison::Comparison, expected: f64, what: &str) {
    let nrmse = c.analysis.force().validation.nrmse;
    eprintln!("{what}: validation NRMSE {nrmse:.5}, expected floor {expected:.5} (ratio {:.3})", nrmse / expected);
    assert!((0.9..1.1).contains(&(nrmse / expected)), "{what}: NRMSE {nrmse} is not at the noise floor {expected}");
    assert_eq!(c.analysis.force().lag.samples, 0, "{what}: lag");
}

#[test]
fn the_rig_export_example_reads_and_fits_at_the_noise_floor() {
    let dir = common::scratch("rig_export");
    let maps: Vec<Mapping> = MAPS.iter().map(|m| Mapping::parse(m).unwrap()).collect();
    let c = common::compare(&dir, &example(), "out", |o| o.maps = maps);
    let m = &c.measurement;

    // 500 Hz for 4 s, three samples dropped and put back on the grid
    assert_eq!(m.len(), 2001);
    assert!((m.median_interval() - 2e-3).abs() < 1e-9, "{}", m.median_interval());
    // every channel is read: the oil temperature too (in °C, a model input)
    assert!(m.ignored.is_empty(), "{:?}", m.ignored);
    let said = m.notes.join("\n");
    for part in [
        "decimal comma",
        "holds timestamps",
        "2 gap(s)",
        "between lines 705 and 706 (1 missing)",
        "between lines 1504 and 1505 (2 missing)",
        "resampled",
    ] {
        assert!(said.contains(part), "notes lack '{part}': {said}");
    }
    // the first sample (line 6) in SI: 0,02 mm/s, 18,5586 kN, -0,999 kN, 2,4987 mm, 5,07 bar, 41,3 °C
    assert_eq!(m.lines[0], 6);
    for (col, si) in [
        (Column::VDamper, 0.02e-3),
        (Column::FDemand, 18558.6),
        (Column::FDamper, -999.0),
        (Column::XSpool, 2.4987e-3),
        (Column::PExt, 5.07e5),
        (Column::TOil, 41.3 + 273.15),
    ] {
        let v = m.get(col).unwrap()[0];
        assert!((v - si).abs() <= 1e-9 * si.abs(), "{col}: {v} against {si}");
    }
    // the notes reach the report
    let html = std::fs::read_to_string(dir.join("out/report.html")).unwrap();
    assert!(html.contains("2 gap(s) in the sampling"), "report lacks the gap note");

    // the same data as generated (README: --rate 500 --duration 4 --seed 21) sets the floor
    let (_, g) = common::generate(&dir, "si", |o| {
        o.rate = 500.0;
        o.duration = 4.0;
        o.seed = 21;
    });
    assert_at_floor(&c, g.expected_floor, "rig export example");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sample_rates_other_than_1khz_work_end_to_end() {
    let dir = common::scratch("rates");
    for rate in [500.0, 2000.0] {
        let (csv, g) = common::generate(&dir, &format!("r{rate}"), |o| {
            o.rate = rate;
            o.duration = 3.0;
        });
        let c = common::compare(&dir, &csv, &format!("out{rate}"), |_| {});
        assert!((c.analysis.dt - 1.0 / rate).abs() < 1e-9 / rate, "{rate} Hz: dt {}", c.analysis.dt);
        assert!(c.warnings.is_empty(), "{rate} Hz: {:?}", c.warnings);
        assert_at_floor(&c, g.expected_floor, &format!("{rate} Hz"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
