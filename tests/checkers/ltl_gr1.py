#!/usr/bin/env python3
"""Second opinion on the engine's verdict for GR(1)-shaped specifications, from gr1py.

Usage: ltl_gr1.py [-v] FILE.json, or ltl_gr1.py [-v] --each FILE.json... (a line of JSON per
document with what the single form prints and exits with)
Prints `realizable` or `unrealizable` (exit 0) as gr1py decides, or `not-gr1` (exit 4, the
reason on stderr) when the specification is outside the fragment where gr1py's answer is
provably the answer to our question. Exit 2: malformed document; exit 3: gr1py missing or
failing. `-v` prints the generated spc on stderr.

gr1py (PyPI, by S. C. Livingston; an enumerative solver for the gr1c input format) is run as
`gr1py -r SPEC.spc`: exit 0 "Realizable.", exit 3 "Not realizable.". Nothing here comes from
the engine: the formulas are parsed by ltl_mc.py's parser and classified here.

The fragment. Each assumption and each guarantee, split at top-level `&&`, must be
- propositional: an initial condition (ENVINIT / SYSINIT);
- `G φ`, φ propositional over current signals and `X` of propositional subformulas (no `X`
  under `X`): a safety condition (ENVTRANS / SYSTRANS, `X a` written `a'`). When φ has no `X`
  at all it is written as an initial condition `φ` plus the transition condition `φ'`;
- `G F φ`, φ propositional: a goal (ENVGOAL / SYSGOAL).

The semantics, and why the answers agree. gr1py's game (gr1c's ALL_ENV_EXIST_SYS_INIT): for
every initial input valuation satisfying ENVINIT the system picks an initial output valuation
satisfying SYSINIT; then, each step, the environment picks next inputs allowed by ENVTRANS and
the system, seeing them, picks next outputs allowed by SYSTRANS; the system wins when it can
always move and the play satisfies GF(env goals) -> GF(sys goals). The environment moves first
and the system sees the step's inputs: our Mealy semantics, the letter of step t being the
state (inputs(t), outputs(t)). Moore specifications are refused (not-gr1).
Our question is realizability of the plain implication `(∧ assumptions) -> (∧ guarantees)`,
where the system also wins by waiting for the environment to break a safety assumption, or
by giving up its own safety once the environment can no longer satisfy its goals; gr1py solves
the "strict" game, where the system must keep its safety for as long as the environment keeps
its own. The two differ in general. They agree when the environment, after any finite play
that kept its assumptions so far, can still go on keeping them and meet every goal infinitely
often, whatever the system does: then a system that breaks a guarantee on some prefix loses
the implication too (the environment completes the prefix into a play satisfying every
assumption), and a strict winner obviously wins the implication. So the assumptions must
mention inputs only (initial conditions, safety over inputs and next inputs, goals over inputs),
and this script checks, on the graph of input valuations that the environment's safety allows,
that every valuation reachable from an initial one can reach a cycle meeting every goal (and
that every valuation has a successor, as gr1py's solver needs). Otherwise: not-gr1.
Signals are renamed e0 e1 ... (inputs) and s0 s1 ... (outputs): gr1c's identifiers have no dots.
"""
import itertools
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ltl_mc import Malformed, atoms, load_json, parse_formula  # noqa: E402

TEMPORAL = {"G", "F", "X", "U", "R", "W"}
MAX_SIGNALS = 10


class NotGr1(Exception):
    pass


def temporal_ops(ast, acc=None):
    acc = set() if acc is None else acc
    if ast[0] in TEMPORAL:
        acc.add(ast[0])
    if ast[0] not in ("ap", "const"):
        for sub in ast[1:]:
            temporal_ops(sub, acc)
    return acc


def conjuncts(ast):
    if ast[0] == "&&":
        return conjuncts(ast[1]) + conjuncts(ast[2])
    return [ast]


def to_spc(ast, names, primed=False):
    """Propositional formula (X allowed one level deep) in gr1c syntax."""
    op = ast[0]
    if op == "ap":
        return names[ast[1]] + ("'" if primed else "")
    if op == "const":
        return "True" if ast[1] else "False"
    if op == "X":
        if primed:
            raise NotGr1("X under X")
        return to_spc(ast[1], names, True)
    if op == "!":
        return f"!({to_spc(ast[1], names, primed)})"
    if op in ("&&", "||", "->", "<->"):
        symbol = {"&&": "&", "||": "|", "->": "->", "<->": "<->"}[op]
        return f"({to_spc(ast[1], names, primed)} {symbol} {to_spc(ast[2], names, primed)})"
    raise NotGr1(f"temporal operator {op} inside a GR(1) part")


def evaluate(ast, now, nxt=None):
    op = ast[0]
    if op == "ap":
        return now[ast[1]]
    if op == "const":
        return ast[1]
    if op == "X":
        return evaluate(ast[1], nxt)
    if op == "!":
        return not evaluate(ast[1], now, nxt)
    a, b = evaluate(ast[1], now, nxt), evaluate(ast[2], now, nxt)
    return {"&&": a and b, "||": a or b, "->": (not a) or b, "<->": a == b}[op]


def classify(ast):
    """('init' | 'trans' | 'goal', propositional body)."""
    ops = temporal_ops(ast)
    if not ops:
        return "init", ast
    if ast[0] == "G":
        body = ast[1]
        if body[0] == "F" and not temporal_ops(body[1]):
            return "goal", body[1]
        if temporal_ops(body) <= {"X"}:
            to_spc(body, {a: a for a in atoms(body)})  # raises on X under X
            return "trans", body
    raise NotGr1(f"not a GR(1) part: {ast}")


def env_can_always_continue(inputs, init, trans, goals):
    """On the graph of input valuations allowed by the environment's safety, every valuation
    reachable from an initial one reaches a cycle that meets every goal. Raises NotGr1."""
    vals = [dict(zip(inputs, v)) for v in itertools.product([False, True], repeat=len(inputs))]
    succ = {
        i: [j for j, y in enumerate(vals) if all(evaluate(t, x, y) for t in trans)]
        for i, x in enumerate(vals)
    }
    if any(not s for s in succ.values()):
        raise NotGr1("the environment's safety assumptions can deadlock")
    reach = {i for i, x in enumerate(vals) if all(evaluate(c, x) for c in init)}
    frontier = list(reach)
    while frontier:
        for j in succ[frontier.pop()]:
            if j not in reach:
                reach.add(j)
                frontier.append(j)
    # a valuation is good when it reaches a nontrivial SCC holding every goal; the graph is
    # small (at most 2^MAX_SIGNALS vertices), so compute mutual reachability directly
    closure = {}
    for i in range(len(vals)):
        seen, stack = set(), list(succ[i])
        while stack:
            j = stack.pop()
            if j not in seen:
                seen.add(j)
                stack.extend(succ[j])
        closure[i] = seen
    good_cycles = set()
    for i in range(len(vals)):
        if i in closure[i]:
            component = {j for j in closure[i] if i in closure[j]}
            if all(any(evaluate(g, vals[j]) for j in component) for g in goals):
                good_cycles.add(i)
    for i in reach:
        if not ({i} | closure[i]) & good_cycles:
            raise NotGr1(
                f"from inputs {vals[i]} the environment cannot keep its assumptions and meet "
                "its goals: the implication and gr1py's strict game may disagree"
            )


def build_spc(doc):
    if doc["semantics"] != "mealy":
        raise NotGr1("gr1py decides Mealy realizability only")
    inputs, outputs = doc["inputs"], doc["outputs"]
    if len(inputs) + len(outputs) > MAX_SIGNALS:
        raise NotGr1(f"more than {MAX_SIGNALS} signals: too large for enumerative gr1py")
    names = {s: f"e{i}" for i, s in enumerate(inputs)}
    names.update({s: f"s{i}" for i, s in enumerate(outputs)})
    parts = {}
    for side in ("assumptions", "guarantees"):
        formulas = doc.get(side)
        if not isinstance(formulas, list) or not all(isinstance(f, str) for f in formulas):
            raise Malformed(f"{side} must be a list of formulas")
        for text in formulas:
            ast = parse_formula(text)
            unknown = atoms(ast) - set(names)
            if unknown:
                raise Malformed(f"{text!r} names undeclared signals {sorted(unknown)}")
            for part in conjuncts(ast):
                kind, body = classify(part)
                if side == "assumptions" and not atoms(body) <= set(inputs):
                    raise NotGr1(
                        f"assumption {text!r} mentions outputs: the implication and gr1py's "
                        "strict game may disagree"
                    )
                if kind == "trans" and "X" not in temporal_ops(body):
                    parts.setdefault((side, "init"), []).append(body)
                    parts.setdefault((side, "trans"), []).append(("X", body))
                else:
                    parts.setdefault((side, kind), []).append(body)
    env_can_always_continue(
        inputs,
        parts.get(("assumptions", "init"), []),
        parts.get(("assumptions", "trans"), []),
        parts.get(("assumptions", "goal"), []),
    )

    def section(label, side, kind):
        bodies = [to_spc(b, names) for b in parts.get((side, kind), [])]
        if kind == "init":
            return f"{label} {' & '.join(bodies)};" if bodies else f"{label};"
        op = "[]" if kind == "trans" else "[]<>"
        return f"{label} " + " & ".join(f"{op}{b}" for b in bodies) + ";" if bodies else f"{label};"

    lines = [
        "ENV: " + " ".join(names[s] for s in inputs) + ";",
        "SYS: " + " ".join(names[s] for s in outputs) + ";",
        section("ENVINIT:", "assumptions", "init"),
        section("ENVTRANS:", "assumptions", "trans"),
        section("ENVGOAL:", "assumptions", "goal"),
        section("SYSINIT:", "guarantees", "init"),
        section("SYSTRANS:", "guarantees", "trans"),
        section("SYSGOAL:", "guarantees", "goal"),
    ]
    return "\n".join(lines) + "\n"


def gr1py_command():
    beside = os.path.join(os.path.dirname(sys.executable), "gr1py")
    if os.path.exists(beside):
        return beside
    return shutil.which("gr1py")


def check(path, verbose=False):
    """gr1py's verdict on one document: (exit code, stdout text, stderr text), as `main`."""
    try:
        doc = load_json(path)
        for key in ("semantics", "inputs", "outputs"):
            if key not in doc:
                raise Malformed(f"missing key {key!r}")
        spc = build_spc(doc)
    except Malformed as e:
        return 2, "", f"malformed: {e}\n"
    except NotGr1 as e:
        return 4, "not-gr1\n", f"not-gr1: {e}\n"
    err = f"{spc}\n" if verbose else ""
    command = gr1py_command()
    if command is None:
        return 3, "", err + "gr1py is missing: pip install gr1py (bash scripts/python-checkers.sh)\n"
    with tempfile.NamedTemporaryFile("w", suffix=".spc", delete=False) as f:
        f.write(spc)
    try:
        done = subprocess.run([command, "-r", f.name], capture_output=True, text=True)
    finally:
        os.unlink(f.name)
    if done.returncode == 0 and "Realizable." in done.stdout:
        return 0, "realizable\n", err
    if done.returncode == 3 and "Not realizable." in done.stdout:
        return 0, "unrealizable\n", err
    return 3, "", err + f"gr1py failed (exit {done.returncode}):\n{done.stdout}{done.stderr}\n{spc}\n"


def main(argv):
    verbose = "-v" in argv
    each = "--each" in argv
    args = [a for a in argv if a not in ("-v", "--each")]
    if each:
        # One process for many documents (a test's whole listing): a line of JSON per document,
        # {"file", "code", "stdout", "stderr"}, in the order given; exit 0 once all are checked.
        for path in args:
            code, out, err = check(path, verbose)
            print(json.dumps({"file": path, "code": code, "stdout": out, "stderr": err}), flush=True)
        return 0
    if len(args) != 1:
        print("usage: ltl_gr1.py [-v] FILE.json | ltl_gr1.py [-v] --each FILE.json...", file=sys.stderr)
        return 2
    code, out, err = check(args[0], verbose)
    sys.stdout.write(out)
    sys.stderr.write(err)
    return code


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
