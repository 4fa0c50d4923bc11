//! Mount: the nylon bushes and the frame as one cubic spring in series with the damper body
//! (the paper's Fig. 5).
//!
//! ```text
//! F = g(δ) = k1 δ + k3 δ³          δ = mount deflection (m), tension positive
//! δ = g⁻¹(F) = u (1 + ε P(ε)),  u = F/k1,  ε = k3 u²/k1,  P = −(1 + ε P)³
//! ```
//! The spring is massless, so δ is not a state: it follows from the hydraulic force.

use super::piecewise::octic;

/// The cubic share ε = k3 u²/k1 up to which [`CubicMount::deflection`] takes the root from
/// `MOUNT_DEFLECTION`: forces up to 39.5 kN with the default mount, beyond the relief valve's cap
/// of 36.7 kN.
const MOUNT_SHARE_MAX: f64 = 0.25;
/// P(ε) on 0 ≤ ε ≤ `MOUNT_SHARE_MAX`, within 9e-16 relative (see [`super::piecewise`]; tested
/// here by `the_table_reaches_rounding_up_to_its_limit`).
#[rustfmt::skip]
const MOUNT_DEFLECTION: [[f64; 9]; 16] = [
    [-0.977269672964306, 0.02204746410173455, -0.0006594550824268213, 2.2540887716601577e-05, -8.331736329497341e-07, 3.242454279928906e-08, -1.3088113164461054e-09, 5.4515427474222373e-11, -2.3134573496270884e-12],
    [-0.9356446085342023, 0.019655837725564597, -0.0005418932913124319, 1.6989829665336032e-05, -5.744821838504617e-07, 2.0418507308574874e-08, -7.51911864380987e-10, 2.8530256306128003e-11, -1.1029686362461932e-12],
    [-0.8983731706752551, 0.017675259910063558, -0.0004522715384893087, 1.3104572470207733e-05, -4.0852607291986106e-07, 1.3367051112128438e-08, -4.527003739094701e-10, 1.5776849076890735e-11, -5.658497933157805e-13],
    [-0.8647330361928232, 0.01601134475728682, -0.000382478355903483, 1.0306521948242879e-05, -2.9816528190587914e-07, 9.041501749759537e-09, -2.8353115162455905e-10, 9.14300884725109e-12, -3.0206548444172003e-13],
    [-0.8341623062930269, 0.014596240991024724, -0.0003271342838809207, 8.242114042656906e-06, -2.2250792454540273e-07, 6.288723226239022e-09, -1.8366292139882179e-10, 5.5111423719419464e-12, -1.6467170362305706e-13],
    [-0.8062157945123605, 0.013379959109084297, -0.00028255935310458495, 6.687018344621338e-06, -1.692696964421185e-07, 4.480766686723418e-09, -1.2246712644138794e-10, 3.4349399147265592e-12, -9.920291046474533e-14],
    [-0.7805351899131442, 0.01232488567616247, -0.0002461685056518302, 5.494255449410113e-06, -1.3094920990402827e-07, 3.2604462291079806e-09, -8.376894347440677e-11, 2.2092662283617922e-12, -5.508573621978981e-14],
    [-0.7568281344859172, 0.011402198027915039, -0.00021610363927350318, 4.564813803524978e-06, -1.0281374233526982e-07, 2.416838034263544e-09, -5.858079833629727e-11, 1.4549660165402102e-12, -3.7387120038270546e-14],
    [-0.7348532057299555, 0.010589453911589866, -0.00019100208397416124, 3.8303570328767526e-06, -8.179100057882427e-08, 1.821198944217793e-09, -4.177739007423621e-11, 9.80571183379727e-13, -3.015794529461159e-14],
    [-0.7144089163186855, 0.009868930637193187, -0.00016984663966245124, 3.242700834911825e-06, -6.58358600729392e-08, 1.3926638377480727e-09, -3.034554999496441e-11, 6.763267422484336e-13, -1.3318969953688417e-14],
    [-0.6953255106639296, 0.00922645561634371, -0.00015186593598143447, 2.7672186335338053e-06, -5.355631694087307e-08, 1.0791267022511122e-09, -2.2381415399477336e-11, 4.741931597162761e-13, -1.1158114956582951e-14],
    [-0.6774587491694137, 0.008650566929034655, -0.0001364667160979487, 2.378600391142244e-06, -4.39857884694302e-08, 8.462215967358697e-10, -1.674843446039912e-11, 3.3838514863871013e-13, -8.134847432970426e-15],
    [-0.6606851310965022, 0.00813190035071947, -0.00012318687923131466, 2.058060849473664e-06, -3.644099210808154e-08, 6.708255759351756e-10, -1.2703413002461985e-11, 2.4423997766220185e-13, -2.8858410722345205e-15],
    [-0.6448981757972819, 0.007662734784993207, -0.00011166232325355126, 1.7914632395470296e-06, -3.043102695446213e-08, 5.370741549379835e-10, -9.738006398882677e-12, 1.7949565840185999e-13, -6.255030302425825e-15],
    [-0.6300054941257732, 0.007236650430655357, -0.0001016031455606814, 1.5680342898470383e-06, -2.5597936436861678e-08, 4.3390782726891887e-10, -7.560828909851847e-12, 1.3540430923676774e-13, -5.84524418031841e-16],
    [-0.615926457721383, 0.006848268445377098, -9.277630525834053e-05, 1.3794690755338495e-06, -2.16772245294293e-08, 3.53500301170117e-10, -5.921174520088631e-12, 1.0185878527865814e-13, -1.5437679031937464e-15],
];

/// Cubic series spring.
#[derive(Clone, Copy, Debug)]
pub struct CubicMount {
    /// Linear stiffness (N/m).
    pub k1: f64,
    /// Cubic stiffness (N/m³).
    pub k3: f64,
    /// 1/k1 (m/N) and k3/k1 (1/m²), kept so that [`CubicMount::deflection`], which every
    /// evaluation of the plant waits for, starts without two divisions in a row.
    compliance: f64,
    cubic_share: f64,
}

impl CubicMount {
    /// The mount of linear stiffness `k1` (N/m) and cubic stiffness `k3` (N/m³).
    pub fn new(k1: f64, k3: f64) -> Self {
        CubicMount { k1, k3, compliance: 1.0 / k1, cubic_share: k3 / k1 }
    }

    /// Force (N) at deflection `delta` (m).
    pub fn force(&self, delta: f64) -> f64 {
        self.k1 * delta + self.k3 * delta * delta * delta
    }

    /// Tangent stiffness dF/dδ (N/m).
    pub fn stiffness(&self, delta: f64) -> f64 {
        self.k1 + 3.0 * self.k3 * delta * delta
    }

    /// Deflection (m) carrying `force` (N): the one real root of the cubic. The mount is solved at
    /// every evaluation of the plant, and the rest of the evaluation waits for it (force →
    /// deflection → chamber volumes), so the usual case is a table: where the cubic term is a
    /// share ε = k3 u²/k1 ≤ 0.25 of the linear spring's deflection u = F/k1, the root is
    /// u (1 + ε P(ε)) with P from `MOUNT_DEFLECTION` (within a few ulps: tested). Beyond it
    /// Halley's iteration runs to convergence from the smaller of the linear and the cubic
    /// spring's deflection alone (both bound the root from outside within a factor of 2). The
    /// table costs less than a series and a Halley step (4 % of the whole damper's time); the
    /// closed form (hyperbolic Cardano) costs several times as much.
    pub fn deflection(&self, force: f64) -> f64 {
        let (k1, k3) = (self.k1, self.k3);
        let linear = force * self.compliance;
        if k3 == 0.0 || force == 0.0 {
            return force / k1;
        }
        let e = self.cubic_share * linear * linear;
        if e <= MOUNT_SHARE_MAX {
            return linear * (1.0 + e * octic(&MOUNT_DEFLECTION, e, MOUNT_SHARE_MAX));
        }
        let mut delta = if k3 * linear * linear <= k1 { linear } else { libm::cbrt(force / k3) };
        for _ in 0..MAX_HALLEY_ITERATIONS {
            let next = self.halley(delta, force);
            let step = delta - next;
            delta = next;
            // also stops on a NaN step
            if step.abs().partial_cmp(&(4.0 * f64::EPSILON * delta.abs())) != Some(std::cmp::Ordering::Greater) {
                break;
            }
        }
        delta
    }

    /// One Halley iteration towards g(δ) = `force` from `delta`.
    #[inline(always)]
    fn halley(&self, delta: f64, force: f64) -> f64 {
        let (k1, k3) = (self.k1, self.k3);
        let g = (k1 + k3 * delta * delta) * delta - force;
        let slope = k1 + 3.0 * k3 * delta * delta;
        delta - 2.0 * g * slope / (2.0 * slope * slope - g * 6.0 * k3 * delta)
    }
}

/// Halley's iteration converges cubically from within a factor of 2: 3 iterations suffice; the
/// bound only makes the loop finite.
const MAX_HALLEY_ITERATIONS: usize = 8;

#[cfg(test)]
#[allow(
    clippy::disallowed_methods,
    reason = "a test: the platform's math is an independent reference and makes inputs"
)]
mod tests {
    use super::*;

    #[test]
    fn inverse_recovers_the_deflection() {
        let m = CubicMount::new(5e7, 2e13);
        for k in -50..=50 {
            let f = k as f64 * 1e3; // ±50 kN
            let d = m.deflection(f);
            assert!((m.force(d) - f).abs() < 1e-9 * f.abs().max(1.0), "F {f}");
        }
        // hand value: at δ = 1 mm, F = 5e7·1e-3 + 2e13·1e-9 = 50 kN + 20 kN
        assert!((m.force(1e-3) - 70e3).abs() < 1e-6);
        assert!((m.deflection(70e3) - 1e-3).abs() < 1e-15);
        let linear = CubicMount::new(5e7, 0.0);
        assert_eq!(linear.deflection(1e4), 2e-4);
        // k3 so small that k1/k3 overflows: the linear spring
        let tiny = CubicMount::new(5e7, 2.2e-308);
        assert_eq!(tiny.deflection(1e4), 2e-4);
        assert_eq!(tiny.deflection(-7e4), -7e4 / 5e7);
    }

    #[test]
    fn inverse_is_exact_over_every_stiffness_ratio() {
        // from a linear-dominated to a cubic-dominated spring, small to huge forces
        for k3_exp in [0, 5, 10, 13, 16, 20, 30] {
            let m = CubicMount::new(5e7, 10f64.powi(k3_exp));
            for f in [1e-3, 1.0, 1e3, 2e4, 5e4, 1e6, 1e9] {
                for f in [f, -f] {
                    let d = m.deflection(f);
                    assert!((m.force(d) - f).abs() <= 1e-13 * f.abs(), "k3 1e{k3_exp}, F {f}: {d}");
                }
            }
        }
    }

    #[test]
    fn the_table_reaches_rounding_up_to_its_limit() {
        // the cubic share ε from 0 to past the table's limit, where the iteration takes over, and
        // the smallest shares, where the root is the linear spring's deflection to the last bits
        let m = CubicMount::new(5e7, 2e13);
        let shares = (0..=2400).map(|k| 1.2 * MOUNT_SHARE_MAX * k as f64 / 2400.0);
        let small = (0..=100).map(|k| 10f64.powf(-16.0 + 14.0 * k as f64 / 100.0));
        for e in shares.chain(small) {
            let f = m.k1 * (e * m.k1 / m.k3).sqrt();
            for f in [f, -f] {
                let d = m.deflection(f);
                assert!((m.force(d) - f).abs() <= 4.0 * f64::EPSILON * f.abs(), "ε {e}, F {f}: {d}");
            }
        }
    }

    #[test]
    fn stiffness_is_the_slope() {
        let m = CubicMount::new(5e7, 2e13);
        let d = 0.4e-3;
        let fd = (m.force(d + 1e-9) - m.force(d - 1e-9)) / 2e-9;
        assert!((fd - m.stiffness(d)).abs() < 1e-6 * fd);
    }
}
