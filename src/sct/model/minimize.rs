//! Minimisation of a supervisor (5.4.4, Hopcroft's algorithm).

use super::{EventId, SupState, Supervisor};

/// Minimisation (5.4.4): states are equivalent if they prohibit and enforce the same events and
/// their transitions lead to equivalent states, where a missing transition means "stay". The
/// supervisor is read as a complete automaton over the events it mentions (prohibited events
/// lead to a sink) and refined with Hopcroft's algorithm.
pub fn minimize_supervisor(sup: &Supervisor) -> Supervisor {
    let Some(init) = sup.init else { return sup.clone() };
    let n = sup.states.len();
    let mut events: Vec<EventId> = sup
        .states
        .iter()
        .flat_map(|s| s.transitions.iter().map(|t| t.0).chain(s.prohibited.iter().copied()).chain(s.enforced))
        .collect();
    crate::sort::sort(&mut events);
    events.dedup();
    let k = events.len();
    let sink = n as u32;
    let mut delta = vec![0u32; (n + 1) * k];
    for (s, st) in sup.states.iter().enumerate() {
        for (a, e) in events.iter().enumerate() {
            delta[s * k + a] = if st.prohibits(*e) { sink } else { st.next(*e).unwrap_or(s as u32) };
        }
    }
    for a in 0..k {
        delta[n * k + a] = sink;
    }
    let mut keys: hashbrown::HashMap<(Vec<EventId>, Option<EventId>), u64> = hashbrown::HashMap::new();
    let mut key: Vec<u64> = sup
        .states
        .iter()
        .map(|s| {
            let mut p = s.prohibited.clone();
            crate::sort::sort(&mut p);
            let next = keys.len() as u64;
            *keys.entry((p, s.enforced)).or_insert(next)
        })
        .collect();
    key.push(u64::MAX);
    let class = crate::sct::partition::coarsest_partition(n + 1, k, &delta, &key);
    let count = class.iter().copied().max().map_or(0, |c| c as usize + 1);
    // Build the quotient from the initial state.
    // Per class, its state in the quotient once reached; `reps` holds a state of each.
    let mut renum = vec![None; count];
    let mut reps: Vec<usize> = vec![init as usize];
    renum[class[init as usize] as usize] = Some(0);
    let mut states = Vec::new();
    let mut k = 0;
    while k < reps.len() {
        let s = reps[k];
        let st = &sup.states[s];
        let mut transitions = Vec::new();
        for &(e, t) in &st.transitions {
            let c = class[t as usize] as usize;
            if class[t as usize] == class[s] {
                continue;
            }
            let target = *renum[c].get_or_insert_with(|| {
                reps.push(t as usize);
                reps.len() as u32 - 1
            });
            transitions.push((e, target));
        }
        states.push(SupState { transitions, ..st.clone() });
        k += 1;
    }
    Supervisor { name: sup.name.clone(), init: Some(0), states, plants_used: sup.plants_used.clone() }
}
