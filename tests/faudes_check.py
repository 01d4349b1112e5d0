"""Independent check of plcsynth's SupCon against libFAUDES.

Usage: faudes_check.py MANIFEST
MANIFEST lists one case directory per line; each holds plant.gen, spec.gen, sup.gen (our
supremal controllable nonblocking supervisor) and supc.gen (our supremal controllable closed
sublanguage). Prints one JSON object per case, and writes libFAUDES's own files into each
case directory: lf_plant.gen, lf_spec.gen, lf_sup.gen (libFAUDES's SupCon), lf_supc.gen
(SupConClosed), with Write in even cases and XWrite in odd ones, for plcsynth to read back.
"""
import json
import os
import sys

import faudes


def marked_all(g):
    h = faudes.Generator(g)
    h.InjectMarkedStates(h.States())
    return h


def main():
    with open(sys.argv[1]) as f:
        dirs = [l.strip() for l in f if l.strip()]
    for i, d in enumerate(dirs):
        plant = faudes.System(os.path.join(d, "plant.gen"))
        spec = faudes.Generator(os.path.join(d, "spec.gen"))
        ours = faudes.Generator(os.path.join(d, "sup.gen"))
        ours_c = faudes.Generator(os.path.join(d, "supc.gen"))
        ref = faudes.Generator()
        faudes.SupCon(plant, spec, ref)
        ref_c = faudes.Generator()
        faudes.SupConClosed(plant, spec, ref_c)
        ref_min = faudes.Generator()
        faudes.StateMin(ref, ref_min)
        out = {
            "dir": d,
            "marked_eq": faudes.LanguageEquality(ref, ours),
            "closure_eq": faudes.LanguageEquality(marked_all(ref), marked_all(ours)),
            "faudes_min_states": ref_min.Size(),
            "faudes_states": ref.Size(),
            "closed_gen_eq": faudes.LanguageEquality(marked_all(ref_c), marked_all(ours_c)),
            "closed_marked_eq": faudes.LanguageEquality(ref_c, ours_c),
        }
        for name, g in [("plant", plant), ("spec", spec), ("sup", ref), ("supc", ref_c)]:
            path = os.path.join(d, "lf_%s.gen" % name)
            if i % 2 == 0:
                g.Write(path)
            else:
                g.XWrite(path)
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
