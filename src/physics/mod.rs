//! Physics of the damper, in plain safe Rust with SI units: one file per component.
pub mod fixed_power;
pub mod fluid;
pub mod hydraulics;
pub mod iteration_matrix;
pub mod mount;
pub mod params;
pub mod passive_valve;
pub mod piecewise;
pub mod plant;
pub mod valve;
