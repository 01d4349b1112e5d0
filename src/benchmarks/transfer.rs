//! The transfer-line family of Göbe 2019, section 7.5 (after Wonham's transfer line): `k`
//! lines of `m` machines and a test unit each. Machines and test units are plant models; the
//! buffers between them exist only as specifications that forbid taking from an empty buffer
//! and putting into a full one (capacity 2). A buffer `TB` joins the test unit of one line to
//! the first machine of the next. That gives `k·(m+1)` plants and `k·m + k − 1` specifications.

use std::fmt::Write as _;

/// Events of machine `j` (1-based) of line `i`, or of the test unit (`j = m + 1`).
fn dev(i: usize, j: usize, m: usize) -> String {
    if j == m + 1 {
        format!("TL{i}.TU")
    } else {
        format!("TL{i}.M{j}")
    }
}

fn buffer(out: &mut String, name: &str, ins: &[String], outs: &[String], cap: usize) {
    let _ = writeln!(out, "spec {name} {{");
    for n in 0..=cap {
        let init = if n == 0 { " initial" } else { "" };
        let _ = write!(out, "  state n{n}{init} {{");
        if n == 0 {
            let _ = write!(out, " forbid {};", outs.join(", "));
        } else {
            for o in outs {
                let _ = write!(out, " {o} -> n{};", n - 1);
            }
        }
        if n == cap {
            let _ = write!(out, " forbid {};", ins.join(", "));
        } else {
            for i in ins {
                let _ = write!(out, " {i} -> n{};", n + 1);
            }
        }
        let _ = writeln!(out, " }}");
    }
    let _ = writeln!(out, "}}");
}

/// The `.sct` text of `k` transfer lines with `m ≥ 1` machines each and buffer capacity `cap`.
pub fn transfer_lines(k: usize, m: usize, cap: usize) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "// {k} transfer lines x {m} machines, buffer capacity {cap} (generated).");
    for i in 1..=k {
        let _ = writeln!(s, "module TL{i} {{");
        for j in 1..=m {
            let _ = writeln!(s, "  module M{j} {{");
            // Triggers on made-up PLC tags, so that the supervisors run in the runtime framework.
            let _ = writeln!(
                s,
                "    event start : controllable {{ detect rising \"Q_L{i}_M{j}_Run\"; reset on denial \"Q_L{i}_M{j}_Run\"; }}\n    \
                 event finish : uncontrollable {{ detect rising \"I_L{i}_M{j}_Done\"; }}"
            );
            let _ = writeln!(s, "    plant P {{ alphabet start, finish; state I initial {{ start -> W; }} state W {{ finish -> I; }} }}");
            let _ = writeln!(s, "  }}");
        }
        let _ = writeln!(s, "  module TU {{");
        let _ = writeln!(
            s,
            "    event start : controllable {{ detect rising \"Q_L{i}_TU_Run\"; reset on denial \"Q_L{i}_TU_Run\"; }}\n    \
             event reject : uncontrollable {{ detect rising \"I_L{i}_TU_Reject\"; }}\n    \
             event accept : uncontrollable {{ detect rising \"I_L{i}_TU_Accept\"; }}"
        );
        let _ = writeln!(
            s,
            "    plant P {{ alphabet start, reject, accept; state I initial {{ start -> W; }} state W {{ reject -> I; accept -> I; }} }}"
        );
        let _ = writeln!(s, "  }}");
        let _ = writeln!(s, "}}");
    }
    for i in 1..=k {
        for j in 1..=m {
            let mut ins = vec![format!("{}.finish", dev(i, j, m))];
            if j == 1 {
                ins.push(format!("TL{i}.TU.reject"));
            }
            let outs = vec![format!("{}.start", dev(i, j + 1, m))];
            buffer(&mut s, &format!("B{i}_{j}"), &ins, &outs, cap);
        }
        if i < k {
            buffer(&mut s, &format!("TB{i}"), &[format!("TL{i}.TU.accept")], &[format!("TL{}.M1.start", i + 1)], cap);
        }
    }
    s
}

/// A reconstruction of the "extended machines" line of table 7.2 (the thesis gives only the
/// automaton sizes): one line whose first machine is abstract and whose other `extended`
/// machines each consist of a process model (6 states), a drill (5 states) and a cooling unit
/// (2 states), followed by the test unit, plus one global sensor (3 states) that shares its
/// `pulse` event with every process model. Process, drill and cooling share uncontrollable
/// events, so the `Dep` closure of every buffer reaches all plants. Buffers (capacity 2) are
/// specifications.
pub fn extended_line(extended: usize) -> String {
    let mut s = String::new();
    let m = extended + 1;
    let _ = writeln!(s, "// One transfer line with {extended} extended machines and a shared sensor (generated).");
    let _ = writeln!(s, "event pulse : uncontrollable;\nevent sensorReset : uncontrollable;");
    let _ = writeln!(s, "plant Sensor {{ alphabet pulse, sensorReset; state s0 initial {{ pulse -> s1; }} state s1 {{ pulse -> s2; }} state s2 {{ sensorReset -> s0; }} }}");
    let _ = writeln!(s, "module TL1 {{");
    let _ = writeln!(s, "  module M1 {{\n    event start : controllable;\n    event finish : uncontrollable;");
    let _ = writeln!(
        s,
        "    plant P {{ alphabet start, finish; state I initial {{ start -> W; }} state W {{ finish -> I; }} }}\n  }}"
    );
    for j in 2..=m {
        let _ = writeln!(s, "  module M{j} {{");
        for (e, k) in [
            ("start", "controllable"),
            ("finish", "uncontrollable"),
            ("drillOn", "controllable"),
            ("drillOff", "controllable"),
            ("coolOn", "controllable"),
            ("cooled", "uncontrollable"),
            ("lower", "uncontrollable"),
            ("raise", "uncontrollable"),
            ("stopped", "uncontrollable"),
        ] {
            let _ = writeln!(s, "    event {e} : {k};");
        }
        let _ = writeln!(
            s,
            "    plant P {{ alphabet start, drillOn, stopped, coolOn, cooled, finish, pulse;\n      \
             state idle initial {{ start -> loaded; pulse -> idle; }}\n      \
             state loaded {{ drillOn -> drilling; pulse -> loaded; }}\n      \
             state drilling {{ stopped -> drilled; pulse -> drilling; }}\n      \
             state drilled {{ coolOn -> cooling; pulse -> drilled; }}\n      \
             state cooling {{ cooled -> done; pulse -> cooling; }}\n      \
             state done {{ finish -> idle; pulse -> done; }} }}"
        );
        let _ = writeln!(
            s,
            "    plant Drill {{ alphabet drillOn, lower, raise, drillOff, stopped;\n      \
             state off initial {{ drillOn -> spinUp; }} state spinUp {{ lower -> down; }} state down {{ raise -> up; }}\n      \
             state up {{ drillOff -> spinDown; }} state spinDown {{ stopped -> off; }} }}"
        );
        let _ = writeln!(s, "    plant Cooling {{ alphabet coolOn, cooled; state off initial {{ coolOn -> on; }} state on {{ cooled -> off; }} }}");
        let _ = writeln!(s, "  }}");
    }
    let _ = writeln!(s, "  module TU {{\n    event start : controllable;\n    event reject : uncontrollable;\n    event accept : uncontrollable;");
    let _ = writeln!(s, "    plant P {{ alphabet start, reject, accept; state I initial {{ start -> W; }} state W {{ reject -> I; accept -> I; }} }}\n  }}");
    let _ = writeln!(s, "}}");
    for j in 1..=m {
        let mut ins = vec![format!("{}.finish", dev(1, j, m))];
        if j == 1 {
            ins.push("TL1.TU.reject".to_string());
        }
        buffer(&mut s, &format!("B1_{j}"), &ins, &[format!("{}.start", dev(1, j + 1, m))], 2);
    }
    s
}
