#!/usr/bin/env python3
"""Random start/goal pairs for `fieldlidar navigate --pairs` on a simulated terrain scene.

Reads the scene's terrain truth (`fieldlidar simulate --scene terrain --seed N --frames 1 --out
DIR` writes DIR/terrain_truth.csv) and draws pairs whose start and goal have every truth cell
within 1 m passable, at least 15 m apart, with uniformly random headings (seeded by 100 + N, so
the file is reproducible). The expected outcome (arrived or unreachable) is not decided here: it
is the Hybrid A* plan on the truth map, which `fieldlidar navigate --pairs` reports per pair.

usage: navigate_random_pairs.py TRUTH_CSV SEED [COUNT]  > pairs.csv
"""
import csv
import math
import random
import sys


def main():
    truth_csv, seed = sys.argv[1], int(sys.argv[2])
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 12
    passable = {}
    for row in csv.DictReader(open(truth_csv)):
        passable[(int(row["ix"]), int(row["iy"]))] = row["passable"] == "1"

    def free(x, y, cell=0.5, clear=1.0):
        for ix in range(int((x - clear) / cell), int((x + clear) / cell) + 1):
            for iy in range(int((y - clear) / cell), int((y + clear) / cell) + 1):
                if not passable.get((ix, iy), False):
                    return False
        return True

    rng = random.Random(100 + seed)
    for k in range(count):
        while True:
            sx, sy = rng.uniform(3, 57), rng.uniform(3, 37)
            gx, gy = rng.uniform(3, 57), rng.uniform(3, 37)
            if math.hypot(gx - sx, gy - sy) > 15 and free(sx, sy) and free(gx, gy):
                break
        syaw, gyaw = rng.uniform(-3.14, 3.14), rng.uniform(-3.14, 3.14)
        print(f"p{k}, {sx:.1f}, {sy:.1f}, {syaw:.3f}, {gx:.1f}, {gy:.1f}, {gyaw:.3f}")


if __name__ == "__main__":
    main()
