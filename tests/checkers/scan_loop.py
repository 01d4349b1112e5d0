"""Runs an AWL program in awlsim as the PLC of a closed loop, one cycle per line of standard
input, on a virtual clock (tests/plc_realtime.rs drives it through a pipe).

Usage: scan_loop.py FILE.awl OUTPUT... (bit operands such as Q125.6 or M10.3)
Each input line is one cycle: the virtual time in microseconds, then the input bits to store
before the cycle, `I124.0=1` or `M10.2=0` (memory bits are changed bit by bit, so that the
outputs sharing their byte keep their values). After the cycle one line goes out: a 0 or 1 per
OUTPUT, in order; it is flushed at once. A line `reset` puts the CPU back in its initial
state (memory, process images, timers: `reallocate`) for the next run and the clock back to 0;
it answers `reset`. Errors go to stderr with exit status 1.

awlsim's S7 timers (`SD`) compare `cpu.now`, which `updateTimestamp` sets from the time function
replaced here: the clock stands still within a cycle and jumps to the line's time between
cycles. `cpu.now` carries an offset of about 2.1e6 s, where a double resolves about 5e-10 s, so
`start + preset` may round either side of a later `now` that equals it exactly; each cycle adds
1e-8 s of drift so that a deadline reached exactly counts as reached, as in the integer model of
the Rust side (for 10^5 cycles the drift stays at 1 ms, below the 10 ms steps of S5TIME).
"""
import functools
import sys
from awlsim.common.compat import *  # noqa: F401,F403 (awlsim's own set-up)
from awlsim.common.monotonic import monotonic_time
from awlsim.core.main import AwlSim
from awlsim.awlcompiler.tokenizer import AwlParser
from awlsim.common.sources import AwlSource


def operand(text):
    """`Q125.6` -> ('Q', 125, 6)."""
    area, rest = text[0], text[1:]
    byte, bit = rest.split(".")
    if area not in "IQM":
        sys.exit(f"scan_loop.py: unsupported operand {text!r}")
    return area, int(byte), int(bit)


parser = AwlParser()
parser.parseSource(AwlSource.fromFile("program", sys.argv[1]))
sim = AwlSim()
sim.load(parser.getParseTree())
sim.startup()
cpu = sim.getCPU()
base = monotonic_time()
clock = [base]
cpu.updateTimestamp = functools.partial(type(cpu).updateTimestamp, cpu, _getTime=lambda: clock[0])
outputs = [operand(o) for o in sys.argv[2:]]
cycles = 0
areas = {"I": cpu.inputs, "Q": cpu.outputs, "M": cpu.flags}
for line in sys.stdin:
    words = line.split()
    if not words:
        continue
    if words == ["reset"]:
        cpu.reallocate(force=True)
        areas = {"I": cpu.inputs, "Q": cpu.outputs, "M": cpu.flags}
        base = monotonic_time()
        cycles = 0
        sys.stdout.write("reset\n")
        sys.stdout.flush()
        continue
    cycles += 1
    clock[0] = base + int(words[0]) / 1e6 + cycles * 1e-8
    for word in words[1:]:
        name, value = word.split("=")
        area, byte, bit = operand(name)
        raw = areas[area].getRawDataBytes()
        raw[byte] = (raw[byte] & ~(1 << bit)) | (int(value) << bit)
    sim.runCycle()
    bits = "".join(str(areas[a].getRawDataBytes()[byte] >> bit & 1) for a, byte, bit in outputs)
    sys.stdout.write(bits + "\n")
    sys.stdout.flush()
