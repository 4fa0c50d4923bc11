//! Records that cannot be compared with the model get a clear error naming the file and what is
//! wrong: a dead load cell, a damper that does not move, velocities beyond the model's range, a
//! time column in another unit than its header says. Calibration refuses them as comparison does.
use crate::common;

use damper_engine::calibrate::{calibrate, CalibrateOptions};
use damper_engine::comparison::{compare, CompareOptions};
use std::path::Path;

/// `src` with the cells of `column` replaced by `f(sample, cell)`.
fn edit(src: &Path, dst: &Path, column: &str, f: impl Fn(usize, &str) -> String) {
    let text = std::fs::read_to_string(src).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let j = header.split(',').position(|c| c == column).unwrap();
    let mut out = format!("{header}\n");
    for (k, line) in lines.enumerate() {
        let mut cells: Vec<String> = line.split(',').map(String::from).collect();
        cells[j] = f(k, &cells[j]);
        out += &cells.join(",");
        out.push('\n');
    }
    std::fs::write(dst, out).unwrap();
}

fn error_of(csv: &Path) -> String {
    compare(&CompareOptions::new(csv)).err().unwrap_or_else(|| panic!("{} was accepted", csv.display())).to_string()
}

#[test]
fn degenerate_records_are_refused_with_the_reason() {
    let dir = common::scratch("degenerate");
    let (csv, _) = common::generate(&dir, "m", |o| {
        o.duration = 2.0;
        o.minimal = true;
    });
    let case = |name: &str, column: &str, f: &dyn Fn(usize, &str) -> String| {
        let p = dir.join(format!("{name}.csv"));
        edit(&csv, &p, column, f);
        let e = error_of(&p);
        assert!(e.contains(&p.display().to_string()), "{name}: {e}");
        e
    };
    let e = case("dead", "F_damper", &|_, _| "-1000".into());
    assert!(e.contains("constant at -1000 N") && e.contains("load cell"), "{e}");
    // calibration refuses the same record for the same reason, before any model run
    let dead = dir.join("dead.csv");
    let Err(e) = calibrate(&CalibrateOptions::new(vec![dead.clone()]), &|_| {}) else {
        panic!("a dead load cell was calibrated")
    };
    let e = e.to_string();
    assert!(e.contains(&dead.display().to_string()) && e.contains("constant at -1000 N"), "{e}");
    let e = case("dead_late", "F_damper", &|k, c| if k > 1000 { "5".into() } else { c.into() });
    assert!(e.contains("validation part"), "{e}");
    let e = case("still", "v_damper", &|_, _| "0.00001".into());
    assert!(e.contains("does not move"), "{e}");
    // a velocity column in mm/s under an SI header: 1000× too fast
    let e = case("mm_per_s", "v_damper", &|_, c| format!("{}", c.parse::<f64>().unwrap() * 1000.0));
    assert!(e.contains("beyond the model's range") && e.contains("line"), "{e}");
    // a time column in ms under an SI header: one sample per second
    let e = case("ms", "time", &|_, c| format!("{}", c.parse::<f64>().unwrap() * 1000.0));
    assert!(e.contains("implausible") && e.contains("time [ms]"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
