//! Bounded synthesis games (placeholder: being written).

use super::{Config, Outcome, Progress, Spec, Stop};

pub fn synthesize(_spec: &Spec, _cfg: &Config, _progress: &mut dyn FnMut(Progress) -> bool) -> Result<Outcome, Stop> {
    Err(Stop::Cancelled)
}
