#!/usr/bin/env python3
"""Writes altered copies of a folder of SWC files, to look for failures the
files themselves do not show (developer tool, run by hand, not in CI).

    python3 benches/stress_copies.py ../shared/swc /tmp/stress MODE [MODE ...]
    ./target/release/examples/survey /tmp/stress/MODE > survey_MODE.txt

Each MODE writes /tmp/stress/MODE/NAME.swc for every NAME.swc of the folder:

  rot     a random rotation per file
  scale   coordinates and radii x1000 (a nanometre file)
  small   coordinates and radii x0.001 (a millimetre file)
  shift   moved by (12345.678, -23456.789, 5432.1) (atlas coordinates)
  farnm   x1000, then moved by (412345.678, 223456.789, 95432.1) (FlyWire)
  fat     radii x2.5
  thin    radii x0.4
  jitter  every neurite sample moved by up to 0.6 of its radius per axis
  int     coordinates rounded to integers, radii to halves (at least 0.5):
          a tracing on a 1-unit voxel grid
  flat    z set to 0 (a tracing drawn in 2D: every branch in one plane)
  dense   a midpoint inserted in every neurite segment (parents follow
          their children in the file, as in unsorted files)

Rotation, scale and shift change nothing a correct mesher should show but
rounding; the others change the cell, so compare them with the survey of
the unaltered folder for validity and time, not for area and volume.
Seeded: the same command writes the same files.
"""
import math
import os
import random
import sys

MODES = ("rot", "scale", "small", "shift", "farnm", "fat", "thin", "jitter", "int", "flat", "dense")


def rotation(rng):
    """A uniformly random rotation matrix, from a random unit quaternion."""
    u1, u2, u3 = rng.random(), rng.random(), rng.random()
    x = math.sqrt(1 - u1) * math.sin(2 * math.pi * u2)
    y = math.sqrt(1 - u1) * math.cos(2 * math.pi * u2)
    z = math.sqrt(u1) * math.sin(2 * math.pi * u3)
    w = math.sqrt(u1) * math.cos(2 * math.pi * u3)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]


def read(path):
    """The file's header and comment lines, and its samples as lists
    [id, type, x, y, z, r, parent]; lines that do not parse are kept as text."""
    head, rows = [], []
    with open(path, newline="", errors="replace") as f:
        for raw in f:
            line = raw.rstrip("\r\n")
            fields = line.split()
            if not fields or line.lstrip().startswith("#") or len(fields) < 7:
                head.append(line)
                continue
            try:
                rows.append(
                    [int(float(fields[0])), int(float(fields[1]))]
                    + [float(v) for v in fields[2:6]]
                    + [int(float(fields[6]))]
                )
            except ValueError:
                head.append(line)
    return head, rows


def alter(rows, mode, rng):
    if mode == "rot":
        m = rotation(rng)
        for r in rows:
            p = r[2:5]
            r[2:5] = [sum(m[i][k] * p[k] for k in range(3)) for i in range(3)]
    scale, shift = {"scale": (1000.0, None), "small": (0.001, None),
                    "farnm": (1000.0, (412345.678, 223456.789, 95432.1)),
                    "shift": (1.0, (12345.678, -23456.789, 5432.1))}.get(mode, (1.0, None))
    if scale != 1.0 or shift:
        for r in rows:
            for k in range(3):
                r[2 + k] = r[2 + k] * scale + (shift[k] if shift else 0.0)
            r[5] *= scale
    if mode in ("fat", "thin"):
        for r in rows:
            r[5] *= 2.5 if mode == "fat" else 0.4
    if mode == "jitter":
        for r in rows:
            if r[1] != 1:
                a = 0.6 * max(r[5], 0.05)
                for k in (2, 3, 4):
                    r[k] += rng.uniform(-a, a)
    if mode == "int":
        for r in rows:
            for k in (2, 3, 4):
                r[k] = float(round(r[k]))
            r[5] = max(0.5, round(r[5] * 2) / 2)
    if mode == "flat":
        for r in rows:
            r[4] = 0.0
    if mode == "dense":
        by_id = {r[0]: r for r in rows}
        next_id = max(by_id, default=0) + 1
        extra = []
        for r in rows:
            p = by_id.get(r[6])
            if p is None or r[1] == 1:
                continue
            extra.append([next_id, r[1]] + [(a + b) / 2 for a, b in zip(r[2:6], p[2:6])] + [p[0]])
            r[6] = next_id
            next_id += 1
        rows.extend(extra)
    return rows


def main():
    if len(sys.argv) < 4 or any(m not in MODES for m in sys.argv[3:]):
        sys.exit(__doc__)
    src, out = sys.argv[1], sys.argv[2]
    names = sorted(n for n in os.listdir(src) if n.lower().endswith(".swc"))
    for mode in sys.argv[3:]:
        rng = random.Random(7)
        os.makedirs(os.path.join(out, mode), exist_ok=True)
        for name in names:
            head, rows = read(os.path.join(src, name))
            rows = alter(rows, mode, rng)
            # Far coordinates keep 4 decimals, as atlas files do; the rest 6
            # significant digits.
            num = "%.4f" if mode in ("shift", "farnm") else "%.6g"
            with open(os.path.join(out, mode, name), "w") as f:
                f.write("\n".join(head) + ("\n" if head else ""))
                for r in rows:
                    f.write("%d %d %s %s %s %s %d\n" % (
                        r[0], r[1], num % r[2], num % r[3], num % r[4], "%.6g" % r[5], r[6]))
        print("%s: %d files in %s" % (mode, len(names), os.path.join(out, mode)))


if __name__ == "__main__":
    main()
