//! Measurement files as engineers' loggers and spreadsheets write them: quoted cells, a byte-order
//! mark, another encoding, decimal commas, timestamps, jittered or dropped samples.

use damper_engine::measurement::{Mapping, Measurement, DEFAULT_MAX_GAP};
use damper_engine::rng::Rng;
use damper_engine::units::Column;

fn parse(text: &[u8], maps: &[&str]) -> Result<Measurement, String> {
    let maps: Vec<Mapping> = maps.iter().map(|m| Mapping::parse(m).unwrap()).collect();
    Measurement::parse("m.csv", text, &maps, DEFAULT_MAX_GAP).map_err(|e| e.to_string())
}

fn assert_close(a: &[f64], b: &[f64], tol: f64) {
    assert_eq!(a.len(), b.len(), "{a:?} against {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() <= tol, "{a:?} against {b:?}");
    }
}

/// Rows `k·dt, 0.1, 1000, 900` for each k, with `delim`.
fn rows(ks: &[f64], dt: f64, delim: &str) -> String {
    ks.iter().map(|k| format!("{}{delim}0.1{delim}1000{delim}{}\n", k * dt, 900.0 + k)).collect()
}

#[test]
fn quoted_header_cells_may_hold_the_delimiter() {
    let data = rows(&[0.0, 1.0, 2.0], 1e-3, ",");
    let text = format!("time,v_damper,F_demand,\"F_damper, load cell\"\n{data}");
    let m = parse(text.as_bytes(), &["F_damper, load cell=F_damper"]).expect("quoted header with a comma");
    assert_eq!(m.get(Column::FDamper).unwrap(), &[900.0, 901.0, 902.0]);
    assert_eq!(m.describe_column(Column::FDamper), "column 4 ('F_damper, load cell')");

    // the unit inside the quotes
    let data = "0,0.1,1000,0.9\n0.001,0.1,1000,0.901\n0.002,0.1,1000,0.902\n";
    let text = format!("time,v_damper,F_demand,\"F_damper, load cell [kN]\"\n{data}");
    let m = parse(text.as_bytes(), &["F_damper, load cell=F_damper"]).expect("quoted header with a unit");
    assert_close(m.get(Column::FDamper).unwrap(), &[900.0, 901.0, 902.0], 1e-9);

    // doubled quotes in a header, quoted numbers, a quoted cell with the delimiter in an ignored column
    let text = "time,\"v \"\"raw\"\" [mm/s]\",F_demand,F_damper,remark\n\
                \"0\",\"100\",1000,900,\"ok, fine\"\n0.001,\"200\",1000,900,x\n0.002,300,1000,900,y\n";
    let m = parse(text.as_bytes(), &["v \"raw\"=v_damper"]).expect("doubled quotes");
    assert_close(m.get(Column::VDamper).unwrap(), &[0.1, 0.2, 0.3], 1e-12);
    assert_eq!(m.ignored, vec!["remark".to_string()]);
}

#[test]
fn a_byte_order_mark_is_skipped() {
    let text = format!("\u{feff}time;v_damper;F_demand;F_damper\n{}", rows(&[0.0, 1.0, 2.0], 1e-3, ";"));
    let m = parse(text.as_bytes(), &[]).expect("BOM");
    assert_eq!(m.time, vec![0.0, 1e-3, 2e-3]);
    assert_eq!(m.lines, vec![2, 3, 4]);
}

#[test]
fn text_that_is_not_utf8_names_its_line_and_column() {
    // cp1252 "°" is the byte 0xB0
    let mut text = b"time,v_damper,F_demand,F_damper,T_oil [\xb0C]\n".to_vec();
    text.extend_from_slice(b"0,0,0,0,40\n");
    let err = parse(&text, &[]).unwrap_err();
    for part in ["m.csv, line 1, column 5", "not UTF-8", "0xB0", "iconv -f cp1252 -t utf-8"] {
        assert!(err.contains(part), "lacks '{part}': {err}");
    }
    let mut text = b"# rig 3\ntime,v_damper,F_demand,F_damper,operator\n0,0,0,0,anna\n".to_vec();
    text.extend_from_slice(b"0.001,0,0,0,J\xfcrgen\n");
    let err = parse(&text, &[]).unwrap_err();
    assert!(err.contains("m.csv, line 4, column 5 ('operator'): not UTF-8"), "{err}");
}

#[test]
fn line_numbers_count_comments_blank_lines_and_crlf() {
    let text = "# logger v2\r\n\r\n# channels:\r\ntime,v_damper,F_demand,F_damper\r\n\
                0,0,0,0\r\n# marker\r\n0.001,0,0,0\r\n0.002,0,0,0\r\n\r\n";
    let m = parse(text.as_bytes(), &[]).expect("CRLF with comments");
    assert_eq!(m.lines, vec![5, 7, 8]);
    let text = "# logger\r\ntime,v_damper,F_demand,F_damper\r\n0,0,0,0\r\n\r\n0.001,0,0,0\r\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("m.csv, line 4: empty line inside the data"), "{err}");
    let text = "time,v_damper,F_demand,F_damper\n0,0,0,0\n0.001,0,0,0\n0.002,0,x,0\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("m.csv, line 4, column 3 ('F_demand'): not a number: 'x'"), "{err}");
}

#[test]
fn decimal_commas_with_semicolon_or_tab() {
    for delim in [";", "\t"] {
        let text = format!(
            "time [ms]{delim}v_damper [mm/s]{delim}F_demand [kN]{delim}F_damper [kN]\n\
             0{delim}1,5{delim}1{delim}0,9\n0,5{delim}-2,25{delim}1{delim}0,901\n1{delim}3{delim}1{delim}0,902\n"
        );
        let m = parse(text.as_bytes(), &[]).expect("decimal comma");
        assert_close(&m.time, &[0.0, 0.5e-3, 1e-3], 1e-15);
        assert_close(m.get(Column::VDamper).unwrap(), &[1.5e-3, -2.25e-3, 3e-3], 1e-15);
        assert_close(m.get(Column::FDamper).unwrap(), &[900.0, 901.0, 902.0], 1e-9);
        assert!(m.notes.iter().any(|n| n.contains("decimal comma") && n.contains("'1,5'")), "{:?}", m.notes);
    }
    // one file, both separators: refused
    let text = "time;v_damper;F_demand;F_damper\n0;1,5;1;0\n0.001;1;1;0\n0.002;1;1;0\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("line 2, column 2 ('v_damper'): '1,5' has a comma") && err.contains("line 3"), "{err}");
    // a point-decimal file has no note
    let m = parse(format!("time;v_damper;F_demand;F_damper\n{}", rows(&[0.0, 1.0, 2.0], 1e-3, ";")).as_bytes(), &[])
        .unwrap();
    assert!(m.notes.iter().all(|n| !n.contains("decimal comma")), "{:?}", m.notes);
}

#[test]
fn decimal_commas_in_a_comma_file_only_when_unambiguous() {
    // "1,5" cannot be a thousands separator: the file uses decimal commas, so "1,500" is 1.5 too
    let text = "time,v_damper,F_demand,F_damper\n0,\"0,1\",\"1,500\",900\n\"0,001\",\"0,2\",1,900\n\
                \"0,002\",\"0,3\",1,900\n";
    let m = parse(text.as_bytes(), &[]).expect("quoted decimal commas");
    assert_close(&m.time, &[0.0, 1e-3, 2e-3], 1e-15);
    assert_close(m.get(Column::FDemand).unwrap(), &[1.5, 1.0, 1.0], 1e-15);
    assert!(m.notes.iter().any(|n| n.contains("decimal comma")), "{:?}", m.notes);
    // only thousands-like cells: 1.5 or 1500?
    let text = "time,v_damper,F_demand,F_damper\n0,1,\"1,500\",900\n1,1,\"2,000\",900\n2,1,1,900\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("line 2, column 3 ('F_demand')") && err.contains("thousands separator"), "{err}");
    // unquoted, a decimal comma splits the number
    let text = "time,v_damper,F_demand,F_damper\n0,0,1,5,900\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("line 2, column 5: 5 fields") && err.contains("decimal comma splits a number"), "{err}");
}

#[test]
fn time_in_microseconds_and_as_timestamps() {
    for unit in ["us", "\u{b5}s", "\u{3bc}s"] {
        let text = format!("time [{unit}],v_damper,F_demand,F_damper\n{}", rows(&[0.0, 1.0, 2.0], 500.0, ","));
        let m = parse(text.as_bytes(), &[]).expect(unit);
        assert_close(&m.time, &[0.0, 500e-6, 1000e-6], 1e-18);
    }
    let cases: [(&[&str], f64); 4] = [
        (&["2026-03-04T10:15:30.123", "2026-03-04T10:15:30.125", "2026-03-04T10:15:30.127"], 2e-3),
        (&["2026-03-04 10:15:30.123456", "2026-03-04 10:15:30.123956", "2026-03-04 10:15:30.124456"], 0.5e-3),
        (&["2026-03-04T23:59:59.999Z", "2026-03-05T00:00:00.000Z", "2026-03-05T00:00:00.001Z"], 1e-3),
        // a zone change between samples: the offsets are honoured
        (&["2026-03-04T10:00:00+01:00", "2026-03-04T09:00:01+00:00", "2026-03-04T09:00:02Z"], 1.0),
    ];
    for (stamps, dt) in cases {
        let text: String = std::iter::once("Timestamp;v_damper;F_demand;F_damper\n".to_string())
            .chain(stamps.iter().map(|s| format!("{s};0,1;1000;900\n")))
            .collect();
        let m = parse(text.as_bytes(), &["Timestamp=time"]).unwrap_or_else(|e| panic!("{stamps:?}: {e}"));
        assert_close(&m.time, &[0.0, dt, 2.0 * dt], 1e-12);
        assert!(m.notes.iter().any(|n| n.contains("timestamps") && n.contains(stamps[0])), "{:?}", m.notes);
    }
    // ISO 8601's decimal comma in the seconds, with a decimal-comma file
    let text = "time;v_damper;F_demand;F_damper\n2026-03-04 10:15:30,000;0,1;1;1\n\
                2026-03-04 10:15:30,002;0,1;1;1\n2026-03-04 10:15:30,004;0,1;1;1\n";
    assert_close(&parse(text.as_bytes(), &[]).unwrap().time, &[0.0, 2e-3, 4e-3], 1e-12);
    // a broken timestamp, and a zone on some samples only
    let text = "time,v_damper,F_demand,F_damper\n2026-03-04T10:15:30.000,0,0,0\n2026-03-04T10:15:30.001,0,0,0\n\
                2026-03-04T10:15:3x.002,0,0,0\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("line 4, column 1 ('time'): '2026-03-04T10:15:3x.002' is not an ISO 8601 timestamp"), "{err}");
    let text = "time,v_damper,F_demand,F_damper\n2026-03-04T10:15:30.000,0,0,0\n2026-03-04T10:15:30.001Z,0,0,0\n\
                2026-03-04T10:15:30.002,0,0,0\n";
    let err = parse(text.as_bytes(), &[]).unwrap_err();
    assert!(err.contains("line 3, column 1 ('time')") && err.contains("time zone"), "{err}");
}

/// A file with time `t` and a linear `v_damper` and `F_damper`: exact under linear interpolation.
fn linear(t: &[f64]) -> String {
    let mut s = String::from("time,v_damper,F_demand,F_damper\n");
    for t in t {
        s += &format!("{t},{},1000,{}\n", 0.5 * t, 100.0 + 2000.0 * t);
    }
    s
}

#[test]
fn jitter_beyond_one_percent_is_resampled_onto_the_median_interval() {
    let dt = 2e-3;
    // ±3 % jitter, alternating
    let t: Vec<f64> = (0..50).map(|k| k as f64 * dt + if k % 2 == 1 { 0.03 * dt } else { 0.0 }).collect();
    let m = parse(linear(&t).as_bytes(), &[]).unwrap();
    let median = (t[2] - t[1]).max(t[1] - t[0]);
    assert_eq!(m.len(), ((t[49] - t[0]) / median).floor() as usize + 1);
    for (k, w) in m.time.windows(2).enumerate() {
        assert!((w[1] - w[0] - median).abs() < 1e-12, "interval {k}: {}", w[1] - w[0]);
    }
    assert_close(m.get(Column::VDamper).unwrap(), &m.time.iter().map(|t| 0.5 * t).collect::<Vec<_>>(), 1e-12);
    assert_close(m.get(Column::FDamper).unwrap(), &m.time.iter().map(|t| 100.0 + 2000.0 * t).collect::<Vec<_>>(), 1e-9);
    assert!(m.notes.iter().any(|n| n.contains("not uniform")), "{:?}", m.notes);
    assert!(m.notes.iter().any(|n| n.contains("resampled")), "{:?}", m.notes);
    // each resampled sample keeps the line of the measured sample at or before it
    assert_eq!(m.lines[0], 2);
    assert!(m.lines.windows(2).all(|w| w[1] >= w[0]) && *m.lines.last().unwrap() <= 51);

    // within 1 %: the samples stay where they were
    let t: Vec<f64> = (0..50).map(|k| k as f64 * dt + if k % 2 == 1 { 0.004 * dt } else { 0.0 }).collect();
    let m = parse(linear(&t).as_bytes(), &[]).unwrap();
    assert_eq!(m.time, t);
    assert!(m.notes.is_empty(), "{:?}", m.notes);
}

#[test]
fn dropped_samples_are_interpolated_and_listed_longer_gaps_refused() {
    let dt = 1e-3;
    // samples 10 and 11 (lines 12, 13) and 30 (line 32) dropped
    let t: Vec<f64> = (0..60).filter(|k| ![10, 11, 30].contains(k)).map(|k| k as f64 * dt).collect();
    let m = parse(linear(&t).as_bytes(), &[]).unwrap();
    assert_eq!(m.len(), 60);
    assert_close(&m.time, &(0..60).map(|k| k as f64 * dt).collect::<Vec<_>>(), 1e-15);
    assert_close(m.get(Column::FDamper).unwrap(), &m.time.iter().map(|t| 100.0 + 2000.0 * t).collect::<Vec<_>>(), 1e-9);
    let gaps = m.notes.iter().find(|n| n.contains("gap")).expect("gaps noted");
    assert!(gaps.starts_with("2 gap(s)"), "{gaps}");
    assert!(
        gaps.contains("t = 0.0090 to 0.0120 s between lines 11 and 12 (2 missing)")
            && gaps.contains("between lines 29 and 30 (1 missing)"),
        "{gaps}"
    );
    assert!(m.notes.iter().all(|n| !n.contains("not uniform")), "a gap is not jitter: {:?}", m.notes);

    // 8 samples missing: more than the default 5
    let t: Vec<f64> = (0..60).filter(|k| !(20..28).contains(k)).map(|k| k as f64 * dt).collect();
    let err = parse(linear(&t).as_bytes(), &[]).unwrap_err();
    for part in ["m.csv, line 22, column 1 ('time')", "0.019", "line 21", "about 8 samples missing", "--max-gap 5"] {
        assert!(err.contains(part), "lacks '{part}': {err}");
    }
    let m = Measurement::parse("m.csv", linear(&t).as_bytes(), &[], 8).expect("--max-gap 8");
    assert_eq!(m.len(), 60);
}

#[test]
fn max_gap_reaches_the_reader_through_compare_options() {
    let dir = std::env::temp_dir().join(format!("damper_engine_test_max_gap_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let t: Vec<f64> = (0..400).filter(|k| !(200..207).contains(k)).map(|k| k as f64 * 1e-3).collect();
    let csv = dir.join("gap7.csv");
    std::fs::write(&csv, linear(&t)).unwrap();
    let mut o = damper_engine::comparison::CompareOptions::new(&csv);
    let err = damper_engine::comparison::compare(&o).unwrap_err().to_string();
    assert!(err.contains("gap7.csv, line 202") && err.contains("--max-gap 5"), "{err}");
    o.max_gap = 7;
    let c = damper_engine::comparison::compare(&o).expect("bridged");
    assert_eq!(c.measurement.len(), 400);
    assert!(c.warnings.iter().any(|w| w.contains("1 gap(s)")), "{:?}", c.warnings);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A record of a 1.5 Hz stroke at 1 kHz whose displacement carries 5 µm of white noise, with a
/// velocity column made by `velocity(x)`; the time, x, v, F_demand and F_damper columns.
fn lvdt_record(mut velocity: impl FnMut(&[f64]) -> Vec<f64>) -> String {
    let mut rng = Rng::new(17);
    let x: Vec<f64> = (0..6000)
        .map(|k| 0.02 * libm::sin(2.0 * std::f64::consts::PI * 1.5 * k as f64 * 1e-3) + 5e-6 * rng.normal())
        .collect();
    let v = velocity(&x);
    let rows: String = x
        .iter()
        .zip(&v)
        .enumerate()
        .map(|(k, (x, v))| format!("{},{x:.7},{v:.6},1000,900\n", k as f64 * 1e-3))
        .collect();
    format!("time,x_damper,v_damper,F_demand,F_damper\n{rows}")
}

/// A logger's velocity (central differences of the LVDT under a first-order 60 Hz low-pass, run
/// forwards and backwards) holds nothing its displacement does not: the reader says so, keeps the
/// one with the smaller error and the velocity made again from the displacement beside it, with its
/// coloured noise, for the diagnosis; a velocity transducer of its own (0.1 mm/s white noise) beside
/// the same displacement is left as it is.
#[test]
fn a_velocity_made_from_the_displacement_is_made_again_from_it() {
    let logger = |x: &[f64]| {
        let d: Vec<f64> = (0..x.len()).map(|k| (x[(k + 1).min(x.len() - 1)] - x[k.saturating_sub(1)]) / 2e-3).collect();
        let a = libm::exp(-2.0 * std::f64::consts::PI * 60.0 * 1e-3);
        let mut y = d.clone();
        for k in 1..y.len() {
            y[k] = a * y[k - 1] + (1.0 - a) * d[k];
        }
        for k in (0..y.len() - 1).rev() {
            y[k] = a * y[k + 1] + (1.0 - a) * y[k];
        }
        y
    };
    let m = parse(lvdt_record(logger).as_bytes(), &[]).expect("an LVDT record");
    let noise = m.velocity_noise.as_ref().expect("the velocity is made from the displacement");
    assert!((4e-6..6e-6).contains(&noise.sigma_x), "σ_x {}", noise.sigma_x);
    assert!(m.notes.iter().any(|n| n.contains("v_damper is made from x_damper")), "{:#?}", m.notes);
    // the logger's 60 Hz filter on a 1.5 Hz stroke errs less than a velocity made again: kept, and
    // the one made again beside it for the diagnosis
    assert!(m.notes.iter().any(|n| n.contains("v_damper kept")), "{:#?}", m.notes);
    let logged = m.get(Column::VDamper).unwrap().to_vec();
    let again = m.with_velocity_made_again();
    assert!(again.velocity_noise.as_ref().is_some_and(|n| n.smoother.is_some()));
    assert_ne!(again.get(Column::VDamper).unwrap(), logged.as_slice());

    let mut rng = Rng::new(5);
    let transducer = |x: &[f64]| {
        (0..x.len())
            .map(|k| {
                0.02 * 2.0 * std::f64::consts::PI * 1.5 * libm::cos(2.0 * std::f64::consts::PI * 1.5 * k as f64 * 1e-3)
                    + 1e-4 * rng.normal()
            })
            .collect()
    };
    let m = parse(lvdt_record(transducer).as_bytes(), &[]).expect("a transducer record");
    assert!(m.velocity_noise.is_none());
    assert!(!m.notes.iter().any(|n| n.contains("made from x_damper")), "{:#?}", m.notes);
}
