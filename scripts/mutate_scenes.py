#!/usr/bin/env python3
"""Mutates the repository's scenes one line at a time and runs `trample check`
and `trample simulate --frames 3` on each mutant, looking for what a user's
bad scene could do that an error message should have caught: a panic (the
CLI's "internal error ... please report it"), an exit status other than
0, 1 or 2, or a run that does not finish in time (RELIABILITY.md, "Mutated
scenes and flags").

Each mutant changes one line of one scene: a number replaced by NaN, inf,
0, a negative, a huge or a tiny value or one past u32/u64; a string by an
empty one, a missing file or a path out of the folder; an array by one of
another length or of other values; the line deleted or repeated. Seeded:
the same seed gives the same mutants.

Usage: scripts/mutate_scenes.py [--bin target/release/trample] [--seed N]
       [--count N] [--timeout S] [--backend cpu|gpu|auto]
(`--backend gpu` runs `simulate` on the GPU path; on a machine without a GPU
set `WGPU_BACKEND=gl` for llvmpipe.)
Prints one FOUND line a finding (the scene, the line, the mutant, the
command and its stderr's tail) and keeps the finding's folder under
/tmp/trample-mutants; exits 1 when something was found.
"""

import argparse
import os
import random
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "scenes")
NUMBERS = ["nan", "inf", "-inf", "-1", "0", "-0.0", "1e30", "-1e30", "1e-30",
           "4294967296", "2147483648", "18446744073709551616", "65537"]
STRINGS = ['""', '"nope"', '"../../etc/passwd"', '"meshes/missing.obj"', '"éé"']
ARRAYS = ["[]", "[1]", "[1, 2, 3, 4]", "[nan, nan]", "[1e9, 1e9]", "[0, 0]",
          "[-5, 3]", '["a", "b"]']
NUMBER = re.compile(r'(?<![\w."])(-?\d+(\.\d+)?([eE]-?\d+)?)(?![\w."])')


def mutate(lines, rng):
    """One mutant of `lines`: (text, line number, what was done) or None."""
    k = rng.randrange(len(lines))
    line = lines[k]
    op = rng.choice(["number", "number", "string", "array", "delete", "repeat"])
    if op == "number":
        found = list(NUMBER.finditer(line))
        if not found:
            return None
        m = rng.choice(found)
        line = line[:m.start()] + rng.choice(NUMBERS) + line[m.end():]
    elif op == "string":
        if '"' not in line:
            return None
        line = re.sub(r'"[^"]*"', rng.choice(STRINGS), line, count=1)
    elif op == "array":
        if not re.search(r"\[[^\[\]]*\]", line) or line.lstrip().startswith("["):
            return None
        line = re.sub(r"\[[^\[\]]*\]", rng.choice(ARRAYS), line, count=1)
    elif op == "delete":
        line = ""
    else:
        line = line + "\n" + line
    out = lines[:k] + [line] + lines[k + 1:]
    return "\n".join(out) + "\n", k + 1, f"{op}: {lines[k].strip()!r} -> {line.strip()[:80]!r}"


def run(binary, args, cwd, timeout):
    try:
        r = subprocess.run([binary] + args, cwd=cwd, capture_output=True,
                           text=True, timeout=timeout)
        return r.returncode, r.stderr
    except subprocess.TimeoutExpired:
        return "timeout", ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "target/release/trample"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--timeout", type=float, default=90.0)
    ap.add_argument("--backend", default="cpu", choices=["cpu", "gpu", "auto"])
    a = ap.parse_args()
    if not os.access(a.bin, os.X_OK):
        sys.exit(f"{a.bin}: not an executable (cargo build --release -p trample-cli)")
    rng = random.Random(a.seed)
    scenes = sorted(f for f in os.listdir(SCENES) if f.endswith(".toml"))
    # The herd's 16.8 M blades take minutes to build: its small cut stands in.
    scenes = [s for s in scenes if s != "herd.toml"]
    work = "/tmp/trample-mutants"
    os.makedirs(work, exist_ok=True)
    found = tried = 0
    while tried < a.count:
        name = rng.choice(scenes)
        lines = open(os.path.join(SCENES, name)).read().splitlines()
        mutant = mutate(lines, rng)
        if mutant is None:
            continue
        text, line, what = mutant
        tried += 1
        d = os.path.join(work, f"{a.seed}-{tried}")
        os.makedirs(d, exist_ok=True)
        for sub in ["meshes", "garden"]:
            link = os.path.join(d, sub)
            if not os.path.exists(link):
                os.symlink(os.path.join(SCENES, sub), link)
        with open(os.path.join(d, "s.toml"), "w") as f:
            f.write(text)
        simulate = ["simulate", "s.toml", "--frames", "3", "--out", "o", "--backend", a.backend]
        for args in (["check", "s.toml"], simulate):
            rc, err = run(a.bin, args, d, a.timeout)
            if rc == "timeout" or "internal error" in err or rc not in (0, 1, 2):
                found += 1
                tail = err[-400:].replace("\n", " | ")
                print(f"FOUND {name} line {line} ({what}) {args[0]}: {rc}: {tail}", flush=True)
                break
        else:
            shutil.rmtree(d)
    print(f"{tried} mutants, {found} found")
    sys.exit(1 if found else 0)


if __name__ == "__main__":
    main()
