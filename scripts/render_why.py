#!/usr/bin/env python3
"""Why each pixel of a `make render` image differs from Embree's image.

usage: render_why.py OUT CAMERA_HITS [SECONDARY_HITS]

OUT is a render's folder (accel.png, embree.png, camera/, secondary.txt,
secondary/). Every pixel that differs between accel.png and embree.png is
traced back to the rays behind it, and each ray to the class `nori-bridge
compare` gives it against Embree's answer (tie, edge, reference_wrong,
mismatch, ...: docs/memory-format.md), with both answers' prim and t:
- camera ray k is pixel k (SPP=1; with more samples a pixel's rays are not
  separated and the camera part is skipped);
- the secondary rays (secondary.txt, in camera-hit order, one group per
  camera hit, all with that hit point as origin) are matched to the camera
  hit whose point o + t d they start from; those whose occlusion differs from
  Embree's (the only thing the ao and direct integrators read) explain it.
Writes OUT/why.json and prints one line per cause. Standard library only.
"""
import collections
import csv
import json
import os
import struct
import subprocess
import sys
import zlib

BRIDGE = 'nori-bridge/target/release/nori-bridge'


def read_png(path):
    """8-bit RGB or RGBA, non-interlaced (what nori-bridge writes): rows of bytes."""
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        sys.exit(f'Error: {path}: not a PNG')
    pos, idat, w = 8, b'', 0
    while pos < len(data):
        n, = struct.unpack('>I', data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b'IHDR':
            w, h, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', body)
            if depth != 8 or colour not in (2, 6) or interlace:
                sys.exit(f'Error: {path}: depth {depth}, colour type {colour}, interlace {interlace}: only 8-bit RGB(A)')
        elif kind == b'IDAT':
            idat += body
    bpp = 3 if colour == 2 else 4
    raw, stride, rows, prev, i = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp), 0
    for _ in range(h):
        f, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([bytes(line[k * bpp:k * bpp + 3]) for k in range(w)])
        prev = line
    return w, rows


def differing_pixels(a, b):
    w, ra = read_png(a)
    _, rb = read_png(b)
    return w * len(ra), [y * w + x for y in range(len(ra)) for x in range(w) if ra[y][x] != rb[y][x]]


def csv_rows(path):
    with open(path) as f:
        return {int(r['ray']): r for r in csv.DictReader(f)}


def classes(pkg, hits, out):
    """nori-bridge compare's class of each ray that does not agree with Embree."""
    subprocess.run([BRIDGE, 'compare', '--package', pkg, '--hits', hits, '--out', out], check=True,
                   stdout=subprocess.DEVNULL)
    d = json.load(open(out))
    return d['counts'], {r: c for c, rays in d['ray_lists'].items() for r in rays}


def answer(row):
    return {'hit': row['hit'] == '1', 'prim': int(row['prim']), 't': row['t']}


def secondary_groups(out, cam_rays, cam_hits):
    """camera ray -> its secondary rays (indices into secondary.txt's rays)."""
    lines = [l.split() for l in open(f'{out}/secondary.txt') if l.strip() and not l.startswith('#')]
    hit_rays = [k for k in sorted(cam_rays) if cam_hits[k]['hit'] == '1']
    groups, ci, last, cur = collections.defaultdict(list), 0, None, None
    for k, l in enumerate(lines):
        o = tuple(float(v) for v in l[:3])
        if o != last:
            # The next camera hit whose point is this origin (the integrator may skip hits: misses, emitters).
            while True:
                if ci == len(hit_rays):
                    sys.exit(f'Error: {out}/secondary.txt: ray {k}: origin {o} is no camera hit point')
                r, t = cam_rays[hit_rays[ci]], float(cam_hits[hit_rays[ci]]['t'])
                p = [float(r['o' + a]) + t * float(r['d' + a]) for a in 'xyz']
                ci += 1
                if max(abs(p[j] - o[j]) for j in range(3)) <= 1e-3 * max(1.0, *map(abs, p)):
                    break
            cur, last = hit_rays[ci - 1], o
        groups[cur].append(k)
    return groups


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    out, cam_hits_path = sys.argv[1], sys.argv[2]
    sec_hits_path = sys.argv[3] if len(sys.argv) == 4 else None
    npix, pixels = differing_pixels(f'{out}/accel.png', f'{out}/embree.png')
    cam_rays, cam_hits = csv_rows(f'{out}/camera/rays.csv'), csv_rows(cam_hits_path)
    cam_ref = csv_rows(f'{out}/camera/reference.csv')
    one_per_pixel = len(cam_rays) == npix
    cam_counts, cam_cls = classes(f'{out}/camera', cam_hits_path, f'{out}/why-camera-compare.json')
    why = {'pixels_differing': len(pixels), 'camera_classes': cam_counts, 'causes': {}, 'pixels': []}
    groups, sec_cls = {}, {}
    if sec_hits_path:
        sec_counts, sec_cls = classes(f'{out}/secondary', sec_hits_path, f'{out}/why-secondary-compare.json')
        why['secondary_classes'] = sec_counts
        sec_hits, sec_ref = csv_rows(sec_hits_path), csv_rows(f'{out}/secondary/reference.csv')
        groups = secondary_groups(out, cam_rays, cam_hits)
    causes = collections.Counter()
    for p in pixels:
        entry = {'pixel': p}
        if one_per_pixel and p in cam_cls:
            cause = f'camera ray {cam_cls[p]}'
            entry['camera'] = {'ray': p, 'class': cam_cls[p], 'accel': answer(cam_hits[p]), 'embree': answer(cam_ref[p])}
        else:
            bad = [k for k in groups.get(p, []) if sec_hits[k]['hit'] != sec_ref[k]['hit']]
            cause = 'secondary rays ' + ('+'.join(sorted({sec_cls.get(k, 'agree') for k in bad})) if bad else
                                         '(none differ in occlusion)')
            entry['secondary'] = [{'ray': k, 'class': sec_cls.get(k, 'agree'), 'accel': answer(sec_hits[k]),
                                   'embree': answer(sec_ref[k])} for k in bad]
        entry['cause'] = cause
        causes[cause] += 1
        why['pixels'].append(entry)
    why['causes'] = dict(causes)
    with open(f'{out}/why.json', 'w') as f:
        json.dump(why, f, indent=1)
    print(f'render: {len(pixels)} pixels differ from Embree\'s image' +
          ''.join(f'; {n} by {c}' for c, n in causes.most_common()) + f' ({out}/why.json)')


if __name__ == '__main__':
    main()
