#!/usr/bin/env python3
"""Analysis aid for docs/reports/speed-vs-error-notes.md: how many triangles of the
closed hard-case meshes become zero-area when their f32 vertices are rounded
(to nearest even) to a narrower mantissa, as the datapath's input converters
do. Exact (fractions). Usage: scripts/zero_area_after_rounding.py
"""
import math, sys, os
from fractions import Fraction
def rnd(x, m):
    # round to nearest even with m stored mantissa bits (exponent unbounded: e8 range suffices here)
    if x == 0: return 0.0
    e = math.floor(math.log2(abs(x)))
    q = 2.0 ** (e - m)
    return round(x / q) * q
def load(path):
    vs, fs = [], []
    for line in open(path):
        p = line.split()
        if not p: continue
        if p[0] == 'v': vs.append(tuple(float(t) for t in p[1:4]))
        if p[0] == 'f': fs.append(tuple(int(t.split('/')[0]) - 1 for t in p[1:4]))
    return vs, fs
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'scenes', 'hard')
for case in ['sphere-closed', 'sphere-offset-1e4', 'sphere-offset-1e6', 'tiny-edges']:
    objs = [f for f in os.listdir(f'{root}/{case}') if f.endswith('.obj')]
    for m in [23, 19, 18, 15, 12, 10, 9, 7]:
        zero = 0; total = 0
        for o in objs:
            vs, fs = load(f'{root}/{case}/{o}')
            r = [tuple(rnd(c, m) for c in v) for v in vs]
            for f in fs:
                a, b, c = (tuple(Fraction(x) for x in r[i]) for i in f)
                e1 = [b[i] - a[i] for i in range(3)]; e2 = [c[i] - a[i] for i in range(3)]
                n = (e1[1]*e2[2]-e1[2]*e2[1], e1[2]*e2[0]-e1[0]*e2[2], e1[0]*e2[1]-e1[1]*e2[0])
                total += 1
                if n == (0, 0, 0): zero += 1
        print(f'{case:20s} m{m:2d}: {zero}/{total} zero-area triangles after rounding')
