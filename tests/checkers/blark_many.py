"""Parses many files with blark in one process (its start-up and grammar build cost about a
second, more than parsing a file). Usage: blark_many.py FILE...; prints each failure and exits
with status 1 if any file does not parse."""
import sys
from blark.parse import parse

failed = 0
for path in sys.argv[1:]:
    for result in parse(path):
        if result.exception is not None:
            failed += 1
            print(f"{path}: {result.exception}")
sys.exit(1 if failed else 0)
