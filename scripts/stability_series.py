#!/usr/bin/env python3
"""Series for docs/stability.md from `tumble run` trajectories (see stability_figures.sh):
top-box drift and total energy of the 20-box tower, top-box height of the penalty stacks,
ball height of the bounce. All boxes of these scenes are unit cubes of 1 kg."""
import csv
import os
import sys

G = 9.81


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def by_time(path):
    out = {}
    for r in rows(path):
        out.setdefault(float(r["time"]), {})[r["body"]] = {k: float(v) for k, v in r.items()
                                                          if k not in ("body", "time")}
    return sorted(out.items())


def main(work):
    for solver in ("impulse", "penalty"):
        series = by_time(os.path.join(work, f"tower_{solver}", "trajectory.csv"))
        z0 = series[0][1]["box19"]["pz"]
        e0 = None
        with open(os.path.join(work, f"tower_{solver}.dat"), "w") as out:
            for t, bodies in series:
                energy = 0.0
                for name, b in bodies.items():
                    if not name.startswith("box"):
                        continue
                    v2 = b["vx"] ** 2 + b["vy"] ** 2 + b["vz"] ** 2
                    w2 = b["wx"] ** 2 + b["wy"] ** 2 + b["wz"] ** 2
                    energy += 0.5 * v2 + 0.5 * w2 / 6 + G * b["pz"]  # I = m a^2 / 6, a = 1
                e0 = energy if e0 is None else e0
                out.write(f"{t} {1000 * (bodies['box19']['pz'] - z0)} {energy - e0}\n")
    for k in ("1e5", "1e7", "1e9"):
        series = by_time(os.path.join(work, f"stack_{k}", "trajectory.csv"))
        z0 = series[0][1]["box4"]["pz"]
        with open(os.path.join(work, f"stack_{k}.dat"), "w") as out:
            for t, bodies in series:
                out.write(f"{t} {1000 * (bodies['box4']['pz'] - z0)}\n")
    for solver in ("impulse", "penalty"):
        series = by_time(os.path.join(work, f"bounce_{solver}", "trajectory.csv"))
        with open(os.path.join(work, f"bounce_{solver}.dat"), "w") as out:
            for t, bodies in series:
                out.write(f"{t} {bodies['ball']['pz'] - 0.5}\n")


if __name__ == "__main__":
    main(sys.argv[1])
