#!/usr/bin/env python3
"""make cppsim-speed: the C++ harness's simulation speed, measured so that it can be trusted on a shared machine.

Runs rtaccel-sim (the runner of `make regress SIM=cpp`, same memory options as the regression's defaults) on
each package, RUNS times, alternating the simulator builds given (so a change of machine load hits all of
them alike), and writes every run and a summary per (build, package) to OUT (JSON) and to stdout.

Each run's figures are rtaccel-sim's own (sim.json): simulated cycles from the scene load to the batch's
end, over wall seconds (`cyclesPerSecond`, what report.json's simulation.cyclesPerSecond holds) and over the
process's CPU seconds (`cyclesPerCpuSecond`: clock(), user + sys; on a machine shared by several sessions
wall time includes waiting for a core, CPU time much less so). The load average is recorded with each run.

usage: speed.py OUT.json RUNS SIMDIR[,SIMDIR...] PKG [PKG...]
"""
import json
import os
import statistics
import subprocess
import sys
import tempfile

# make regress's memory defaults (scripts/regress.sh, CppSim.memoryOptions): 100 ns, 200 MHz, 64 outstanding, seed 1.
MEMORY = ["--mem-latency", "100-100", "--fabric-mhz", "200", "--outstanding", "64", "--seed", "1"]


def run(simdir, pkg):
    with tempfile.TemporaryDirectory(prefix="cppsim-speed.") as out:
        cmd = [os.path.join(simdir, "rtaccel-sim"), "--package", pkg, "--out", out] + MEMORY
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            sys.exit(f"cppsim-speed: {' '.join(cmd)} failed (exit {p.returncode}):\n{p.stderr}")
        with open(os.path.join(out, "sim.json")) as f:
            s = json.load(f)
    sim = s["simulation"]
    return {"build": simdir, "package": pkg, "batchCycles": s["batchCycles"], "simulatedCycles": sim["simulatedCycles"],
            "wallSeconds": sim["seconds"], "cpuSeconds": sim["cpuSeconds"], "cyclesPerSecond": sim["cyclesPerSecond"],
            "cyclesPerCpuSecond": sim["cyclesPerCpuSecond"], "loadAverage1": os.getloadavg()[0]}


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    out, runs, builds, pkgs = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(","), sys.argv[4:]
    for b in builds:
        if not os.access(os.path.join(b, "rtaccel-sim"), os.X_OK):
            sys.exit(f"cppsim-speed: {b}/rtaccel-sim: not built (make regress SCENE=scenes/cornell-box/cornell-box.xml "
                     "SIM=cpp builds the clang one; make cppsim-test the gcc one)")
    for p in pkgs:
        if not os.path.exists(os.path.join(p, "rays.csv")):
            sys.exit(f"cppsim-speed: {p}/rays.csv: no package")
    rows = []
    for r in range(runs):
        for p in pkgs:
            for b in builds:
                row = run(b, p)
                row["round"] = r
                rows.append(row)
                print(f"cppsim-speed: round {r} {os.path.basename(b)} {os.path.basename(p)}: {row['simulatedCycles']} cycles, "
                      f"{row['cyclesPerCpuSecond']:.0f} per CPU s, {row['cyclesPerSecond']:.0f} per wall s "
                      f"(load {row['loadAverage1']:.2f})", flush=True)
    summary = []
    for p in pkgs:
        for b in builds:
            rs = [x for x in rows if x["build"] == b and x["package"] == p]
            cpu = [x["cyclesPerCpuSecond"] for x in rs]
            wall = [x["cyclesPerSecond"] for x in rs]
            summary.append({"build": b, "package": p, "runs": len(rs), "simulatedCycles": rs[0]["simulatedCycles"],
                            "cyclesPerCpuSecond": {"median": statistics.median(cpu), "min": min(cpu), "max": max(cpu)},
                            "cyclesPerSecond": {"median": statistics.median(wall), "min": min(wall), "max": max(wall)},
                            "loadAverage1": {"min": min(x["loadAverage1"] for x in rs), "max": max(x["loadAverage1"] for x in rs)}})
    with open(out, "w") as f:
        json.dump({"memory": MEMORY, "summary": summary, "runs": rows}, f, indent=2)
    print(f"cppsim-speed: {out}")
    for s in summary:
        c, w, l = s["cyclesPerCpuSecond"], s["cyclesPerSecond"], s["loadAverage1"]
        print(f"  {os.path.basename(s['build'])} {os.path.basename(s['package'])}: {s['simulatedCycles']} cycles, per CPU s "
              f"median {c['median']:.0f} (min {c['min']:.0f}, max {c['max']:.0f}); per wall s median {w['median']:.0f} "
              f"(min {w['min']:.0f}, max {w['max']:.0f}); load {l['min']:.1f}-{l['max']:.1f}; {s['runs']} runs")


if __name__ == "__main__":
    main()
