"""Register offsets and fields. The bench reads them from config.json, which
Prepare writes from RegisterMap (the register map's single source); when the
generated C header a driver includes (rtaccel_regs.h) is there too, every
RTACCEL_<NAME>_OFFSET in it must agree, so a header that disagrees with the
RTL fails here."""

import re

_DEFINE = re.compile(r"^\s*#define\s+RTACCEL_(\w+)\s+\(?\s*(0x[0-9a-fA-F]+|\d+)[uUlL]*\s*\)?")


class RegMap:
    def __init__(self, regs):
        """regs: {name: {"offset": int, "fields": {field: [lsb, width]}}} from config.json."""
        self.regs = regs

    def offset(self, reg):
        if reg not in self.regs:
            raise KeyError(f"no register {reg} in the register map")
        return self.regs[reg]["offset"]

    def mask(self, reg, field):
        fields = self.regs[reg]["fields"]
        if field not in fields:
            raise KeyError(f"register {reg} has no field {field}")
        lsb, width = fields[field]
        return ((1 << width) - 1) << lsb

    def header_disagreements(self, path):
        """#defines of the C header (RTACCEL_<REG>_OFFSET, RTACCEL_<REG>_<FIELD>_MASK)
        that differ from the map or are missing."""
        found = {}
        with open(path) as f:
            for line in f:
                m = _DEFINE.match(line)
                if m:
                    found[m.group(1)] = int(m.group(2), 0)
        want = {}
        for n, r in self.regs.items():
            want[f"{n}_OFFSET"] = r["offset"]
            for fld in r["fields"]:
                want[f"{n}_{fld}_MASK"] = self.mask(n, fld)
        return [f"{path}: RTACCEL_{k} is {found[k]:#x}, the map says {v:#x}" if k in found else f"{path}: no RTACCEL_{k}"
                for k, v in want.items() if found.get(k) != v]
