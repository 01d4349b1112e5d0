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
            let _ = writeln!(s, "    event start : controllable;\n    event finish : uncontrollable;");
            let _ = writeln!(s, "    plant P {{ alphabet start, finish; state I initial {{ start -> W; }} state W {{ finish -> I; }} }}");
            let _ = writeln!(s, "  }}");
        }
        let _ = writeln!(s, "  module TU {{");
        let _ = writeln!(s, "    event start : controllable;\n    event reject : uncontrollable;\n    event accept : uncontrollable;");
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
