//! Column names and units that differ from ours: the same measurement in cm/s, kN, ms, mm, mA,
//! bar and MPa, in another column order with an extra column, gives the same comparison as in SI.

use crate::common;

use damper_engine::measurement::Mapping;
use damper_engine::units::Column;

/// Rewrites a generated SI CSV: every column renamed and scaled by `1/factor`.
fn convert(si: &str, columns: &[(&str, &str, f64)]) -> String {
    let mut lines = si.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let index: Vec<usize> =
        columns.iter().map(|(from, _, _)| header.iter().position(|h| h == from).expect("column")).collect();
    let mut out = columns.iter().map(|(_, to, _)| *to).collect::<Vec<_>>().join(",") + ",operator\n";
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let row: Vec<String> = index
            .iter()
            .zip(columns)
            .map(|(&i, (_, _, f))| format!("{}", cells[i].parse::<f64>().unwrap() / f))
            .collect();
        out += &(row.join(",") + ",anna\n");
    }
    out
}

#[test]
fn other_names_and_units_give_the_same_result_as_si() {
    let dir = common::scratch("units");
    let (csv, _) = common::generate(&dir, "si", |o| o.duration = 3.0);
    let si = common::compare(&dir, &csv, "out_si", |_| {});
    let text = std::fs::read_to_string(&csv).unwrap();
    // the load cell's unit from its header cell (kN), its name and the rest through --map
    let converted = convert(
        &text,
        &[
            ("F_damper", "Force [kN]", 1e3),
            ("time", "t", 1e-3),
            ("F_demand", "Fdem", 1e3),
            ("v_damper", "vel", 1e-2),
            ("x_spool", "spool", 1e-3),
            ("i_sol", "current", 1e-3),
            ("p_ext", "pA", 1e5),
            ("p_comp", "pB", 1e6),
        ],
    );
    let other = dir.join("other.csv");
    std::fs::write(&other, converted).unwrap();
    let maps: Vec<Mapping> = [
        "Force=F_damper",
        "t=time:ms",
        "vel=v_damper:cm/s",
        "Fdem=F_demand:kN",
        "spool=x_spool:mm",
        "current=i_sol:mA",
        "pA=p_ext:bar",
        "pB=p_comp:MPa",
    ]
    .iter()
    .map(|m| Mapping::parse(m).unwrap())
    .collect();
    let mapped = common::compare(&dir, &other, "out_mapped", |o| o.maps = maps);
    assert_eq!(mapped.measurement.ignored, vec!["operator".to_string()]);
    assert_eq!(mapped.analysis.fits.len(), si.analysis.fits.len());
    for (a, b) in si.analysis.fits.iter().zip(&mapped.analysis.fits) {
        assert_eq!(a.column, b.column);
        for (x, y) in [(a.train.nrmse, b.train.nrmse), (a.validation.nrmse, b.validation.nrmse)] {
            assert!((x - y).abs() <= 1e-6 * x, "{}: {x} against {y}", a.column);
        }
        assert_eq!(a.lag.samples, b.lag.samples);
    }
    for (a, b) in si.analysis.regimes.iter().zip(&mapped.analysis.regimes) {
        assert_eq!(a.samples, b.samples, "{}", a.name);
    }
    let (f_si, f_mapped) =
        (si.measurement.get(Column::FDamper).unwrap(), mapped.measurement.get(Column::FDamper).unwrap());
    assert!(f_si.iter().zip(f_mapped).all(|(a, b)| (a - b).abs() <= 1e-9 * a.abs().max(1.0)));
    eprintln!(
        "SI: validation NRMSE {:.6}; cm/s, kN, ms, mm, mA, bar, MPa: {:.6}",
        si.analysis.force().validation.nrmse,
        mapped.analysis.force().validation.nrmse
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn displacement_in_mm_stands_in_for_velocity() {
    let dir = common::scratch("displacement");
    let (csv, g) = common::generate(&dir, "x", |o| {
        o.displacement = true;
        o.minimal = true;
    });
    let m = common::compare(&dir, &csv, "out_m", |_| {});
    assert!(m.measurement.velocity_from_displacement);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mm = convert(
        &text,
        &[
            ("time", "time", 1.0),
            ("x_damper", "x_damper [mm]", 1e-3),
            ("F_demand", "F_demand", 1.0),
            ("F_damper", "F_damper", 1.0),
        ],
    );
    let other = dir.join("x_mm.csv");
    std::fs::write(&other, mm).unwrap();
    let c = common::compare(&dir, &other, "out_mm", |_| {});
    let (a, b) = (m.analysis.force().validation.nrmse, c.analysis.force().validation.nrmse);
    eprintln!(
        "displacement (derived velocity): validation NRMSE {a:.5} in m, {b:.5} in mm, floor {:.5}",
        g.expected_floor
    );
    assert!((a - b).abs() <= 1e-6 * a);
    assert!(a < 1.1 * g.expected_floor, "the truth was driven by the same derived velocity");
    let _ = std::fs::remove_dir_all(&dir);
}
