"""Runs an AWL program in awlsim, one PLC cycle per line of a script.

Usage: awl_run.py FILE.awl SCRIPT
SCRIPT lines: `IBYTE=VALUE ...` assignments of input bytes before the cycle; the output bytes
named with `?QBYTE` are printed after it, one line per cycle: `Q125=64`. An empty script runs
20 cycles with all inputs 0 and prints nothing (a load-and-run check).
"""
import sys
from awlsim.common.compat import *  # noqa: F401,F403 (awlsim's own set-up)
from awlsim.core.main import AwlSim
from awlsim.awlcompiler.tokenizer import AwlParser
from awlsim.common.sources import AwlSource

path, script = sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else ""
parser = AwlParser()
parser.parseSource(AwlSource.fromFile("program", path))
sim = AwlSim()
sim.load(parser.getParseTree())
sim.startup()
cpu = sim.getCPU()
lines = [l for l in script.split(";") if l.strip()] or [""] * 20
for line in lines:
    reads = []
    for word in line.split():
        if word.startswith("?Q"):
            reads.append(int(word[2:]))
        else:
            byte, value = word.split("=")
            cpu.storeInputByte(int(byte[1:]), int(value))
    sim.runCycle()
    if reads:
        print(" ".join(f"Q{b}={cpu.fetchOutputRange(b, 1)[0]}" for b in reads))
