//! The suspension laws that `QuarterTruck.fmu` and `FullTruck.fmu` share, in plain safe Rust
//! without FMI types (docs/physics.md §3.7, §4.5):
//!
//! - [`laws`]: the clipped demand law (the paper's Modified Skyhook with an optional groundhook
//!   term and floor) and the passive damper (linear, or asymmetric with a knee);
//! - [`tracking`]: the idealised tracking damper (a delay and a lag per direction) and the demand's
//!   past it needs;
//! - [`integration`]: classical RK4 in equal substeps and its stability bound;
//! - [`road`]: the ISO 8608 random road of `python/damper_tools/roads.py` (numpy's random numbers,
//!   the profile, the road under the wheel in time), for a truck that makes its own road;
//! - [`fft`]: the road's FFT, of any length (radix-2, Bluestein's otherwise), its cosines and sines
//!   from libm, so that the Linux and Windows builds make the same road.
//!
//! ```
//! use suspension::laws::{DemandLaw, PassiveDamper};
//! // the paper's law: C_m 24 kN·s/m, α 0.8, clipped to zero force where it would push
//! let msd = DemandLaw { cm: 24e3, alpha: 0.8, c_ground: 0.0, c_min: 0.0 };
//! assert!((msd.demand(0.1, 0.0, -0.1) - 1920.0).abs() < 1e-9);
//! assert_eq!(msd.demand(-0.01, 0.5, 0.51), 0.0);
//! let passive = PassiveDamper::linear(20e3);
//! assert_eq!(passive.force(-0.05), -1000.0);
//! ```
pub mod error;
pub mod fft;
pub mod integration;
pub mod laws;
pub mod road;
pub mod tracking;
