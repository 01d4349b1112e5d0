//! A checked specification written back in the input syntax G4LTL itself reads
//! (`plcsynth ltl FILE --to-g4ltl`), so that TLSF families and our own files can be decided by
//! G4LTL beside us (`bench ltl --compare-g4ltl`).
//!
//! G4LTL hands each formula line to JPF's LTL2Buchi parser, which is narrower than our
//! G4LTL front end: it knows `[] <> X U V W ! && || ->` and `true`/`false`, but no `<->`, `G`,
//! `F` or `R`, and it reads an upper-case `U`, `V`, `W` or `X` as an operator wherever it stands,
//! even inside a name (`aXb` fails, `TRUE` is `TR U E`). Its file reader takes `##` comments only,
//! one formula per line. So the text uses only those operators, every operand that is not an atom
//! or a unary application is parenthesised, and `<->`/`R` are rewritten into what they mean.
//!
//! What G4LTL cannot express is refused with a located error: numeric inputs (its numerical
//! synthesis is not read from files) and names its parser would split or misread. Moore
//! semantics, which G4LTL lacks, is mapped: a Moore specification φ is realizable exactly when
//! the Mealy one with every input `i` replaced by `X i` is (the controller's output at step t
//! then answers only the inputs up to step t, which the shifted formula reads at steps up to
//! t − 1 of the original play).

use super::refine::timer_liveness;
use super::spec::Notation;
use super::{Ltl, Semantics, SignalId, SignalKind, Spec};
use crate::diag::{Diagnostic, Diagnostics};

/// The specification in G4LTL's syntax, or why it has none. `source` is the text `spec` was
/// checked from (errors are located in it).
pub fn to_g4ltl(source: &str, spec: &Spec) -> Result<String, Vec<Diagnostic>> {
    let mut diags = Diagnostics::new(source);
    for input in &spec.numeric {
        diags
            .error(
                input.span,
                format!("G4LTL reads Boolean signals only: the numeric input `{}` has no G4LTL form", input.name),
            )
            .with_note("G4LTL's numerical synthesis takes its predicates in the GUI, not from a file");
    }
    // Timer signals are written as G4LTL writes them (`t.start`); G4LTL renames them `t_start`.
    let is_timer_signal = |s: SignalId| spec.timers.iter().any(|t| t.start == s || t.expire == s);
    for (i, signal) in spec.signals.iter().enumerate() {
        let id = SignalId(i as u32);
        if spec.predicate_of(id).is_some() || is_timer_signal(id) {
            continue;
        }
        if let Err(why) = g4ltl_name(&signal.name) {
            diags.error(signal.span, format!("G4LTL cannot read the signal name `{}`: {why}", signal.name));
        }
    }
    for timer in &spec.timers {
        if let Err(why) = g4ltl_name(&timer.name) {
            diags.error(timer.span, format!("G4LTL cannot read the timer name `{}`: {why}", timer.name));
        }
        // G4LTL turns every `.` into `_`: `t.start` must not meet a signal `t_start`.
        for field in ["start", "expire"] {
            let renamed = format!("{}_{field}", timer.name);
            if let Some(other) = spec.signal_id(&renamed) {
                diags
                    .error(
                        spec.signal(other).span,
                        format!("`{renamed}` clashes with G4LTL's name for `{}.{field}`", timer.name),
                    )
                    .with_note("G4LTL replaces every `.` of a specification with timers by `_`");
            }
        }
    }
    if diags.has_errors() {
        return Err(diags.items);
    }
    let moore = spec.semantics == Semantics::Moore;
    let name = |s: SignalId| spec.name(s).to_string();
    let text = |f: &Ltl| {
        let f = if moore { delay_inputs(f, spec) } else { f.clone() };
        f.written(&JPF, &name)
    };
    let mut out = String::new();
    if let Some(title) = &spec.title {
        out.push_str(&format!("## {}\n", title.replace(['\n', '\r'], " ")));
    }
    if moore {
        out.push_str("## Moore semantics as Mealy: every input is read one step later (X input)\n");
    }
    // Our front end adds each timer's liveness; G4LTL adds its own antecedent for a `TIMER` line.
    let liveness: Vec<Ltl> = spec.timers.iter().map(timer_liveness).collect();
    for clause in spec.assumptions.iter().filter(|c| !liveness.contains(&c.formula)) {
        out.push_str(&format!("ASSUME {}\n", text(&clause.formula)));
    }
    for clause in &spec.guarantees {
        out.push_str(&format!("{}\n", text(&clause.formula)));
    }
    if spec.guarantees.is_empty() {
        // G4LTL builds `A -> (G1 && …)` from the lines; with none it would parse `A -> ()`.
        out.push_str("true\n");
    }
    out.push('\n');
    let declared = |kind: SignalKind| -> Vec<String> {
        let ids = if kind == SignalKind::Input { spec.inputs() } else { spec.outputs() };
        ids.into_iter().filter(|&s| !is_timer_signal(s)).map(name).collect()
    };
    for (keyword, kind) in [("INPUT", SignalKind::Input), ("OUTPUT", SignalKind::Output)] {
        let names = declared(kind);
        if !names.is_empty() {
            out.push_str(&format!("{keyword} {}\n", names.join(", ")));
        }
    }
    for timer in &spec.timers {
        out.push_str(&format!("TIMER {}({})\n", timer.name, duration(timer.preset_ms)));
    }
    Ok(out)
}

/// Whether JPF's parser and G4LTL's line reader take `name` as one signal; if not, why.
fn g4ltl_name(name: &str) -> Result<(), &'static str> {
    let mut chars = name.chars();
    let first_ok = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if !first_ok || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err("a name is a letter or `_` followed by letters, digits and `_`");
    }
    if name.contains(['U', 'V', 'W', 'X']) {
        return Err("its parser reads an upper-case U, V, W or X as an operator, even inside a name");
    }
    if ["true", "false"].contains(&name) {
        return Err("it is a constant");
    }
    // G4LTL tells declarations from formulas by how a line starts (`TIMER`; INPUT, OUTPUT and
    // ASSUME have a U), and our reader keeps these words; both would misread the name.
    if name.starts_with("TIMER") || ["G", "F", "R", "THEN", "FOR", "REAL", "INT"].contains(&name) {
        return Err("G4LTL or our reader of its files takes it for a keyword");
    }
    Ok(())
}

/// A preset as the shortest G4LTL duration that names it exactly.
fn duration(ms: u64) -> String {
    match ms {
        0 => "0ms".to_string(),
        _ if ms % 3_600_000 == 0 => format!("{}h", ms / 3_600_000),
        _ if ms % 60_000 == 0 => format!("{}min", ms / 60_000),
        _ if ms % 1000 == 0 => format!("{}s", ms / 1000),
        _ => format!("{ms}ms"),
    }
}

/// `f` with every input `i` replaced by `X i` (Moore to Mealy, see the module's comment).
fn delay_inputs(f: &Ltl, spec: &Spec) -> Ltl {
    let d = |g: &Ltl| Box::new(delay_inputs(g, spec));
    match f {
        Ltl::True | Ltl::False => f.clone(),
        Ltl::Var(s) if spec.signal(*s).kind == SignalKind::Input => Ltl::next(f.clone()),
        Ltl::Var(_) => f.clone(),
        Ltl::Not(a) => Ltl::Not(d(a)),
        Ltl::Next(a) => Ltl::Next(d(a)),
        Ltl::Globally(a) => Ltl::Globally(d(a)),
        Ltl::Finally(a) => Ltl::Finally(d(a)),
        Ltl::And(xs) => Ltl::And(xs.iter().map(|x| delay_inputs(x, spec)).collect()),
        Ltl::Or(xs) => Ltl::Or(xs.iter().map(|x| delay_inputs(x, spec)).collect()),
        Ltl::Implies(a, b) => Ltl::Implies(d(a), d(b)),
        Ltl::Iff(a, b) => Ltl::Iff(d(a), d(b)),
        Ltl::Until(a, b) => Ltl::Until(d(a), d(b)),
        Ltl::Release(a, b) => Ltl::Release(d(a), d(b)),
        Ltl::WeakUntil(a, b) => Ltl::WeakUntil(d(a), d(b)),
    }
}

/// JPF's LTL2Buchi, which G4LTL's parser hands formulas to: `[]`, `<>`, release as `V`, no
/// `<->`.
const JPF: Notation = Notation { globally: "[] ", finally: "<> ", release: " V ", iff: None };

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ltl::compile;
    use crate::ltl::Format;

    fn written(source: &str, format: Format) -> String {
        let (spec, _) = compile(source, format, &[]).expect("a valid specification");
        to_g4ltl(source, &spec).expect("expressible in G4LTL")
    }

    #[test]
    fn operators_become_jpf_operators() {
        let text = written("ALWAYS (a <-> NEXT b)\nASSUME G F (a R !b)\nINPUT a\nOUTPUT b\n", Format::G4ltl);
        assert_eq!(text, "ASSUME [] <> (a V !b)\n[] ((a -> X b) && (X b -> a))\n\nINPUT a\nOUTPUT b\n");
    }

    #[test]
    fn timers_keep_their_declaration_and_lose_our_liveness_assumption() {
        let text = written(
            "ALWAYS (a -> t1.start)\nALWAYS (t1.expire -> b)\nINPUT a\nOUTPUT b\nTIMER t1(90s)\n",
            Format::G4ltl,
        );
        assert_eq!(text, "[] (a -> t1.start)\n[] (t1.expire -> b)\n\nINPUT a\nOUTPUT b\nTIMER t1(90s)\n");
    }

    #[test]
    fn moore_reads_inputs_one_step_later() {
        let source = "INFO { TITLE: \"c\" DESCRIPTION: \"d\" SEMANTICS: Moore TARGET: Moore }\n\
                      MAIN { INPUTS { r; } OUTPUTS { g; } GUARANTEES { G (r -> g); } }";
        let text = written(source, Format::Tlsf);
        assert!(text.contains("\n[] (X r -> g)\n"), "{text}");
    }

    #[test]
    fn names_jpf_would_split_are_refused_where_declared() {
        let source = "ALWAYS (aXb -> c)\nINPUT aXb\nOUTPUT c\n";
        let (spec, _) = compile(source, Format::G4ltl, &[]).unwrap();
        let errors = to_g4ltl(source, &spec).unwrap_err();
        assert_eq!(errors.len(), 1);
        assert_eq!((errors[0].line, errors[0].column), (2, 7));
        assert!(errors[0].message.contains("`aXb`"), "{}", errors[0].message);
    }

    #[test]
    fn durations_are_exact() {
        assert_eq!(duration(10_000), "10s");
        assert_eq!(duration(1500), "1500ms");
        assert_eq!(duration(120_000), "2min");
        assert_eq!(duration(7_200_000), "2h");
    }
}
