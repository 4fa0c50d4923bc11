//! scratch (not committed): prints t, v, demand, measured and predicted force
use damper_engine::comparison::{compare, CompareOptions};
use damper_engine::units::Column;
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let mut o = CompareOptions::new(&a[1]);
    o.load_cell_lowpass_hz = Some(400.0);
    o.tare_load_cell = a.get(2).is_some_and(|s| s == "tare");
    o.rtol_at_most = Some(1e-4);
    let c = compare(&o).unwrap();
    let m = &c.measurement;
    let (t, v, y) = (&m.time, m.get(Column::VDamper).unwrap(), m.get(Column::FDamper).unwrap());
    let fd = m.get(Column::FDemand).unwrap();
    println!("t,v,fd,measured,model");
    for k in 0..t.len() {
        println!("{},{},{},{},{}", t[k], v[k], fd[k], y[k], c.prediction.f_damper[k]);
    }
}
