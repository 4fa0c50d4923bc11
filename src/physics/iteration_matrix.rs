//! The plant's Rosenbrock iteration matrix M = I/(γh) − J, solved through the structure of its
//! Jacobian. Three of the seven equations have a fixed form whatever the state and the effects:
//!
//! ```text
//! ẋ_s = v_s            row x_s of J: 1 in column v_s, else 0
//! i̇   = (i_cmd − i)/τ  row i of J:   −1/τ on the diagonal, else 0
//! ẋ   = v              row x of J:   0
//! ```
//! so, with c = 1/(γh), M k = b gives k_i = b_i/(c + 1/τ), k_x = b_x/c and k_xs = (b_xs + k_vs)/c
//! directly; substituted into the other four rows (p_A, p_B, V_g, v_s) they leave a 4×4 system.
//! Its LU cost a fifth of the 7×7 one (4³ against 7³ operations) and each stage's solve a third,
//! which was a quarter of the damper's instructions (`cargo bench --bench realtime`,
//! docs/performance.md); the stages now multiply by its inverse, from its adjugate (see
//! `kept_inverse`).

use super::plant::{idx, N_STATES};
use crate::solver::{inverse_4x4, IterationMatrix};
use nalgebra::{SMatrix, SVector};

/// The rows (and columns) left after the elimination.
const KEPT: [usize; 4] = [idx::P_A, idx::P_B, idx::V_GAS, idx::V_SPOOL];

/// M factorised through its structure.
#[derive(Clone, Copy, Debug)]
pub struct PlantIterationMatrix {
    /// The inverse of the 4×4 system on the kept states, row by row: each of a step's four solves
    /// is then a product whose rows are independent sums of four terms, where an LU's
    /// substitutions are a chain of eight dependent operations (6 % of the damper's time). From
    /// the adjugate ([`inverse_4x4`]), not from a pivoted LU: no branch and no row swap, and
    /// indifferent to the rows' units (11 % of its time).
    kept_inverse: [[f64; 4]; 4],
    /// γh (s).
    gamma_h: f64,
    /// 1/(c − J_ii): k_i = b_i · this.
    coil: f64,
    /// Per kept row r: M[r][x_s]/c, M[r][i] and M[r][x], the coefficients of the eliminated
    /// unknowns on the right-hand side.
    spool_position: [f64; 4],
    coil_current: [f64; 4],
    stroke: [f64; 4],
}

/// Whether the rows of x_s, i and x of `jacobian` have the form the elimination assumes.
pub fn has_plant_structure(jacobian: &SMatrix<f64, N_STATES, N_STATES>) -> bool {
    use idx::*;
    (0..N_STATES).all(|c| {
        jacobian[(X_SPOOL, c)] == if c == V_SPOOL { 1.0 } else { 0.0 }
            && (c == I_COIL || jacobian[(I_COIL, c)] == 0.0)
            && jacobian[(X_DAMPER, c)] == 0.0
    })
}

impl IterationMatrix<N_STATES> for PlantIterationMatrix {
    #[inline]
    fn factor(jacobian: &SMatrix<f64, N_STATES, N_STATES>, c: f64) -> Option<Self> {
        use idx::*;
        debug_assert!(has_plant_structure(jacobian), "the plant's Jacobian lost its structure:\n{jacobian}");
        let gamma_h = 1.0 / c;
        let coil = 1.0 / (c - jacobian[(I_COIL, I_COIL)]);
        if !(coil.is_finite() && gamma_h.is_finite()) {
            return None;
        }
        // M = cI − J on the kept rows; k_xs = (b_xs + k_vs)/c moves x_s's column onto v_s's
        let spool_position: [f64; 4] = std::array::from_fn(|r| -jacobian[(KEPT[r], X_SPOOL)] * gamma_h);
        let rows: [[f64; 4]; 4] = std::array::from_fn(|r| {
            std::array::from_fn(|k| {
                let m = -jacobian[(KEPT[r], KEPT[k])] + if r == k { c } else { 0.0 };
                if k == 3 {
                    m + spool_position[r]
                } else {
                    m
                }
            })
        });
        Some(PlantIterationMatrix {
            kept_inverse: inverse_4x4(&rows)?,
            gamma_h,
            coil,
            spool_position,
            coil_current: std::array::from_fn(|r| -jacobian[(KEPT[r], I_COIL)]),
            stroke: std::array::from_fn(|r| -jacobian[(KEPT[r], X_DAMPER)]),
        })
    }

    // Always inlined: a step solves four times, and as a call (LLVM's choice) the damper took
    // 13 % longer in wall-clock time for 3.5 % more instructions; the stalls are likely the
    // vectors passed and returned through memory.
    #[inline(always)]
    fn solve(&self, b: &SVector<f64, N_STATES>) -> SVector<f64, N_STATES> {
        use idx::*;
        let k_coil = b[I_COIL] * self.coil;
        let k_stroke = b[X_DAMPER] * self.gamma_h;
        let rhs: [f64; 4] = std::array::from_fn(|r| {
            b[KEPT[r]] - self.spool_position[r] * b[X_SPOOL] - self.coil_current[r] * k_coil - self.stroke[r] * k_stroke
        });
        let kept: [f64; 4] = std::array::from_fn(|i| {
            let row = &self.kept_inverse[i];
            (row[0] * rhs[0] + row[1] * rhs[1]) + (row[2] * rhs[2] + row[3] * rhs[3])
        });
        let mut k = SVector::<f64, N_STATES>::zeros();
        for r in 0..4 {
            k[KEPT[r]] = kept[r];
        }
        k[I_COIL] = k_coil;
        k[X_DAMPER] = k_stroke;
        k[X_SPOOL] = (b[X_SPOOL] + kept[3]) * self.gamma_h;
        k
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::params::Parameters;
    use crate::physics::plant::{every_effect_on, random_state, Plant};
    use crate::solver::Lu;

    /// Against the dense LU of the whole matrix, at states across the regimes, for the step sizes
    /// the damper takes.
    #[test]
    fn solves_as_the_dense_matrix_does() {
        let p = Parameters { effect_seal_friction: true, effect_piston_leakage: true, ..Default::default() };
        let d = p.derive();
        let rest =
            Plant { p: &p, d: &d, v_damper: 0.0, i_command: 1.2, t_oil: 293.15, a_damper: 0.0 }.rest_state(0.01, 1e-3);
        for (case, (p_a, p_b, x_s, v)) in
            [(5e5, 5e5, 1e-3, 0.0), (60e5, 8e5, 2.5e-3, 0.4), (3e5, 40e5, 0.2e-3, -0.6), (120e5, 5.2e5, 4.6e-3, 1.0)]
                .into_iter()
                .enumerate()
        {
            let mut y = rest;
            y[idx::P_A] = p_a;
            y[idx::P_B] = p_b;
            y[idx::X_SPOOL] = x_s;
            y[idx::V_SPOOL] = 0.05;
            let (_, lin) = Plant { p: &p, d: &d, v_damper: v, i_command: 1.2, t_oil: 293.15, a_damper: 0.0 }
                .evaluate_linearised(&y);
            assert!(has_plant_structure(&lin.jacobian));
            for h in [1e-7, 1e-5, 5e-4] {
                let c = 1.0 / (0.5 * h);
                let structured = PlantIterationMatrix::factor(&lin.jacobian, c).unwrap();
                let dense = <Lu<N_STATES> as IterationMatrix<N_STATES>>::factor(&lin.jacobian, c).unwrap();
                let b = SVector::<f64, N_STATES>::from([3e9, -2e9, 0.4, 1e-2, -7.0, 300.0, 0.3]);
                let (x, reference) = (structured.solve(&b), dense.solve(&b));
                let matrix = SMatrix::<f64, N_STATES, N_STATES>::identity() * c - lin.jacobian;
                for i in 0..N_STATES {
                    // relative to the size of the terms each row sums
                    let scale = (0..N_STATES).map(|j| (matrix[(i, j)] * x[j]).abs()).fold(b[i].abs(), f64::max);
                    let residual = (matrix * x - b)[i];
                    assert!(residual.abs() <= 1e-12 * scale, "case {case}, h {h}, row {i}: residual {residual:e}");
                    assert!((x[i] - reference[i]).abs() <= 1e-9 * x[i].abs().max(reference[i].abs()).max(1e-300));
                }
            }
        }
    }

    /// The residual of a solve, row by row, at rounding level of the largest term the row sums:
    /// over random states across the regimes (check valves, relief valve, spool stops, every
    /// effect on and off) and step sizes from 1 ns to 0.1 s. Measured worst: 3.1e-13 (the pivoted
    /// 4×4 LU it replaced: 1.8e-11; the dense 7×7 LU: 3.9e-10).
    #[test]
    fn solves_to_rounding_level_across_regimes_and_step_sizes() {
        let mut uniform = crate::test_rng::uniform(0x2545_f491_4f6c_dd1d);
        let mut worst = 0.0f64;
        for all_on in [false, true] {
            let mut p = Parameters::default();
            if all_on {
                every_effect_on(&mut p);
            }
            let d = p.derive();
            let t_oil = if all_on { 335.0 } else { 293.15 };
            let rest =
                Plant { p: &p, d: &d, v_damper: 0.0, i_command: 0.7, t_oil, a_damper: 0.0 }.rest_state(0.0, 1e-3);
            for _ in 0..1000 {
                let y = random_state(&rest, &mut uniform, false);
                let plant =
                    Plant { p: &p, d: &d, v_damper: 1.5 * (uniform() - 0.5), i_command: 0.7, t_oil, a_damper: 0.0 };
                let jacobian = plant.evaluate_linearised(&y).1.jacobian;
                for h in [1e-9, 1e-7, 1e-5, 1e-4, 5e-4, 2e-3, 1e-2, 1e-1] {
                    let c = 3.0 / h;
                    let matrix = SMatrix::<f64, N_STATES, N_STATES>::identity() * c - jacobian;
                    let b = SVector::<f64, N_STATES>::from_fn(|i, _| {
                        (uniform() - 0.5) * [3e9, 3e9, 0.4, 1e-2, 7.0, 300.0, 0.3][i]
                    });
                    let x = PlantIterationMatrix::factor(&jacobian, c).unwrap().solve(&b);
                    let residual = matrix * x - b;
                    for i in 0..N_STATES {
                        let scale = (0..N_STATES).map(|j| (matrix[(i, j)] * x[j]).abs()).fold(b[i].abs(), f64::max);
                        worst = worst.max(residual[i].abs() / scale);
                    }
                }
            }
        }
        assert!(worst <= 1e-12, "worst residual {worst:e} of the row's largest term");
    }

    #[test]
    fn notices_a_jacobian_without_the_structure() {
        let mut j = SMatrix::<f64, N_STATES, N_STATES>::zeros();
        j[(idx::X_SPOOL, idx::V_SPOOL)] = 1.0;
        j[(idx::I_COIL, idx::I_COIL)] = -3e3;
        assert!(has_plant_structure(&j));
        j[(idx::I_COIL, idx::P_A)] = 1e-9;
        assert!(!has_plant_structure(&j));
    }
}
