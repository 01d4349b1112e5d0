//! Random timed-game specifications (a few hardware units and automata, an assertion, a plan
//! of one or two goals, perhaps with a deadline), shared by `tests/random_specs.rs` and the
//! real-time checks of `tests/plc_realtime.rs`.

use plcsynth::timed::program::simulate;

struct Gen(simulate::Rng);

impl Gen {
    fn below(&mut self, n: u64) -> u64 {
        self.0.below(n)
    }
    fn pick<'a>(&mut self, items: &'a [String]) -> &'a String {
        &items[self.below(items.len() as u64) as usize]
    }
}

/// A random specification, the same for the same seed.
pub fn spec(seed: u64) -> String {
    let mut g = Gen(simulate::Rng::new(seed));
    let mut out = String::from("plant {\n");
    let mut states: Vec<(String, Vec<String>)> = Vec::new();
    let mut messages: Vec<String> = Vec::new();
    let units = 1 + g.below(3);
    for u in 0..units {
        if g.below(2) == 0 {
            let names: Vec<String> = (0..2 + g.below(2)).map(|k| format!("h{u}s{k}")).collect();
            out.push_str(&format!("  hardware h{u} {{\n    states {};\n", names.join(", ")));
            for k in 1..names.len() {
                let lo = g.below(3);
                let hi = lo + g.below(3);
                out.push_str(&format!("    {} <-> {} takes [{lo},{hi}];\n", names[k - 1], names[k]));
                messages.push(format!("reached_{}", names[k]));
                messages.push(format!("reached_{}", names[k - 1]));
            }
            out.push_str("  }\n");
            let mut nodes = names.clone();
            for k in 1..names.len() {
                nodes.push(format!("moving_{}_{}", names[k - 1], names[k]));
                nodes.push(format!("moving_{}_{}", names[k], names[k - 1]));
            }
            states.push((format!("h{u}"), nodes));
        } else {
            let n = 2 + g.below(3);
            let nodes: Vec<String> = (0..n).map(|k| format!("q{k}")).collect();
            let clocked = g.below(2) == 0;
            out.push_str(&format!("  automaton a{u} {{\n"));
            if clocked {
                out.push_str("    clocks c;\n");
            }
            let decl: Vec<String> = nodes
                .iter()
                .map(|q| {
                    if clocked && g.below(3) == 0 {
                        format!("{q} {{c in [0,{}]}}", 2 + g.below(3))
                    } else {
                        q.clone()
                    }
                })
                .collect();
            out.push_str(&format!("    nodes {};\n", decl.join(", ")));
            for k in 0..n + g.below(3) {
                let from = &nodes[(k % n) as usize];
                let to = &nodes[g.below(n) as usize];
                let sigil = if g.below(2) == 0 { "?" } else { "!" };
                let msg = format!("a{u}m{k}");
                let mut line = format!("    {from} -> {to} {sigil}{msg}");
                if clocked && g.below(2) == 0 {
                    line.push_str(&format!(" {{c in [{},inf)}}", 1 + g.below(2)));
                }
                if clocked && g.below(2) == 0 {
                    line.push_str(" reset{c}");
                }
                line.push_str(";\n");
                out.push_str(&line);
                messages.push(msg);
            }
            out.push_str("  }\n");
            states.push((format!("a{u}"), nodes));
        }
    }
    out.push_str("}\n");
    if states.len() > 1 && g.below(2) == 0 {
        let (u1, n1) = &states[0];
        let (u2, n2) = &states[1];
        out.push_str(&format!("assertions {{\n  never {u1}.{} and {u2}.{};\n}}\n", g.pick(n1), g.pick(n2)));
    }
    messages.sort();
    messages.dedup();
    let goal1 = g.pick(&messages).clone();
    let goal2 = g.pick(&messages).clone();
    out.push_str("plans {\n  plan {\n");
    if g.below(2) == 0 {
        out.push_str(&format!("    clocks t {};\n    reset t;\n", 4 + g.below(10)));
    }
    if goal1 == goal2 {
        out.push_str(&format!("    waitfor {goal1};\n"));
    } else {
        out.push_str(&format!("    waitfor {goal1};\n    waitfor {goal2};\n"));
    }
    out.push_str("  }\n}\n");
    out
}
