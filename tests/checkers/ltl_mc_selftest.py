#!/usr/bin/env python3
"""Cross-checks ltl_mc.py against brute force, so that the checker is not trusted blindly.

Usage: ltl_mc_selftest.py [CASES] [SEED]

1. Known facts: a controller that always grants satisfies `G F grant` and violates
   `F G !grant`; Moore and Mealy timing of a one-step delay; an unsatisfiable and a valid
   formula.
2. Random small machines (controllers and counter-strategies, Mealy and Moore, 1-3 states,
   one or two signals a side) and random formulas over all the operators. Each is decided by
   ltl_mc.py in both modes (whole formula, and split) and by brute force: every lasso the
   machine can produce with a prefix plus cycle of at most MAX_LASSO steps is evaluated directly
   against the formula (fixpoint semantics, no automaton). A verdict `ok` with a brute-force
   counterexample, or the two modes disagreeing, is a failure; so is a reported violation that
   brute force cannot confirm within the bound (the reported lassos are short).
Prints `N passed, 0 failed` and exits 0, or lists the failures and exits 1.
"""
import io
import itertools
import json
import os
import random
import sys
import tempfile
from contextlib import redirect_stderr, redirect_stdout

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ltl_mc  # noqa: E402

MAX_LASSO = 7


def run(doc, *flags):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(doc, f)
    out, err = io.StringIO(), io.StringIO()
    try:
        with redirect_stdout(out), redirect_stderr(err):
            code = ltl_mc.main([*flags, f.name])
    finally:
        os.unlink(f.name)
    return code, out.getvalue() + err.getvalue()


def random_formula(rng, signals, depth):
    if depth == 0 or rng.random() < 0.2:
        if rng.random() < 0.08:
            return rng.choice(["true", "false"])
        return rng.choice(signals)
    op = rng.choice(["!", "G", "F", "X", "&&", "||", "->", "<->", "U", "R", "W", "!", "&&"])
    if op in ("!", "G", "F", "X"):
        return f"{op} ({random_formula(rng, signals, depth - 1)})"
    a = random_formula(rng, signals, depth - 1)
    b = random_formula(rng, signals, depth - 1)
    return f"({a}) {op} ({b})"


def valuations(signals):
    for values in itertools.product([False, True], repeat=len(signals)):
        yield dict(zip(signals, values))


def random_machine(rng, reads, writes, nstates, writes_per_state):
    """Rows keyed by every valuation of `reads` (some merged into one row where possible);
    `writes_per_state`: every row of a state writes the same values (Moore controllers,
    counter-strategies that move first)."""
    states = {}
    for s in range(nstates):
        fixed = {w: rng.random() < 0.5 for w in writes}
        if rng.random() < 0.3 or not reads:
            states[str(s)] = [[{}, rng.randrange(nstates), fixed]]
            continue
        rows = []
        for val in valuations(reads):
            out = fixed if writes_per_state else {w: rng.random() < 0.5 for w in writes}
            rows.append([val, rng.randrange(nstates), out])
        states[str(s)] = rows
    return {"init": 0, "states": states}


def plays(doc):
    """Every lasso (letters, loop start) of the machine with at most MAX_LASSO letters."""
    realizable = doc["verdict"] == "realizable"
    machine = doc["mealy"] if realizable else doc["counterstrategy"]
    reads = doc["inputs"] if realizable else doc["outputs"]
    rows = machine["states"]

    def step(state, choice):
        for guard, nxt, assign in rows[state]:
            if all(choice[k] == v for k, v in guard.items()):
                letter = dict(choice)
                letter.update(assign)
                return letter, str(nxt)
        raise AssertionError("no row")

    choices = list(valuations(reads))
    for n in range(1, MAX_LASSO + 1):
        for seq in itertools.product(choices, repeat=n):
            state, trail, letters = str(machine["init"]), [], []
            for choice in seq:
                trail.append(state)
                letter, state = step(state, choice)
                letters.append(letter)
            for loop in range(n):
                if trail[loop] == state:
                    yield letters, loop


def brute_force(doc):
    """(True, None) when no short lasso is bad, else (False, a bad lasso)."""
    formula = ltl_mc.parse_formula(doc["ltl"])
    want = doc["verdict"] == "realizable"
    for letters, loop in plays(doc):
        # unlisted written signals are free: complete them both ways
        free = [s for s in doc["inputs"] + doc["outputs"] if s not in letters[0]]
        if free:
            continue  # random_machine always lists every written signal
        if ltl_mc.evaluate_lasso(formula, letters, loop)[0] != want:
            return False, (letters, loop)
    return True, None


def known_facts():
    always = {"init": 0, "states": {"0": [[{}, 0, {"grant": True}]]}}
    delay = {
        "init": 0,
        "states": {
            "0": [[{"req": True}, 1, {"grant": False}], [{"req": False}, 0, {"grant": False}]],
            "1": [[{"req": True}, 1, {"grant": True}], [{"req": False}, 0, {"grant": True}]],
        },
    }
    instant = {
        "init": 0,
        "states": {"0": [[{"req": True}, 0, {"grant": True}], [{"req": False}, 0, {"grant": False}]]},
    }
    cases = [
        ("always grant, G F grant", always, "mealy", "G F grant", 0),
        ("always grant, F G !grant", always, "mealy", "F G !grant", 1),
        ("always grant, G grant (Moore)", always, "moore", "G grant", 0),
        ("always grant, X !grant", always, "mealy", "X !grant", 1),
        ("always grant, req U grant", always, "mealy", "req U grant", 0),
        ("always grant, false", always, "mealy", "false", 1),
        ("always grant, true", always, "mealy", "true", 0),
        ("delay, Moore: grant is last step's req", delay, "moore", "G (req <-> X grant)", 0),
        ("delay, Moore: grant is not this step's req", delay, "moore", "G (req <-> grant)", 1),
        ("delay, Moore: first grant is false", delay, "moore", "!grant", 0),
        ("instant, Mealy: grant is this step's req", instant, "mealy", "G (req <-> grant)", 0),
        ("instant, Mealy: not last step's", instant, "mealy", "G (req <-> X grant)", 1),
        ("instant, Mealy: W", instant, "mealy", "G ((!req) W grant)", 0),
        ("instant, Mealy: W is not U", instant, "mealy", "G ((!req) U grant)", 1),
        ("instant, Mealy: R", instant, "mealy", "req R grant", 1),
        ("instant, Mealy: dotted names ok", instant, "mealy", "G (req -> grant)", 0),
    ]
    failures = []
    for name, machine, semantics, ltl, expected in cases:
        doc = {
            "verdict": "realizable",
            "semantics": semantics,
            "inputs": ["req"],
            "outputs": ["grant"],
            "ltl": ltl,
            "mealy": machine,
        }
        for flags in ([], ["--split"]):
            code, out = run(doc, *flags)
            if code != expected:
                failures.append(f"{name} {flags}: exit {code}, expected {expected}\n{out}")
    # a signal name with a dot
    doc = {
        "verdict": "realizable",
        "semantics": "mealy",
        "inputs": ["t1.start"],
        "outputs": ["t1.done"],
        "ltl": "G (t1.start -> t1.done) && G F t1.done",
        "mealy": {"init": 0, "states": {"0": [[{}, 0, {"t1.done": True}]]}},
    }
    code, out = run(doc)
    if code != 0:
        failures.append(f"dotted names: exit {code}\n{out}")
    return len(cases) * 2 + 1, failures


def random_cases(count, seed):
    rng = random.Random(seed)
    failures = []
    for case in range(count):
        ni, no = rng.choice([(1, 1), (1, 1), (2, 1), (1, 2)])
        inputs = [f"i{k}" for k in range(ni)]
        outputs = [f"o{k}" for k in range(no)]
        semantics = rng.choice(["mealy", "moore"])
        realizable = rng.random() < 0.6
        nstates = rng.randint(1, 3)
        if realizable:
            machine = random_machine(rng, inputs, outputs, nstates, semantics == "moore")
        else:
            machine = random_machine(rng, outputs, inputs, nstates, semantics == "mealy")
            machine["moves_first"] = semantics == "mealy"
        ltl = random_formula(rng, inputs + outputs, rng.randint(1, 4))
        doc = {
            "verdict": "realizable" if realizable else "unrealizable",
            "semantics": semantics,
            "inputs": inputs,
            "outputs": outputs,
            "ltl": ltl,
            "mealy" if realizable else "counterstrategy": machine,
        }
        whole, out_whole = run(doc)
        split, out_split = run(doc, "--split")
        truth, witness = brute_force(doc)
        problem = None
        if whole != split:
            problem = f"modes disagree: whole {whole}, split {split}"
        elif whole not in (0, 1):
            problem = f"exit {whole}"
        elif whole == 0 and not truth:
            problem = f"ok, but brute force finds {witness}"
        elif whole == 1 and truth:
            problem = "violation that brute force does not confirm within its bound"
        if problem:
            failures.append(
                f"case {case}: {problem}\n{json.dumps(doc)}\n{out_whole}\n{out_split}"
            )
    return count, failures


def main(argv):
    count = int(argv[0]) if argv else 200
    seed = int(argv[1]) if len(argv) > 1 else 1
    n1, f1 = known_facts()
    n2, f2 = random_cases(count, seed)
    failures = f1 + f2
    for failure in failures:
        print(failure)
    print(f"{n1 + n2 - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
