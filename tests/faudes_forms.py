"""libFAUDES's own writing and reading of .gen files, for tests/sct_gen_files.rs.

Usage:
  faudes_forms.py write DIR    writes generators in the forms libFAUDES writes: native (Write)
                               and XML (XWrite), with empty sections, attributes, state names,
                               name#index, consecutive ranges, large generators
  faudes_forms.py read FILE... prints one JSON object per line: the generator libFAUDES reads
                               from FILE as a System (states by name, or by index if unnamed)
"""
import json
import os
import sys

import faudes


def system(events, states, trans, init=(), marked=(), name=None):
    """events: [(name, flags)] with flags from 'C' (controllable), 'o' (unobservable),
    'F' (forcible), 'P' (preemptible); states: names or None (anonymous)."""
    g = faudes.System()
    if name is not None:
        g.Name(name)
    for e, flags in events:
        g.InsEvent(e)
        if "C" in flags:
            g.SetControllable(e)
        if "o" in flags:
            g.ClrObservable(e)
        if "F" in flags:
            g.SetForcible(e)
        if "P" in flags:
            g.SetPreemptible(e)
    idx = [g.InsState(s) if s is not None else g.InsState() for s in states]
    for a, e, b in trans:
        g.SetTransition(idx[a], g.EventIndex(e), idx[b])
    for s in init:
        g.SetInitState(idx[s])
    for s in marked:
        g.SetMarkedState(idx[s])
    return g, idx


def forms():
    out = {}
    out["empty_generator"] = faudes.Generator()
    e = faudes.System()
    e.Name("empty system")
    out["empty_system"] = e
    out["states_only"], _ = system([("a", "")], [None, None], [])
    out["no_events"], _ = system([], ["idle", "busy"], [], init=[0], marked=[1])
    out["no_marked"], _ = system([("a", "C"), ("b", "")], [None, None], [(0, "a", 1), (1, "b", 0)], init=[0])
    out["no_init"], _ = system([("a", "C"), ("b", "")], [None, None], [(0, "a", 1), (1, "b", 0)], marked=[1])
    out["attributes"], _ = system(
        [("start", "C"), ("stop", "CF"), ("hidden", "o"), ("forced", "F"), ("preempt", "P"), ("plain", "")],
        ["idle", "run"],
        [(0, "start", 1), (1, "stop", 0), (1, "hidden", 1), (0, "forced", 0), (0, "preempt", 1), (1, "plain", 1)],
        init=[0],
        marked=[0],
        name="attributes",
    )
    # Deleting a state leaves a hole in the indices: named states are written as name#index.
    g, idx = system([("a", "C"), ("b", "")], ["p", "q", "r", "s"], [(0, "a", 1), (1, "b", 3), (3, "a", 0)], init=[0], marked=[3])
    g.DelState(idx[2])
    out["named_with_hole"] = g
    g, idx = system([("a", "")], [None] * 6, [(0, "a", 5), (5, "a", 4)], init=[0], marked=[4])
    g.DelState(idx[2])
    out["anonymous_with_hole"] = g
    # More than six anonymous states in a row are written as a <Consecutive> range.
    n = 20
    out["consecutive"], _ = system(
        [("a", "C"), ("u", "")],
        [None] * n,
        [(i, "a", i + 1) for i in range(n - 1)] + [(n - 1, "u", 0)],
        init=[0],
        marked=list(range(5, 15)),
    )
    # From 100 states on, <TransRel> refers to named states by index.
    n = 120
    out["large_named"], _ = system(
        [("a", "C"), ("b", "")],
        ["n%d" % i for i in range(n)],
        [(i, "a", (i + 1) % n) for i in range(n)] + [(i, "b", 0) for i in range(0, n, 7)],
        init=[0],
        marked=[0, 60],
    )
    plant, _ = system([("a", "C"), ("b", "")], ["idle", "busy"], [(0, "a", 1), (1, "b", 0)], init=[0], marked=[0])
    spec, _ = system([("a", ""), ("b", "")], ["x"], [(0, "a", 0), (0, "b", 0)], init=[0], marked=[0])
    sup = faudes.Generator()
    faudes.SupCon(plant, spec, sup)
    out["supcon_result"] = sup
    # libFAUDES stores nondeterministic generators; plcsynth refuses them.
    out["nondeterministic"], _ = system([("a", "C")], ["p", "q", "r"], [(0, "a", 1), (0, "a", 2)], init=[0])
    out["two_initial"], _ = system([("a", "C")], ["p", "q"], [(0, "a", 1)], init=[0, 1])
    return out


def write(d):
    os.makedirs(d, exist_ok=True)
    for name, g in forms().items():
        g.Write(os.path.join(d, "native_%s.gen" % name))
        g.XWrite(os.path.join(d, "xml_%s.gen" % name))
    # Written under another label: libFAUDES reads it back only when told the label.
    g, _ = system([("a", "C")], ["p"], [(0, "a", 0)], init=[0], marked=[0])
    g.Write(os.path.join(d, "native_labelled.gen"), "Plant")


def describe(g):
    label = lambda s: g.StateName(s) or str(s)
    trans = []
    it, end = g.TransRelBegin(), g.TransRelEnd()
    while it != end:
        trans.append([label(it.X1()), g.EventName(it.Ev()), label(it.X2())])
        it.Inc()
    alphabet = [g.EventName(e) for e in g.Alphabet()]
    return {
        "ok": True,
        "states": sorted(label(s) for s in g.States()),
        "init": sorted(label(s) for s in g.InitStates()),
        "marked": sorted(label(s) for s in g.MarkedStates()),
        "alphabet": sorted(alphabet),
        "controllable": sorted(e for e in alphabet if g.Controllable(e)),
        "transitions": sorted(trans),
        "deterministic": faudes.IsDeterministic(g),
    }


def read(files):
    for f in files:
        try:
            v = describe(faudes.System(f))
        except Exception as e:  # libFAUDES reports every read error as an exception
            v = {"ok": False, "error": str(e).splitlines()[0]}
        v["file"] = f
        print(json.dumps(v), flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2])
    else:
        read(sys.argv[2:])
