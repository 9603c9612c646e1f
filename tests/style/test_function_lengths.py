#!/usr/bin/python3
"""No function in src/ or include/ longer than 150 lines, as universal-ctags measures them
(`--kinds-c++=f --fields=+ne`: from the line of the name to the closing brace). A function that
long interleaves what should be named steps of their own (the force loop was 420 lines).

usage: test_function_lengths.py SOURCE_DIR [LIMIT]
"""
import subprocess
import sys
from pathlib import Path

SRC = Path(sys.argv[1])
LIMIT = int(sys.argv[2]) if len(sys.argv) > 2 else 150

files = sorted(str(p) for d in ("src", "include") for p in (SRC / d).rglob("*")
               if p.suffix in (".cpp", ".hpp", ".h") and p.is_file())
out = subprocess.run(["ctags-universal", "--language-force=C++", "--kinds-C++=f", "--fields=+ne",
                      "-o", "-", *files], capture_output=True, text=True, check=True).stdout
lengths = []
for line in out.splitlines():
    cols = line.split("\t")
    fields = dict(c.split(":", 1) for c in cols[3:] if ":" in c)
    if "line" in fields and "end" in fields:
        lengths.append((int(fields["end"]) - int(fields["line"]) + 1, cols[0],
                        Path(cols[1]).relative_to(SRC), int(fields["line"])))
if len(lengths) < 500:  # the source has ~1,100 functions: ctags read too little
    sys.exit(f"ctags found only {len(lengths)} functions")
lengths.sort(reverse=True)
print("longest functions:")
for n, name, path, line in lengths[:5]:
    print(f"  {n:4d}  {name}  {path}:{line}")
over = [x for x in lengths if x[0] > LIMIT]
for n, name, path, line in over:
    print(f"FAIL {path}:{line}: {name} is {n} lines (at most {LIMIT})")
print(f"{len(lengths)} functions, {len(over)} over {LIMIT} lines")
sys.exit(1 if over else 0)
