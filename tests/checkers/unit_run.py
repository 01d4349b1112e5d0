"""Runs an AWL program in awlsim cycle by cycle, driven by a script on stdin.

Usage: unit_run.py FILE.awl [--virtual-time] < SCRIPT
Each script line is one PLC cycle; its words, in any order:
  `I3=17`          stores 17 into input byte 3 before the cycle,
  `M500=3`         stores 3 into memory byte 500 before the cycle,
  `S50`            sleeps 50 ms before the cycle (awlsim's timers read the real clock),
  `T50`            with --virtual-time: lets 50 ms pass on the CPU's clock, which otherwise
                   stands still (so timers see exactly the time a test says),
  `?DB2:0:14`      after the cycle, reads 14 bytes of DB 2 from byte 0,
  `?Q0:2` `?M0:4`  reads output or memory bytes.
One line is printed per cycle: the reads in hex, separated by spaces, in script order.
Errors (parsing, loading, running) go to stderr with exit status 1.
"""
import sys
import time
from awlsim.common.compat import *  # noqa: F401,F403 (awlsim's own set-up)
from awlsim.core.main import AwlSim
from awlsim.awlcompiler.tokenizer import AwlParser
from awlsim.common.sources import AwlSource

parser = AwlParser()
parser.parseSource(AwlSource.fromFile("program", sys.argv[1]))
sim = AwlSim()
sim.load(parser.getParseTree())
sim.startup()
cpu = sim.getCPU()
virtual = None
if "--virtual-time" in sys.argv[2:]:
    # awlsim reads the time through S7CPU.updateTimestamp(_getTime=monotonic_time); a clock of
    # our own, advanced only by `T` words, makes SFB 4 deterministic.
    import functools
    from awlsim.common.monotonic import monotonic_time
    virtual = [monotonic_time()]
    cpu.updateTimestamp = functools.partial(type(cpu).updateTimestamp, cpu, _getTime=lambda: virtual[0])
out = []
for line in sys.stdin:
    reads = []
    for word in line.split():
        if word.startswith("?"):
            if word.startswith("?DB"):
                area, offset, length = word[1:].split(":")
            else:
                area = word[1]
                offset, length = word[2:].split(":")
            reads.append((area, int(offset), int(length)))
        elif word.startswith("S"):
            time.sleep(int(word[1:]) / 1000.0)
        elif word.startswith("T") and virtual is not None:
            virtual[0] += int(word[1:]) / 1000.0
        elif word.startswith("M"):
            byte, value = word[1:].split("=")
            cpu.flags.getRawDataBytes()[int(byte)] = int(value)
        elif word.startswith("I"):
            byte, value = word[1:].split("=")
            cpu.storeInputByte(int(byte), int(value))
        else:
            sys.exit(f"unit_run.py: unknown word {word!r}")
    sim.runCycle()
    values = []
    for area, offset, length in reads:
        if area.startswith("DB"):
            data = cpu.getDB(int(area[2:])).structInstance.memory.getRawDataBytes()
        elif area == "Q":
            data = cpu.outputs.getRawDataBytes()
        elif area == "M":
            data = cpu.flags.getRawDataBytes()
        else:
            sys.exit(f"unit_run.py: unknown area {area!r}")
        values.append(bytes(data[offset:offset + length]).hex())
    out.append(" ".join(values))
print("\n".join(out))
