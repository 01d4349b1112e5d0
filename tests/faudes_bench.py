"""Times libFAUDES SupCon on a plant/spec pair: faudes_bench.py PLANT SPEC RUNS.

Prints one JSON line: median milliseconds (file reading excluded) and the result's size.
"""
import json
import sys
import time

import faudes


def main():
    plant = faudes.System(sys.argv[1])
    spec = faudes.Generator(sys.argv[2])
    runs = int(sys.argv[3])
    times = []
    res = None
    for _ in range(runs):
        res = faudes.Generator()
        t = time.perf_counter()
        faudes.SupCon(plant, spec, res)
        times.append((time.perf_counter() - t) * 1000.0)
    times.sort()
    print(json.dumps({"ms": times[len(times) // 2], "states": res.Size(), "transitions": res.TransRelSize()}))


if __name__ == "__main__":
    main()
