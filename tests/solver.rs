//! The damper's Rosenbrock integrator against problems with known answers: order of convergence,
//! of the error estimate, L-stability and A-stability, stiff Van der Pol.
#![allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]

use nalgebra::{SMatrix, SVector};
use semi_active_damper::solver::{rosenbrock_step, OdeSystem};

struct Linear(f64);
impl OdeSystem<1> for Linear {
    fn rhs(&self, y: &SVector<f64, 1>) -> SVector<f64, 1> {
        y * self.0
    }
}

/// y1' = y2, y2' = −y1 − 0.1 y2 (damped oscillator) plus a cubic term: smooth and nonlinear. Its
/// Jacobian is exact: forward differences at y2 = 0 take an increment of 1.5e-14 and err by 1 %,
/// which a Rosenbrock method's order rests on (the error estimate would fall as h², not h³).
struct Nonlinear;
impl OdeSystem<2> for Nonlinear {
    fn rhs(&self, y: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::from([y[1], -y[0] - 0.1 * y[1] - 0.5 * y[0] * y[0] * y[0]])
    }
    fn jacobian(&self, y: &SVector<f64, 2>, _f0: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -1.0 - 1.5 * y[0] * y[0], -0.1)
    }
}

fn integrate<const N: usize, S: OdeSystem<N>>(sys: &S, y0: SVector<f64, N>, t: f64, n: usize) -> SVector<f64, N> {
    let mut y = y0;
    for _ in 0..n {
        y = rosenbrock_step(sys, &y, t / n as f64).unwrap().0;
    }
    y
}

#[test]
fn third_order_convergence() {
    // Error ratio for halved steps → 2³ = 8 for a third-order method.
    let exact = (-1.0f64).exp();
    let err = |n| (integrate(&Linear(-1.0), SVector::from([1.0]), 1.0, n)[0] - exact).abs();
    let (e1, e2, e3) = (err(10), err(20), err(40));
    for ratio in [e1 / e2, e2 / e3] {
        assert!((7.0..9.5).contains(&ratio), "linear: error ratio {ratio}");
    }
    let reference = integrate(&Nonlinear, SVector::from([1.0, 0.0]), 2.0, 20_000);
    let err = |n| (integrate(&Nonlinear, SVector::from([1.0, 0.0]), 2.0, n) - reference).norm();
    let ratio = err(20) / err(40);
    assert!((7.0..9.5).contains(&ratio), "nonlinear: error ratio {ratio}");
}

#[test]
fn l_stable_stiff_decay_is_damped_in_one_step() {
    // y' = −1e8 y with h = 1e-4 (λh = −1e4): an L-stable method gives |y1| ≪ |y0|; the
    // trapezoidal rule would return ≈ −y0.
    let y1 = rosenbrock_step(&Linear(-1e8), &SVector::from([1.0]), 1e-4).unwrap().0[0];
    assert!(y1.abs() < 1e-3, "y1 = {y1}");
}

#[test]
fn the_error_estimate_is_the_local_error_of_an_order_2_solution() {
    // one step from the same state: the estimate falls as h³ (8× for half the step), and it is of
    // the size of the step's own local error or larger
    let y0 = SVector::from([1.0, 0.0]);
    let estimate = |h: f64| rosenbrock_step(&Nonlinear, &y0, h).unwrap().1.norm();
    for h in [0.04, 0.01, 0.0025] {
        let ratio = estimate(h) / estimate(h / 2.0);
        assert!((7.5..8.5).contains(&ratio), "h {h}: estimate ratio {ratio}");
        let exact = integrate(&Nonlinear, y0, h, 2_000);
        let local_error = (rosenbrock_step(&Nonlinear, &y0, h).unwrap().0 - exact).norm();
        assert!(estimate(h) > local_error, "h {h}: estimate {:e}, local error {local_error:e}", estimate(h));
    }
}

/// y' = ω J y, J the rotation generator: a purely imaginary eigenvalue pair ±iω.
struct Rotation(f64);
impl OdeSystem<2> for Rotation {
    fn rhs(&self, y: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::from([-self.0 * y[1], self.0 * y[0]])
    }
}

#[test]
fn a_stable_on_the_imaginary_axis_and_damped_on_the_negative_axis() {
    // |R(iωh)| ≤ 1: an undamped oscillation never grows, whatever ωh
    for k in 0..=60 {
        let omega_h = 10f64.powf(-2.0 + 8.0 * k as f64 / 60.0);
        let y1 = rosenbrock_step(&Rotation(omega_h), &SVector::from([1.0, 0.0]), 1.0).unwrap().0;
        assert!(y1.norm() <= 1.0 + 1e-12, "ωh {omega_h}: |R| = {}", y1.norm());
    }
    // 0 < R(z) < 1 for real z < 0 up to z = −2 (the decay's sign kept), |R(z)| < 1 beyond
    for k in 1..=60 {
        let z = -(10f64.powf(-3.0 + 9.0 * k as f64 / 60.0));
        let r = rosenbrock_step(&Linear(z), &SVector::from([1.0]), 1.0).unwrap().0[0];
        assert!(r.abs() < 1.0 && (z < -2.0 || r > 0.0), "z {z}: R = {r}");
    }
}

struct VanDerPol;
impl OdeSystem<2> for VanDerPol {
    fn rhs(&self, y: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::from([y[1], ((1.0 - y[0] * y[0]) * y[1] - y[0]) / 1e-6])
    }
    fn jacobian(&self, y: &SVector<f64, 2>, _f0: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, (-2.0 * y[0] * y[1] - 1.0) / 1e-6, (1.0 - y[0] * y[0]) / 1e-6)
    }
}

#[test]
fn stiff_van_der_pol_matches_radau5() {
    // Hairer's stiff Van der Pol, ε = 1e-6, y(0) = (2, −0.6), t = 2; reference y(2) from radau5.f
    // (as quoted by russell_ode's tests): (1.706163410178079, −0.8927971289301175).
    // Step-size control with the embedded error estimate (rtol = atol = 1e-7).
    let (mut t, mut h, mut y): (f64, f64, SVector<f64, 2>) = (0.0, 1e-6, SVector::from([2.0, -0.6]));
    let mut steps = 0;
    while t < 2.0 {
        h = h.min(2.0 - t);
        let (y1, e) = rosenbrock_step(&VanDerPol, &y, h).unwrap();
        let err = e.iter().zip(y1.iter()).map(|(e, y)| (e / (1e-7 + 1e-7 * y.abs())).powi(2)).sum::<f64>().sqrt()
            / 2f64.sqrt();
        if err <= 1.0 {
            t += h;
            y = y1;
            steps += 1;
        }
        h *= (0.9 * err.max(1e-10).powf(-1.0 / 3.0)).clamp(0.2, 5.0);
    }
    assert!(
        (y[0] - 1.706163410178079).abs() < 1e-4 && (y[1] + 0.8927971289301175).abs() < 1e-4,
        "y(2) = {y:?} after {steps} steps"
    );
}
