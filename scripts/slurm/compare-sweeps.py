#!/usr/bin/env python3
"""Checks that two sweep directories hold the same results, e.g. one made by
`make -j` and one by a Slurm job array (SWEEP_ENGINE=slurm):
    compare-sweeps.py A B [point ...]
The points default to every points/<point>.json in B (the newer, usually
smaller, run); each must have, in both A and B, the same
  points/<point>.json, points/<point>.hard.json, area/<point>.json,
  accuracy/<point>/**, hard/<point>/** (JSON: field by field) and
  hits/<point>/*.csv (byte by byte),
and the shared inputs those points used must be the same too: every file of
packages/<layout>/** for the points' layouts and every hard-ref/*.json of B.
JSON is compared with the wall-clock fields (`seconds`, `timings_seconds`) dropped and the sweep directory's
name in strings replaced by <sweep>; nothing else is skipped. A file missing
on either side is a difference. Exit status 1 on any difference, naming the
file and each differing field (path and both values)."""
import json, pathlib, sys

# Wall-clock fields: a point job's `seconds`, a package's `timings_seconds`.
WALL_TIMES = {"seconds", "timings_seconds"}

def norm(o, root):
    if isinstance(o, dict):
        return {k: norm(v, root) for k, v in o.items() if k not in WALL_TIMES}
    if isinstance(o, list):
        return [norm(v, root) for v in o]
    if isinstance(o, str):
        return o.replace(root, "<sweep>")
    return o

def diffs(x, y, path="$"):
    """Every differing leaf as (json path, value in A, value in B)."""
    if isinstance(x, dict) and isinstance(y, dict):
        for k in sorted(set(x) | set(y)):
            if k not in x or k not in y:
                yield f"{path}.{k}", x.get(k, "<absent>"), y.get(k, "<absent>")
            else:
                yield from diffs(x[k], y[k], f"{path}.{k}")
    elif isinstance(x, list) and isinstance(y, list) and len(x) == len(y):
        for i, (u, v) in enumerate(zip(x, y)):
            yield from diffs(u, v, f"{path}[{i}]")
    elif x != y:
        yield path, x, y

def files_under(d):
    return sorted(p for p in d.rglob("*") if p.is_file()) if d.is_dir() else []

def main(a, b, points):
    a, b = pathlib.Path(a), pathlib.Path(b)
    if not points:
        points = sorted(p.name[:-len(".json")] for p in b.glob("points/*.json") if not p.name.endswith(".hard.json"))
    if not points:
        sys.exit(f"compare-sweeps: no points/*.json in {b}; run make speed-vs-error SWEEP={b} first")
    rels = []
    for p in points:
        rels += [pathlib.Path("points", p + ".json"), pathlib.Path("points", p + ".hard.json"), pathlib.Path("area", p + ".json")]
        for sub in ("accuracy", "hard", "hits"):
            found = {f.relative_to(a) for f in files_under(a / sub / p)} | {f.relative_to(b) for f in files_under(b / sub / p)}
            if not found:
                print(f"compare-sweeps: no {sub}/{p}/ in either sweep")
                rels.append(pathlib.Path(sub, p, "<nothing>"))
            rels += sorted(found)
    for layout in sorted({p.split("-")[0] for p in points}):
        rels += sorted({f.relative_to(b) for f in files_under(b / "packages" / layout)} |
                       {f.relative_to(a) for f in files_under(a / "packages" / layout)})
    rels += sorted(f.relative_to(b) for f in b.glob("hard-ref/*.json"))
    bad = 0
    kinds = {}
    for rel in rels:
        fa, fb = a / rel, b / rel
        if not fa.is_file() or not fb.is_file():
            print(f"compare-sweeps: {rel} missing in {a if not fa.is_file() else b}"); bad += 1; continue
        kind = rel.parts[0]
        kinds[kind] = kinds.get(kind, 0) + 1
        if rel.suffix == ".json":
            d = list(diffs(norm(json.loads(fa.read_text()), str(a)), norm(json.loads(fb.read_text()), str(b))))
            if d:
                bad += 1
                print(f"compare-sweeps: {rel} differs in {len(d)} fields:")
                for path, u, v in d[:20]:
                    print(f"    {path}: {u!r} in A, {v!r} in B")
        elif fa.read_bytes() != fb.read_bytes():
            print(f"compare-sweeps: {rel} differs (bytes)"); bad += 1
    counts = ", ".join(f"{n} {k}" for k, n in sorted(kinds.items()))
    print(f"compare-sweeps: A={a} B={b}, points {' '.join(points)}: {len(rels)} files compared ({counts}), {bad} differences")
    sys.exit(1 if bad else 0)

if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3:])
