#!/usr/bin/env python3
"""Independent model checker for the machines `plcsynth ltl FILE --json` prints.

Usage: ltl_mc.py [--split] [--lbt-timeout SECONDS] FILE.json

Exit 0 and `ok`: the machine is right. For `"verdict": "realizable"` the `mealy` controller,
played against every environment, produces only words that satisfy `ltl`; for
`"unrealizable"` the `counterstrategy`, played against every controller, produces only words
that violate `ltl`. Exit 1: a lasso word (prefix, then a cycle repeated forever) that the
machine can produce and that has the wrong truth value. Exit 2: malformed document (bad JSON,
unknown signal, rows of a state that overlap or miss an input valuation, Moore outputs that
depend on the inputs, ...). Exit 3: the checker itself could not decide (lbt failed on every
way of asking) or found an internal inconsistency.

Method (automata-theoretic model checking, nothing taken from the engine):
1. `ltl` is parsed here (a small Pratt parser) and the property whose words are *bad* is
   formed: `! ltl` for a controller, `ltl` itself for a counter-strategy.
2. Debian's `lbt` (Gerth-Peled-Vardi-Wolper translation, written in 1999 by other people)
   turns it into a generalised Büchi automaton. Its input is prefix notation over `p0 p1 ...`
   (`W` is not in lbt's language: `a W b` is sent as `V b | a b`, `a R b` as `V a b`). Its output
   (LBTT format): `NSTATES NSETS`, then per state `ID INITIAL ACC... -1` followed by
   transitions `DEST GUARD` and `-1`; a run reads letter t on the transition it takes from its
   t-th state, and is accepting when it meets each acceptance set (sets of *states*)
   infinitely often; `NSETS = 0` means every infinite run is accepting.
3. The product of the machine with *every* opponent choice (every valuation of the signals the
   machine does not write, each step; written signals a row leaves out are free too) and the
   automaton is explored; Tarjan's algorithm (iterative) finds its strongly connected
   components, and one that is nontrivial (two nodes, or a self-loop) and meets every
   acceptance set gives a bad lasso word. None: `ok`.
4. Timing. The letter of step t is inputs(t) ∪ outputs(t). Mealy: in state s the
   environment picks inputs(t), the row of s that matches them gives outputs(t) and the next
   state. Moore: outputs(t) are those of state s (every row of s must carry the same outputs:
   checked), then the environment picks inputs(t) and the row gives the next state. Both are
   the same product; only the check on the rows differs. Counter-strategy, moves_first (Mealy):
   every row of a state writes the same inputs(t); the controller's outputs(t) choose the row
   and so the next state. moves_first false (Moore): the row chosen by outputs(t) writes
   inputs(t).
5. Every lasso found is evaluated again directly against `ltl` (the textbook fixpoint
   semantics on an ultimately periodic word, no automaton), so a misreading of lbt's output
   would show up as exit 3 rather than as a wrong counterexample.

Large formulas. GPVW blows up on long conjunctions, and lbt crashes (SIGSEGV, seen on the
negation of five response guarantees `G (r -> (g || X g))` and more, often after seconds). The
whole bad property is tried first (under a timeout: one second where it splits); if lbt fails
or times out, the bad property is rewritten, by propositional equivalences only (De Morgan,
`a -> b` = `!a || b`, distributing `&&` over `||`), into a disjunction of conjunctions of temporal
formulas, each conjunct is translated on its own, and for each disjunct the machine is explored
together with all the automata of its conjuncts at once (the synchronous product of automata
accepts exactly the conjunction). For a controller with `ltl = A1 && ... && An -> G1 && ... && Gm`
that gives one check per guarantee, `A1 && ... && An && !Gi`: guarantees are split,
assumptions never are (the check keeps all of them together, so an environment that breaks one
assumption to break a guarantee is not counted). This is exact, not an approximation: the same
words are bad either way. `--split` forces this mode (the tests use it to check that both modes
agree).
"""
import itertools
import json
import subprocess
import sys
from collections import deque

BINARY = {"<->": 1, "->": 2, "||": 3, "&&": 4, "U": 5, "R": 5, "W": 5}
RIGHT_ASSOC = {"->", "U", "R", "W"}
UNARY = {"!", "G", "F", "X"}
KEYWORDS = {"G", "F", "X", "U", "R", "W", "true", "false"}
# How long lbt may take on the whole formula when the formula can be split instead.
WHOLE_TRY_SECONDS = 1.0


class Malformed(Exception):
    pass


class Undecided(Exception):
    pass


# ----------------------------------------------------------------------------- formulas
# AST: ("ap", name) | ("const", bool) | (op, a) for ! G F X | (op, a, b) for binary ops.


def tokenize(text):
    tokens, i = [], 0
    while i < len(text):
        c = text[i]
        if c.isspace():
            i += 1
        elif text.startswith("<->", i):
            tokens.append("<->")
            i += 3
        elif text[i : i + 2] in ("->", "&&", "||"):
            tokens.append(text[i : i + 2])
            i += 2
        elif c in "()!":
            tokens.append(c)
            i += 1
        elif c.isalpha() or c == "_":
            j = i + 1
            while j < len(text) and (text[j].isalnum() or text[j] in "_."):
                j += 1
            tokens.append(text[i:j])
            i = j
        else:
            raise Malformed(f"unexpected character {c!r} in formula {text!r}")
    return tokens


def parse_formula(text):
    tokens = tokenize(text)
    pos = 0

    def peek():
        return tokens[pos] if pos < len(tokens) else None

    def take():
        nonlocal pos
        if pos >= len(tokens):
            raise Malformed(f"formula ends early: {text!r}")
        pos += 1
        return tokens[pos - 1]

    def primary():
        tok = take()
        if tok == "(":
            inner = expr(0)
            if take() != ")":
                raise Malformed(f"missing ')' in {text!r}")
            return inner
        if tok in UNARY:
            return (tok, primary())
        if tok in ("true", "false"):
            return ("const", tok == "true")
        if tok in KEYWORDS or tok in BINARY or tok == ")":
            raise Malformed(f"unexpected {tok!r} in {text!r}")
        return ("ap", tok)

    def expr(min_prec):
        left = primary()
        while peek() in BINARY and BINARY[peek()] >= min_prec:
            op = take()
            prec = BINARY[op]
            right = expr(prec if op in RIGHT_ASSOC else prec + 1)
            left = (op, left, right)
        return left

    ast = expr(0)
    if pos != len(tokens):
        raise Malformed(f"unexpected {tokens[pos]!r} in {text!r}")
    return ast


def atoms(ast, acc=None):
    acc = set() if acc is None else acc
    if ast[0] == "ap":
        acc.add(ast[1])
    elif ast[0] != "const":
        for sub in ast[1:]:
            atoms(sub, acc)
    return acc


def show(ast):
    if ast[0] == "ap":
        return ast[1]
    if ast[0] == "const":
        return "true" if ast[1] else "false"
    if len(ast) == 2:
        return f"{ast[0]} ({show(ast[1])})" if ast[0] != "!" else f"!({show(ast[1])})"
    return f"({show(ast[1])}) {ast[0]} ({show(ast[2])})"


def to_lbt(ast, index):
    """Prefix notation for lbt; `index` maps signal names to proposition numbers."""
    op = ast[0]
    if op == "ap":
        return f"p{index[ast[1]]}"
    if op == "const":
        return "t" if ast[1] else "f"
    if len(ast) == 2:
        return f"{op} {to_lbt(ast[1], index)}"
    a, b = to_lbt(ast[1], index), to_lbt(ast[2], index)
    if op == "W":  # a W b == b R (a || b)
        return f"V {b} | {a} {b}"
    prefix = {"&&": "&", "||": "|", "->": "i", "<->": "e", "U": "U", "R": "V"}[op]
    return f"{prefix} {a} {b}"


def split_top(ast, positive=True):
    """The formula (negated unless `positive`) as a list of disjuncts, each a list of
    conjuncts, by propositional equivalences applied above the temporal operators."""
    op = ast[0]
    if op == "!":
        return split_top(ast[1], not positive)
    if op == "const":
        return [[]] if ast[1] == positive else []
    if op in ("&&", "||", "->"):
        left_positive = positive if op != "->" else not positive
        left, right = split_top(ast[1], left_positive), split_top(ast[2], positive)
        conjunctive = (op == "&&") == positive
        if not conjunctive:
            return left + right
        return [l + r for l in left for r in right]
    if op == "<->":
        # a <-> b is (a && b) || (!a && !b); its negation (a && !b) || (!a && b). lbt's own `e`
        # crashes it under a negation when the sides hold nested eventualities.
        a, b = ast[1], ast[2]
        pairs = [(True, positive), (False, not positive)]
        return [l + r for pa, pb in pairs for l in split_top(a, pa) for r in split_top(b, pb)]
    return [[ast if positive else ("!", ast)]]


def evaluate_lasso(ast, letters, loop_start):
    """Truth of `ast` at each position of the word letters[:loop_start] (letters[loop_start:])^ω."""
    n = len(letters)
    nxt = [i + 1 if i + 1 < n else loop_start for i in range(n)]
    op = ast[0]
    if op == "ap":
        return [letter[ast[1]] for letter in letters]
    if op == "const":
        return [ast[1]] * n
    if op == "!":
        return [not v for v in evaluate_lasso(ast[1], letters, loop_start)]
    if op == "X":
        sub = evaluate_lasso(ast[1], letters, loop_start)
        return [sub[nxt[i]] for i in range(n)]
    if op in ("G", "F"):
        return evaluate_lasso(
            ("R" if op == "G" else "U", ("const", op == "F"), ast[1]), letters, loop_start
        )
    a = evaluate_lasso(ast[1], letters, loop_start)
    b = evaluate_lasso(ast[2], letters, loop_start)
    if op == "&&":
        return [x and y for x, y in zip(a, b)]
    if op == "||":
        return [x or y for x, y in zip(a, b)]
    if op == "->":
        return [(not x) or y for x, y in zip(a, b)]
    if op == "<->":
        return [x == y for x, y in zip(a, b)]
    # Fixpoints: U least, R and W greatest; n+1 rounds reach them on a lasso.
    if op == "U":
        val, step = [False] * n, lambda i, v: b[i] or (a[i] and v[nxt[i]])
    elif op == "R":
        val, step = [True] * n, lambda i, v: b[i] and (a[i] or v[nxt[i]])
    else:  # W
        val, step = [True] * n, lambda i, v: b[i] or (a[i] and v[nxt[i]])
    while True:
        new = [step(i, val) for i in range(n)]
        if new == val:
            return val
        val = new


# ----------------------------------------------------------------------------- lbt


def parse_guard(tokens, pos):
    """Guard in prefix notation -> (list of cubes {prop: bool}, next position)."""
    tok = tokens[pos]
    if tok == "t":
        return [{}], pos + 1
    if tok == "f":
        return [], pos + 1
    if tok.startswith("p") and tok[1:].isdigit():
        return [{int(tok[1:]): True}], pos + 1
    if tok == "!":
        cubes, pos = parse_guard(tokens, pos + 1)
        # negation of a DNF, back to DNF (lbt only negates propositions in practice)
        result = [{}]
        for cube in cubes:
            result = [
                merged
                for partial in result
                for prop, value in cube.items()
                for merged in [merge(partial, {prop: not value})]
                if merged is not None
            ]
        return result, pos
    if tok in ("&", "|"):
        left, pos = parse_guard(tokens, pos + 1)
        right, pos = parse_guard(tokens, pos)
        if tok == "|":
            return left + right, pos
        both = [merge(l, r) for l in left for r in right]
        return [c for c in both if c is not None], pos
    raise Undecided(f"lbt printed an unknown guard token {tok!r}")


def guard_end(tokens, pos):
    """The position just past the guard in prefix notation that starts at `pos`."""
    open_operands = 1
    while open_operands:
        tok = tokens[pos]
        if tok in ("&", "|"):
            open_operands += 1
        elif tok != "!":
            open_operands -= 1
        pos += 1
    return pos


def merge(a, b):
    out = dict(a)
    for key, value in b.items():
        if out.get(key, value) != value:
            return None
        out[key] = value
    return out


def parse_lbtt(text):
    """LBTT automaton -> (initial state, {state: (acceptance sets, [(dest, cubes)])}, the
    acceptance sets); initial state None when no run is accepting."""
    tokens = text.split()
    if len(tokens) < 2:
        raise Undecided(f"lbt printed no automaton: {text!r}")
    nstates, nsets, pos = int(tokens[0]), int(tokens[1]), 2
    states, initial = {}, None
    # lbt repeats the same guards on many transitions: each distinct one is parsed once (the
    # cubes are only read afterwards, so the transitions may share them).
    guards = {}
    for _ in range(nstates):
        sid, init = int(tokens[pos]), tokens[pos + 1]
        pos += 2
        acc = set()
        while tokens[pos] != "-1":
            acc.add(int(tokens[pos]))
            pos += 1
        pos += 1
        transitions = []
        while tokens[pos] != "-1":
            dest = int(tokens[pos])
            end = guard_end(tokens, pos + 1)
            key = tuple(tokens[pos + 1 : end])
            cubes = guards.get(key)
            if cubes is None:
                cubes, after = parse_guard(tokens, pos + 1)
                assert after == end
                guards[key] = cubes
            pos = end
            transitions.append((dest, cubes))
        pos += 1
        states[sid] = (frozenset(acc), transitions)
        if init == "1":
            if initial is not None:
                raise Undecided("lbt printed two initial states")
            initial = sid
    if pos != len(tokens):
        raise Undecided("lbt printed more than its automaton")
    used = set().union(*(acc for acc, _ in states.values())) if states else set()
    if len(used) > nsets:
        raise Undecided(f"lbt declared {nsets} acceptance sets and used {len(used)}")
    if nstates == 0 or len(used) < nsets:
        return None, {}, []  # no state, or an empty acceptance set: no accepting run
    if initial is None:
        raise Undecided("lbt printed no initial state")
    for _, transitions in states.values():
        for dest, _ in transitions:
            if dest not in states:
                raise Undecided(f"lbt printed a transition to unknown state {dest}")
    return initial, states, sorted(used)


def translate(prefix, timeout):
    try:
        done = subprocess.run(
            ["lbt"], input=prefix + "\n", capture_output=True, text=True, timeout=timeout
        )
    except FileNotFoundError:
        raise Undecided("lbt is missing: apt-get install -y lbt") from None
    except subprocess.TimeoutExpired:
        raise Undecided(f"lbt timed out after {timeout} s") from None
    if done.returncode != 0:
        raise Undecided(f"lbt failed (exit {done.returncode}): {done.stderr.strip()}")
    return parse_lbtt(done.stdout)


# ----------------------------------------------------------------------------- machine


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (OSError, ValueError) as e:
        raise Malformed(f"cannot read {path}: {e}") from None
    if not isinstance(doc, dict):
        raise Malformed("the document is not a JSON object")
    return doc


def load(path):
    doc = load_json(path)
    for key in ("verdict", "semantics", "inputs", "outputs", "ltl"):
        if key not in doc:
            raise Malformed(f"missing key {key!r}")
    inputs, outputs = doc["inputs"], doc["outputs"]
    if not all(isinstance(s, str) for s in inputs + outputs) or len(set(inputs + outputs)) != len(
        inputs + outputs
    ):
        raise Malformed("inputs and outputs must be distinct strings")
    if doc["semantics"] not in ("mealy", "moore"):
        raise Malformed(f"unknown semantics {doc['semantics']!r}")
    if not isinstance(doc["ltl"], str):
        raise Malformed("ltl must be a string")
    formula = parse_formula(doc["ltl"])
    unknown = atoms(formula) - set(inputs) - set(outputs)
    if unknown:
        raise Malformed(f"ltl names undeclared signals: {sorted(unknown)}")
    if doc["verdict"] == "realizable":
        machine, reads, writes = doc.get("mealy"), inputs, outputs
        kind = "controller"
    elif doc["verdict"] == "unrealizable":
        machine, reads, writes = doc.get("counterstrategy"), outputs, inputs
        kind = "counter-strategy"
    else:
        raise Malformed(f"unknown verdict {doc['verdict']!r}")
    if not isinstance(machine, dict) or "init" not in machine or "states" not in machine:
        raise Malformed(f"the {kind} (with init and states) is missing")
    states = machine["states"]
    if not isinstance(states, dict) or not states:
        raise Malformed("states must be a non-empty object")
    init = str(machine["init"])
    if init not in states:
        raise Malformed(f"initial state {init} is not among the states")
    rows = {}
    for name, state_rows in states.items():
        if not isinstance(state_rows, list) or not state_rows:
            raise Malformed(f"state {name} has no rows")
        parsed = []
        for row in state_rows:
            if not (isinstance(row, list) and len(row) == 3):
                raise Malformed(f"state {name}: a row is not [reads, next, writes]: {row!r}")
            guard, nxt, assign = row
            nxt = str(nxt)
            if nxt not in states:
                raise Malformed(f"state {name}: next state {nxt} does not exist")
            for part, allowed, what in ((guard, reads, "read"), (assign, writes, "written")):
                if not isinstance(part, dict) or not all(isinstance(v, bool) for v in part.values()):
                    raise Malformed(f"state {name}: {what} values must be an object of booleans")
                stray = set(part) - set(allowed)
                if stray:
                    raise Malformed(f"state {name}: {sorted(stray)} cannot be {what} here")
            parsed.append((guard, nxt, assign))
        check_rows(name, parsed, reads)
        rows[name] = parsed
    if kind == "controller" and doc["semantics"] == "moore":
        for name, state_rows in rows.items():
            if any(r[2] != state_rows[0][2] for r in state_rows):
                raise Malformed(f"Moore state {name}: the outputs depend on the inputs")
    if kind == "counter-strategy":
        moves_first = machine.get("moves_first")
        if moves_first is not (doc["semantics"] == "mealy"):
            raise Malformed(
                f"{doc['semantics']} semantics needs moves_first "
                f"{str(doc['semantics'] == 'mealy').lower()}, got {moves_first!r}"
            )
        if moves_first:
            for name, state_rows in rows.items():
                if any(r[2] != state_rows[0][2] for r in state_rows):
                    raise Malformed(f"state {name} moves first but its inputs depend on the outputs")
    return doc, formula, kind, init, rows


def check_rows(name, state_rows, reads):
    """Rows must be pairwise disjoint and together cover every valuation of `reads`."""
    for (i, a), (j, b) in itertools.combinations(enumerate(state_rows), 2):
        if merge(a[0], b[0]) is not None:
            raise Malformed(f"state {name}: rows {i} and {j} overlap on {merge(a[0], b[0])}")
    covered = sum(2 ** (len(reads) - len(r[0])) for r in state_rows)
    if covered != 2 ** len(reads):
        # disjoint rows, so the count is exact; name one valuation that is missing
        for values in itertools.product([False, True], repeat=len(reads)):
            valuation = dict(zip(reads, values))
            if not any(merge(r[0], valuation) is not None for r in state_rows):
                raise Malformed(f"state {name}: no row for {valuation}")


# ----------------------------------------------------------------------------- product


def search(init, rows, automata, signals):
    """Explore machine × automata; return a bad lasso (prefix, cycle) of edges or None.
    An edge is (product node (machine state, automaton states) before, letter {signal: bool} with opponent choices that no
    guard constrains set to false)."""
    index = {s: i for i, s in enumerate(signals)}
    if any(a[0] is None for a in automata):
        return None  # some conjunct is unsatisfiable
    requirements = [(k, s) for k, a in enumerate(automata) for s in a[2]]
    start = (init, tuple(a[0] for a in automata))
    succ = {}

    def bits(cube):
        """A cube {proposition: value} as (mask of the propositions it reads, their values)."""
        mask = value = 0
        for i, b in cube.items():
            mask |= 1 << i
            if b:
                value |= 1 << i
        return mask, value

    # Each automaton's transitions with their cubes as bit masks: two cubes agree when they give
    # no shared proposition different values, `(v1 ^ v2) & m1 & m2 == 0` (the dictionaries took
    # most of the search's time on the larger products).
    transitions = [
        {q: [(dest, [bits(c) for c in cubes]) for dest, cubes in state[1]] for q, state in a[1].items()}
        for a in automata
    ]

    def successors(node):
        if node in succ:
            return succ[node]
        mstate, qs = node
        out = {}
        for guard, nxt, assign in rows[mstate]:
            base = bits({index[s]: v for s, v in merge(guard, assign).items()})
            # One transition per automaton, automaton by automaton: a choice of transitions is
            # dropped as soon as its guards contradict (the full product of the automata's
            # transitions is far larger than its consistent part). Each (destinations so far,
            # letter so far) is kept once, in the order first found.
            partials = {((),) + base: None}
            for k, q in enumerate(qs):
                extended = {}
                for dests, mask, value in partials:
                    for dest, cubes in transitions[k][q]:
                        reached = dests + (dest,)
                        for cmask, cvalue in cubes:
                            if (value ^ cvalue) & mask & cmask == 0:
                                extended[(reached, mask | cmask, value | cvalue)] = None
                partials = extended
                if not partials:
                    break
            for dests, _, value in partials:
                target = (nxt, dests)
                if target not in out:
                    out[target] = {s: bool(value >> i & 1) for s, i in index.items()}
        succ[node] = list(out.items())
        return succ[node]

    def accepting(node, req):
        k, s = req
        return s in automata[k][1][node[1][k]][0]

    # Tarjan, iterative.
    order, low, on_stack, stack, counter = {}, {}, set(), [], 0
    order[start] = low[start] = counter
    counter += 1
    stack.append(start)
    on_stack.add(start)
    work = [(start, iter(successors(start)))]
    found = None
    while work and found is None:
        node, it = work[-1]
        advanced = False
        for target, _ in it:
            if target not in order:
                order[target] = low[target] = counter
                counter += 1
                stack.append(target)
                on_stack.add(target)
                work.append((target, iter(successors(target))))
                advanced = True
                break
            if target in on_stack:
                low[node] = min(low[node], order[target])
        if advanced:
            continue
        work.pop()
        if work:
            parent = work[-1][0]
            low[parent] = min(low[parent], low[node])
        if low[node] == order[node]:
            component = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.add(member)
                if member == node:
                    break
            nontrivial = len(component) > 1 or any(t == node for t, _ in successors(node))
            if nontrivial and all(
                any(accepting(m, req) for m in component) for req in requirements
            ):
                found = component
    if found is None:
        return None

    def bfs(sources, goal, within):
        """Shortest continuation of one of `sources` ((node, edges so far) pairs) to a node
        satisfying `goal`, staying inside `within` (None: anywhere)."""
        queue, seen = deque(sources), {node for node, _ in sources}
        while queue:
            node, edges = queue.popleft()
            if goal(node):
                return node, edges
            for target, letter in successors(node):
                if (within is None or target in within) and target not in seen:
                    seen.add(target)
                    queue.append((target, edges + [(node, letter)]))
        raise Undecided("internal: no path where Tarjan found one")

    entry, prefix = bfs([(start, [])], lambda n: n in found, None)
    node, cycle = entry, []
    for req in requirements:
        node, cycle = bfs([(node, cycle)], lambda n, r=req: accepting(n, r), found)
    # back to the entry, with at least one edge
    first = [(t, cycle + [(node, letter)]) for t, letter in successors(node) if t in found]
    _, cycle = bfs(first, lambda n: n == entry, found)
    return prefix, cycle


# ----------------------------------------------------------------------------- main


def main(argv):
    split_only, timeout, args = False, 30.0, []
    it = iter(argv)
    for arg in it:
        if arg == "--split":
            split_only = True
        elif arg == "--lbt-timeout":
            timeout = float(next(it, "30"))
        else:
            args.append(arg)
    if len(args) != 1:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        return 2
    try:
        doc, formula, kind, init, rows = load(args[0])
    except Malformed as e:
        print(f"malformed: {e}", file=sys.stderr)
        return 2
    signals = doc["inputs"] + doc["outputs"]
    index = {s: i for i, s in enumerate(signals)}
    bad = ("!", formula) if kind == "controller" else formula
    cache = {}

    def automaton(ast):
        prefix = to_lbt(ast, index)
        if prefix not in cache:
            cache[prefix] = translate(prefix, timeout)
        return cache[prefix]

    try:
        plans = None
        if not split_only:
            # Where the formula splits, the whole-formula translation only gets a short try:
            # lbt spends seconds on a long conjunction before it crashes on it, and the split
            # check decides the same words (above). Where it does not split, it gets them all.
            whole_timeout = timeout if split_top(bad) == [[bad]] else min(timeout, WHOLE_TRY_SECONDS)
            try:
                prefix = to_lbt(bad, index)
                if prefix not in cache:
                    cache[prefix] = translate(prefix, whole_timeout)
                plans = [[cache[prefix]]]
            except Undecided as e:
                print(f"note: whole formula: {e}; splitting it", file=sys.stderr)
        if plans is None:
            plans = [[automaton(c) for c in conj] for conj in split_top(bad)]
        for automata in plans:
            lasso = search(init, rows, automata, signals)
            if lasso is None:
                continue
            if not split_only and len(plans) == 1 and not lasso_has_truth(formula, kind, lasso):
                # lbt's automaton of the whole formula accepted a word the formula rejects
                # (seen on the refined fig. 1 specification): its automaton is wrong, so the
                # check starts again on the conjuncts, whose automata are smaller.
                print("note: whole formula: lbt's automaton accepts a wrong word; splitting it", file=sys.stderr)
                return check_split(doc, formula, kind, init, rows, signals, automaton, bad)
            return report(doc, formula, kind, lasso)
    except Undecided as e:
        print(f"undecided: {e}", file=sys.stderr)
        return 3
    print("ok")
    return 0


def lasso_has_truth(formula, kind, lasso):
    """Whether the lasso's word gives the formula the truth value a violation needs."""
    prefix, cycle = lasso
    letters = [letter for _, letter in prefix + cycle]
    return evaluate_lasso(formula, letters, len(prefix))[0] == (kind == "counter-strategy")


def check_split(doc, formula, kind, init, rows, signals, automaton, bad):
    """The check on the conjuncts of the split formula alone."""
    for automata in [[automaton(c) for c in conj] for conj in split_top(bad)]:
        lasso = search(init, rows, automata, signals)
        if lasso is not None:
            return report(doc, formula, kind, lasso)
    print("ok")
    return 0


def report(doc, formula, kind, lasso):
    prefix, cycle = lasso
    if not lasso_has_truth(formula, kind, lasso):
        print("undecided: internal: the lasso found does not have the truth value it should")
        return 3
    what = (
        "the controller lets the environment produce a word that violates the specification"
        if kind == "controller"
        else "a controller can play against the counter-strategy a word that satisfies the "
        "specification"
    )
    print(f"VIOLATION ({doc['semantics']} {kind}): {what}:")
    print(f"  ltl: {doc['ltl']}")
    for title, edges in (("prefix", prefix), ("cycle (repeated forever)", cycle)):
        print(f"  {title}:")
        if not edges:
            print("    (empty)")
        for (state, _), letter in edges:
            ins = " ".join(f"{s}={int(letter[s])}" for s in doc["inputs"])
            outs = " ".join(f"{s}={int(letter[s])}" for s in doc["outputs"])
            print(f"    state {state}: inputs [{ins}] outputs [{outs}]")
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
