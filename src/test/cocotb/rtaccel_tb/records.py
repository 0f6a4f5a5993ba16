"""Ray and hit records in DDR (system contract), and the expected answers.

The expected hits come from the golden model (rtaccel.golden.TraversalGolden,
what `make regress` compares the RTL against bit for bit), written per ray by
`runMain rtaccel.cocotb.Prepare` next to the ray words themselves:
golden.csv, header
  ray,ox,oy,oz,dx,dy,dz,tmin,tmax,shadow,hit,t,u,v,prim,errors
with the float words as hex bit patterns.
"""

import csv
import struct
from dataclasses import dataclass

RAY_BYTES = 48
HIT_BYTES = 32
ERROR_SHIFT = 8  # status bits 8.. hold the ray's ErrorFlags


@dataclass(frozen=True)
class Ray:
    number: int
    words: tuple  # ox oy oz dx dy dz tmin tmax, FP32 bit patterns
    shadow: bool

    def record(self) -> bytes:
        return struct.pack("<8II12x", *self.words, 1 if self.shadow else 0)


@dataclass(frozen=True)
class Hit:
    number: int
    hit: bool
    t: int
    u: int
    v: int
    prim: int
    errors: int

    @staticmethod
    def unpack(b: bytes, error_bits: int):
        """Decodes a 32-byte hit record; returns (Hit, what is wrong with the record's reserved bits)."""
        number, status, t, u, v, prim, pad0, pad1 = struct.unpack("<8I", b)
        errors = (status >> ERROR_SHIFT) & ((1 << error_bits) - 1)
        junk = status & ~(1 | (((1 << error_bits) - 1) << ERROR_SHIFT))
        bad = []
        if junk:
            bad.append(f"status {status:#x} has reserved bits set")
        if pad0 or pad1:
            bad.append(f"bytes 24..31 are {pad0:#x} {pad1:#x}, not zero")
        return Hit(number, bool(status & 1), t, u, v, prim, errors), bad


def load_golden(path):
    """(rays, expected hits) in ray order, from a golden.csv."""
    rays, hits = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            n = int(row["ray"])
            words = tuple(int(row[k], 16) for k in ("ox", "oy", "oz", "dx", "dy", "dz", "tmin", "tmax"))
            rays.append(Ray(n, words, row["shadow"] == "1"))
            hits.append(Hit(n, row["hit"] == "1", int(row["t"], 16), int(row["u"], 16), int(row["v"], 16),
                            int(row["prim"]), int(row["errors"])))
    if not rays:
        raise ValueError(f"{path}: no rays (rerun `make test-cocotb`, which writes it)")
    for i, r in enumerate(rays):
        if r.number != i:
            raise ValueError(f"{path}: line {i + 2}: ray {r.number}, expected {i} (rays are numbered from 0 in order)")
    return rays, hits


def agrees(ray: Ray, got: Hit, want: Hit) -> bool:
    """make regress's rule (TraversalGolden.agrees): every field, except that a
    shadow ray is judged on its occlusion answer and error bits only."""
    if ray.shadow:
        return got.number == want.number and got.hit == want.hit and got.errors == want.errors
    return got == want
