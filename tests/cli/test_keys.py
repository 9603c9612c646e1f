#!/usr/bin/python3
"""The deck key reference against the binary (issue 61, item 5).

1. decks/keys.md is exactly `spall keys --markdown` (regenerate it with
   `build/ci/spall keys --markdown > decks/keys.md`).
2. `spall keys` prints one line per key of the page, each beginning with the key's dotted path,
   and `spall keys PREFIX` the lines whose path begins so.
3. The defaults are the reader's: for every key a table gives a literal default (a number, a
   boolean, a quoted string) and one of the decks below leaves out, the deck run a few steps with
   `--set KEY=DEFAULT` for every such key at once gives the same particles bit for bit as without
   them (when it does not, one run per key names the default that differs). A documented default
   that is not the one the code uses changes at least one bit of some field (or the run fails),
   where the key acts within those steps: a wrong artificial_stress.epsilon is caught, a wrong
   h_max_ratio or crack_speed (they act once h has grown, or a crack has started) is not.
4. The bounds are the reader's: every numeric key whose table gives a numeric bound ("> 0",
   ">= 1", "<= 0", "[0, 1]", "(0, 1]") is refused by `spall check` (exit 2, naming the key) just
   outside it, and on it where it is open.
Each key is checked once, on the first deck below that holds its table (and its type). A key
whose bounds say "not with OTHER" is left out of 3. where the table holds OTHER.

The runs are one after another, so they use Open MPI's isolated singletons (no support daemon,
a third of each start): only concurrent ones collide (tests/cli/test_concurrent_runs.py).

usage: test_keys.py SPALL_BINARY SOURCE_DIR
"""
import os
import re
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

SPALL, SRC = sys.argv[1], Path(sys.argv[2])
ENV = dict(os.environ, OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1")
STEPS = 3
# Decks whose sections and model types between them hold most keys: solids with Johnson-Cook
# strength and a wall (rz), Grady-Kipp damage, P-alpha porosity, the cap model, MPM.
DECKS = ["taylor_bar_rz.toml", "spall_plate_1d.toml", "porous_aluminium_hugoniot_1d.toml",
         "sandstone_confined_2d.toml", "vibrating_bar_mpm_1d.toml", "sod_1d.toml",
         "taylor_bar_za_rz.toml"]
# Sections whose keys write outputs, not particles: not compared here (tests/cli/test_reference.py
# checks the outputs).
OUTPUT_SECTIONS = ("output", "checkpoint", "probe", "fragments", "penetration")
ARRAYS = ("material", "body", "boundary", "energy_source", "probe", "jet")
failures = []


def check(cond, message):
    print(("ok   " if cond else "FAIL ") + message)
    if not cond:
        failures.append(message)


def spall(*args):
    return subprocess.run([SPALL, *args], capture_output=True, text=True, env=ENV,
                          stdin=subprocess.DEVNULL)


def parse_page(text):
    """[(section path, type or None, key, type, default, unit, bounds)] from the markdown."""
    rows, path, typ = [], None, None
    for line in text.splitlines():
        m = re.match(r"## (.*)$", line)
        if m:
            h = m.group(1)
            mm = re.match(r'([a-z_.]+)(?: \(type = "([a-z_]+)"\))?$', h)
            path, typ = ("", None) if h == "The top level" else (mm.group(1), mm.group(2))
            continue
        m = re.match(r"\| `([^`]+)` \| (.*) \|$", line)
        if m:
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", m.group(2))]
            key = m.group(1)[len(path) + 1:] if path else m.group(1)
            rows.append((path, typ, key, *cells[:4]))
    return rows


# 1. The page.
page = spall("keys", "--markdown")
check(page.returncode == 0, "spall keys --markdown exits 0")
shipped = (SRC / "decks" / "keys.md").read_text()
check(page.stdout == shipped, "decks/keys.md is `spall keys --markdown` (regenerate it if not)")
rows = parse_page(page.stdout)
check(len(rows) > 200, f"the page lists {len(rows)} keys")

# 2. The lines.
lines = spall("keys").stdout.splitlines()
paths = [(p + "." if p else "") + k for p, _, k, *_ in rows]
check(len(lines) == len(rows), f"spall keys: {len(lines)} lines for the page's {len(rows)} keys")
check(all(line.split()[0] == path for line, path in zip(lines, paths)),
      "each line begins with the key's dotted path, in the page's order")
sub = spall("keys", "material.strength.").stdout.splitlines()
want = [p for p in paths if p.startswith("material.strength.")]
check([s.split()[0] for s in sub] == want,
      f"spall keys material.strength.: the {len(want)} lines whose path begins so")
bad = spall("keys", "no_such_section")
check(bad.returncode == 2 and "no deck key" in bad.stderr, "an unknown prefix: exit 2, said so")

# Sections with a required key of their own (not a typed table's).
REQUIRED_IN = {p for p, typ, _, _, default, *_ in rows if default == "required" and typ is None}
LITERAL = re.compile(r'^(-?[0-9][0-9.e+-]*|true|false|"[^"]*")$')


def entries(deck, section):
    """The --set prefixes of a section's tables in the deck, with each table's contents."""
    parts = section.split(".")
    out = [("", deck)]
    for i, part in enumerate(parts):
        nxt = []
        for prefix, table in out:
            v = table.get(part)
            if v is None:
                # A table the deck leaves out, `--set` makes: its keys take their defaults. Not
                # an entry of an array, a typed table (its type is needed) or [solver.mpm] of a
                # deck of another method.
                typed = section in ("material.eos", "material.strength", "material.damage",
                                    "material.porosity", "body.shape")
                mpm = deck.get("solver", {}).get("method") == "mpm"
                # Nor a table with keys of its own that are required (body.grading): `--set`
                # of its defaults alone cannot make it whole.
                partial = ".".join(parts[:i + 1]) in REQUIRED_IN
                if (i == 0 and part in ARRAYS) or typed or (part == "mpm" and not mpm) or partial:
                    continue
                v = {}
            if i == 0 and part in ARRAYS:
                for k, t in enumerate(v):
                    label = t.get("name") if part in ("material", "body", "probe", "jet") else None
                    nxt.append((f"{part}.{label or k + 1}", t))
            else:
                nxt.append((prefix + ("." if prefix else "") + part, v))
        out = nxt
    return [(p, t) for p, t in out if isinstance(t, dict)]


def runs_same(deck_path, sets, tmp, tag):
    base = Path(tmp) / "base"
    if not base.exists():
        r = spall("run", str(deck_path), "--output", str(base), "--quiet",
                  "--set", f"run.max_steps={STEPS}")
        if r.returncode != 0:
            return f"the deck itself failed: {r.stderr[-300:]}"
    out = Path(tmp) / tag
    r = spall("run", str(deck_path), "--output", str(out), "--quiet",
              "--set", f"run.max_steps={STEPS}", *[a for s in sets for a in ("--set", s)])
    if r.returncode != 0:
        return f"exit {r.returncode}: {r.stderr.strip()[-300:]}"
    c = subprocess.run([str(SRC / "tools" / "compare_snapshots"), str(base), str(out)],
                       capture_output=True, text=True)
    return None if c.returncode == 0 else c.stdout.strip().splitlines()[-1]


NUMBER = r"(-?[0-9.]+(?:e-?[0-9]+)?)"


def outside_values(bound):
    """Values just outside a numeric bound ("> 0", ">= 1", "<= 0", "[0, 1]", "(0, 1]"), on it
    where it is open; [] for a bound by other keys or in words."""
    fmt = lambda x: repr(float(x))
    if m := re.fullmatch(r"(>=|>|<=|<) " + NUMBER, bound):
        op, a = m.group(1), float(m.group(2))
        return {">": [fmt(a - 1), fmt(a)], ">=": [fmt(a - 1)], "<": [fmt(a + 1), fmt(a)],
                "<=": [fmt(a + 1)]}[op]
    if m := re.fullmatch(r"([\[(])" + NUMBER + ", " + NUMBER + r"([\])])", bound):
        lo, a, b, hi = m.group(1), float(m.group(2)), float(m.group(3)), m.group(4)
        return ([fmt(a - 1)] + ([fmt(a)] if lo == "(" else []) + [fmt(b + 1)]
                + ([fmt(b)] if hi == ")" else []))
    return []


# 3. and 4., deck by deck.
defaults_checked = bounds_checked = 0
done_default, done_bounds = set(), set()  # (section, type, key) checked already
for name in DECKS:
    deck_path = SRC / "decks" / name
    deck = tomllib.loads(deck_path.read_text())
    pending = []  # the deck's defaults to give explicitly
    with tempfile.TemporaryDirectory() as tmp:
        for path, typ, key, vtype, default, unit, bounds in rows:
            if not path or path.split(".")[0] in OUTPUT_SECTIONS:
                continue
            for prefix, table in entries(deck, path):
                if typ is not None and table.get("type") != typ:
                    continue
                id_ = (path, typ, key)
                dotted = f"{prefix}.{key}"
                numeric_bound = bounds.split(";")[0].strip()
                excluded = any(other in table for other in re.findall(r"not with (\w+)", bounds))
                if (key not in table and LITERAL.match(default) and vtype != "table"
                        and not excluded and id_ not in done_default):
                    done_default.add(id_)
                    pending.append(f"{dotted}={default}")
                outside = outside_values(numeric_bound)
                if outside and vtype in ("float", "integer") and id_ not in done_bounds:
                    done_bounds.add(id_)
                    for v in outside:
                        r = spall("check", str(deck_path), "--set", f"{dotted}={v}")
                        bounds_checked += 1
                        if not (r.returncode == 2 and key in r.stderr):
                            check(False, f"{name}: {dotted} = {v} against '{numeric_bound}': exit "
                                         f"{r.returncode}, {r.stderr.strip()[-200:]}")
        # All of a deck's defaults in one run; only when that run differs (or two of them cannot
        # go together), one run per key, to name the default that changes the run.
        defaults_checked += len(pending)
        if pending and runs_same(deck_path, pending, tmp, "all"):
            for i, s in enumerate(pending):
                why = runs_same(deck_path, [s], tmp, f"d{i}")
                if why:
                    check(False, f"{name}: {s} (the documented default) changes the run: {why}")
check(defaults_checked >= 30, f"{defaults_checked} documented defaults given explicitly change "
                              "no bit of any particle")
check(bounds_checked >= 40, f"{bounds_checked} values outside the documented bounds refused")

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
