#!/usr/bin/env python3
"""Checks that two sweep directories hold the same results, e.g. one made by
`make -j` and one by a Slurm job array (SWEEP_ENGINE=slurm):
    compare-sweeps.py build/sweep-local build/sweep-slurm
Every point and area JSON must be equal except wall-clock `seconds` and the
paths that name the sweep directory; every hits CSV must be byte-identical.
Exit status 1 on any difference, naming the file and the field."""
import json, pathlib, sys

def norm(o, root):
    if isinstance(o, dict):
        return {k: norm(v, root) for k, v in o.items() if k != "seconds"}
    if isinstance(o, list):
        return [norm(v, root) for v in o]
    if isinstance(o, str):
        return o.replace(root, "<sweep>")
    return o

def main(a, b):
    a, b = pathlib.Path(a), pathlib.Path(b)
    bad = 0
    files = sorted(p.relative_to(a) for p in a.glob("points/*.json")) + \
            sorted(p.relative_to(a) for p in a.glob("area/*.json"))
    hits = sorted(p.relative_to(a) for p in a.glob("hits/**/*.csv"))
    if not files:
        sys.exit(f"compare-sweeps: no points/*.json in {a}; run make speed-vs-error SWEEP={a} first")
    for rel in files:
        if not (b / rel).exists():
            print(f"compare-sweeps: {b / rel} missing"); bad += 1; continue
        x = norm(json.loads((a / rel).read_text()), str(a))
        y = norm(json.loads((b / rel).read_text()), str(b))
        if x != y:
            keys = [k for k in set(x) | set(y) if x.get(k) != y.get(k)]
            print(f"compare-sweeps: {rel} differs in {sorted(keys)}"); bad += 1
    for rel in hits:
        if not (b / rel).exists() or (a / rel).read_bytes() != (b / rel).read_bytes():
            print(f"compare-sweeps: hits {rel} differ or missing in {b}"); bad += 1
    print(f"compare-sweeps: {len(files)} result files and {len(hits)} hits files compared, {bad} differences")
    sys.exit(1 if bad else 0)

if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
