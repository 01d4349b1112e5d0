"""Runs an AWL program in awlsim on a virtual clock, cycle by cycle, and reports named fields
of one data block after each cycle (tests/ltl_timed_loop.rs).

Usage: timed_run.py FILE.awl DB FIELD... < SCRIPT
Each script line is one PLC cycle; its words, in any order:
  `T50`      lets 50 ms pass on the CPU's clock before the cycle (the clock otherwise stands
             still, so SFB 4 sees exactly the time the script says),
  `I3=17`    stores 17 into input byte 3 before the cycle.
One line is printed per cycle: the fields' values after it, read by name from awlsim's own
layout of the data block (BOOL as 0/1, INT signed, TIME in ms), then output byte 0 and 1 as
`Q=<hex>`. Errors go to stderr with exit status 1.
"""
import functools
import sys
from awlsim.common.compat import *  # noqa: F401,F403 (awlsim's own set-up)
from awlsim.common.monotonic import monotonic_time
from awlsim.core.main import AwlSim
from awlsim.core.memory import AwlMemoryObject_asScalar
from awlsim.awlcompiler.tokenizer import AwlParser
from awlsim.common.sources import AwlSource

parser = AwlParser()
parser.parseSource(AwlSource.fromFile("program", sys.argv[1]))
sim = AwlSim()
sim.load(parser.getParseTree())
sim.startup()
cpu = sim.getCPU()
clock = [monotonic_time()]
cpu.updateTimestamp = functools.partial(type(cpu).updateTimestamp, cpu, _getTime=lambda: clock[0])
db = cpu.getDB(int(sys.argv[2]))
instance = db.structInstance
fields = []
for name in sys.argv[3:]:
    field = instance._struct.getField(name)
    fields.append((field, str(field.dataType)))
out = []
for line in sys.stdin:
    for word in line.split():
        if word.startswith("T"):
            clock[0] += int(word[1:]) / 1000.0
        elif word.startswith("I"):
            byte, value = word[1:].split("=")
            cpu.storeInputByte(int(byte), int(value))
        else:
            sys.exit(f"timed_run.py: unknown word {word!r}")
    sim.runCycle()
    values = []
    for field, ty in fields:
        v = AwlMemoryObject_asScalar(instance.getFieldData(field, None))
        if ty == "INT" and v >= 0x8000:
            v -= 0x10000
        elif ty in ("TIME", "DINT") and v >= 0x80000000:
            v -= 0x100000000
        values.append(str(v))
    values.append("Q=" + bytes(cpu.outputs.getRawDataBytes()[0:2]).hex())
    out.append(" ".join(values))
print("\n".join(out))
