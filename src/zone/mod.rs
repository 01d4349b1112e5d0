//! Clock zones as difference bound matrices (DBMs).
//!
//! A zone is a conjunction of constraints `x_i - x_j ≺ c` over real-valued
//! clocks, with `≺ ∈ {<, ≤}` and integer `c`; index 0 is a reference clock
//! that is always 0, so single-clock bounds are differences with `x_0`.
//! [`Dbm`] keeps the matrix in canonical (shortest-path closed) form, which
//! makes emptiness, inclusion and equality cheap entry-wise tests.
//!
//! This module knows nothing of automata, the specification language or I/O.

mod bound;
mod dbm;
mod display;
#[cfg(test)]
mod tests;

pub use bound::Bound;
pub use dbm::{includes_lowered, includes_only_lowered, Dbm};
pub use display::{Constraint, DisplayZone};
