use semi_active_damper::damper::{Damper, Inputs};
use semi_active_damper::variables::default_parameters;
fn rise(t:&[f64], f:&[f64], t0:f64, t1:f64, a:f64, b:f64) -> (f64,f64,f64,f64) {
    let mut r=[f64::NAN;3]; let mut mx=f64::MIN;
    for (k,&tt) in t.iter().enumerate() { if tt < t0 || tt>=t1 {continue;} let fr=(f[k]-a)/(b-a); mx=mx.max(fr);
        for (j,q) in [0.1,0.5,0.9].iter().enumerate() { if r[j].is_nan() && fr>=*q { r[j]=tt-t0; } } }
    (r[0]*1e3,r[1]*1e3,r[2]*1e3,100.0*(mx-1.0).max(0.0))
}
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let hmax: f64 = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(2.5e-4);
    for dir in [1.0f64, -1.0] {
        let mut p = default_parameters(); p.h_max = hmax; p.x_damper_start = -dir*0.045;
        let mut d = Damper::new(p, Inputs{v_damper:0.15*dir, force_demand:0.0, x_spool_demand:0.0}, 0.0).unwrap();
        let (t1,t2)=(0.30,0.45); let h=1e-3/2.0;
        let mut ts=vec![]; let mut fs=vec![];
        let t0 = std::time::Instant::now();
        for k in 0..1200 { let t=k as f64*h; d.inputs.force_demand = dir*if t< t1-1e-9 {2e3} else if t<t2-1e-9 {12e3} else {22e3};
            d.do_step(h).unwrap(); let o=d.outputs(); ts.push(t+h); fs.push(dir*o.plant.force);
            if k%100==99 {eprintln!("t={:.3} F={:.0} xs={:.3}mm pA={:.1}bar pB={:.1}bar i={:.3}", t+h, o.plant.force, o.y[3]*1e3, o.y[0]/1e5, o.y[1]/1e5, o.y[5]);} }
        let el = t0.elapsed().as_secs_f64();
        println!("dir {dir}: 2->12 {:?}  12->22 {:?}  ({:.1} us per sim ms)", rise(&ts,&fs,t1,t2,2e3,12e3), rise(&ts,&fs,t2,1.0,12e3,22e3), el/0.6*1e3);
    }
}
