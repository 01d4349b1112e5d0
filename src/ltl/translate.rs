//! LTL to Büchi automata (placeholder: being written).

use super::spec::Ltl;

pub struct Automaton;

pub fn translate(_f: &Ltl) -> Automaton {
    Automaton
}
