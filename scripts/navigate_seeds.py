#!/usr/bin/env python3
"""Random start/goal pairs on many terrain scenes, driven by `fieldlidar navigate`, summed up.

For each seed from FIRST to LAST: the scene's terrain truth (`fieldlidar simulate --scene terrain
--frames 1`), 12 random pairs (`navigate_random_pairs.py`, reproducible per seed), and one
`fieldlidar navigate --seed N --pairs` run into OUT/seed_N; then one summary over every pair, the
figures the navigate issue is judged by: goals the truth plan reaches that arrived, drives whose
footprint touched truth-impassable cells (and how deep), driven length over the truth plan, and
unreachable goals reported so. Seeds run JOBS at a time (default 2). Extra arguments after `--`
go to every `fieldlidar navigate` run (e.g. `-- --noise-seed 2`).

usage: navigate_seeds.py FIRST LAST OUT [--fieldlidar PATH] [--jobs N] [-- NAVIGATE_OPTIONS...]
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def run_seed(seed, out, fieldlidar, extra):
    """Simulate, draw the pairs and drive them; the rows of the run's pairs.csv."""
    folder = os.path.join(out, f"seed_{seed}")
    truth = os.path.join(folder, "scene")
    subprocess.run([fieldlidar, "simulate", "--scene", "terrain", "--frames", "1", "--seed",
                    str(seed), "--out", truth], check=True, stdout=subprocess.DEVNULL)
    pairs = subprocess.run([sys.executable, os.path.join(HERE, "navigate_random_pairs.py"),
                            os.path.join(truth, "terrain_truth.csv"), str(seed)],
                           check=True, capture_output=True, text=True).stdout
    pairs_file = os.path.join(folder, "pairs_in.csv")
    with open(pairs_file, "w") as f:
        f.write(pairs)
    subprocess.run([fieldlidar, "navigate", "--seed", str(seed), "--pairs", pairs_file, "--out",
                    os.path.join(folder, "runs")] + extra,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(os.path.join(folder, "runs", "pairs.csv")) as f:
        rows = [dict(row, seed=seed) for row in csv.DictReader(f)]
    for row in rows:
        run = os.path.join(folder, "runs", row["pair"])
        row["first_touch_m"] = first_touch_m(run)
        with open(os.path.join(run, "summary.json")) as f:
            info = json.load(f)
        row["blind_radius_m"], row["sensor"] = info["blind_radius_m"], info["sensor"]
        row["mast_m"] = info.get("mast_m", 1.2)
        row["map"] = info.get("built_map_vs_truth", {})
    return rows


def first_touch_m(run):
    """How far (m, straight) from its start a drive's footprint first touched a truth-impassable
    cell (navigate_log.csv); None when it never did."""
    with open(os.path.join(run, "navigate_log.csv")) as f:
        log = list(csv.DictReader(f))
    for row in log:
        if int(row["footprint_on_impassable"]):
            return math.hypot(float(row["x_m"]) - float(log[0]["x_m"]),
                              float(row["y_m"]) - float(log[0]["y_m"]))
    return None


def summary(rows):
    name = lambda r: f"s{r['seed']}{r['pair']}"
    reachable = lambda r: float(r["truth_plan_m"] or "nan") > 0  # the truth plan found a path
    reach = [r for r in rows if reachable(r)]
    unreach = [r for r in rows if not reachable(r)]
    arrived = [r for r in reach if r["outcome"] == "arrived"]
    ratios = [float(r["ratio"]) for r in arrived]
    touched = [r for r in rows if int(r["frames_on_impassable"]) > 0]
    deep = [r for r in touched if float(r["max_impassable_depth_m"]) >= 0.1]
    near = [r for r in touched if r["first_touch_m"] <= r["blind_radius_m"]]
    # the footprint on an obstacle's disc itself, not only on a cell it reaches into
    contact = [r for r in touched if int(r.get("frames_on_obstacles") or 0) > 0]
    tipped = [r for r in rows if float(r.get("max_tilt_deg") or 0) > 25.0]
    blind = max((r["blind_radius_m"] for r in rows), default=0.0)
    sensor = rows[0]["sensor"] if rows else "?"
    mast = rows[0]["mast_m"] if rows else 1.2
    lines = [
        f"{len(rows)} pairs; {len(arrived)} of {len(reach)} goals the truth plan reaches arrived "
        f"(not: {' '.join(name(r) + '/' + r['outcome'] for r in reach if r['outcome'] != 'arrived')})",
        f"  driven / truth plan: mean {sum(ratios) / max(1, len(ratios)):.3f}, "
        f"{sum(x > 1.15 for x in ratios)} over 1.15, largest {max(ratios, default=0):.3f}",
        f"  {len(touched)} drives with the footprint on truth-impassable cells "
        f"({sum(int(r['frames_on_impassable']) for r in touched)} frames; "
        f"{sum(reachable(r) for r in touched)} of the {len(reach)} reachable drives, "
        f"{sum(int(r['frames_on_impassable']) for r in touched if reachable(r))} frames), "
        f"{len(deep)} of them "
        f"0.10 m or more into such a cell: "
        + " ".join(f"{name(r)}:{r['frames_on_impassable']}/{float(r['max_impassable_depth_m']):.2f}"
                   f"@{r['first_touch_m']:.1f}" for r in touched),
        f"  (frames/deepest m@where first touched, m from the start) {len(near)} of them first "
        f"within {blind:.1f} m of their start, in the start's blind disk (a level {sensor} on "
        f"a {mast:g} m mast sees no ground nearer; the approach's sweeps see part of it)",
        f"  {len(contact)} of them with the footprint on an obstacle's disc itself (a rock, "
        f"bush or trunk; the rest on cells a disc reaches into, or on pits' and slopes' walls): "
        + (" ".join(f"{name(r)}:{r['frames_on_obstacles']}/{float(r['min_obstacle_gap_m']):.2f}"
                    for r in contact) + " (frames on it/least gap m)" if contact else "none"),
        f"  chassis tilted over the robot's 25 deg (a wheel down a wall or a step): "
        + (" ".join(f"{name(r)}:{float(r['max_tilt_deg']):.0f}" for r in tipped) or "none"),
        f"  {sum(r['outcome'] == 'unreachable' for r in unreach)} of {len(unreach)} goals the "
        f"truth plan does not reach reported unreachable",
    ]
    maps = [r["map"] for r in rows if r["map"]]
    if maps:
        total = lambda k: sum(m[k] for m in maps)
        known, free, blocked = total("known_cells"), total("truth_passable"), total("passable_blocked")
        lines.append(
            f"  the built map against the truth within {maps[0]['radius_m']:g} m of the drives: "
            f"{known} cells known, {blocked} of the {free} truth-passable ones blocked "
            f"({100.0 * blocked / max(1, free):.1f} %; {total('passable_blocked_beside_impassable')} "
            f"of them next to a truth-impassable cell), {total('impassable_passable')} of the "
            f"{known - free} truth-impassable ones called passable")
    return "\n".join(lines)


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("first", type=int)
    ap.add_argument("last", type=int)
    ap.add_argument("out")
    ap.add_argument("--fieldlidar", default=os.path.join(HERE, "..", "build", "release", "apps",
                                                         "fieldlidar", "fieldlidar"))
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    if a.last < a.first:
        ap.error(f"LAST ({a.last}) is before FIRST ({a.first})")
    if os.path.exists(a.out):
        ap.error(f"{a.out} exists: choose a new folder")
    if not os.access(a.fieldlidar, os.X_OK):
        ap.error(f"no fieldlidar executable at {a.fieldlidar} (build it, or --fieldlidar PATH)")
    os.makedirs(a.out)
    seeds = list(range(a.first, a.last + 1))
    rows = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for k, seed_rows in enumerate(pool.map(
                lambda s: run_seed(s, a.out, a.fieldlidar, extra), seeds)):
            rows += seed_rows
            print(f"seed {seeds[k]} done ({k + 1} of {len(seeds)})", file=sys.stderr)
    text = summary(rows)
    with open(os.path.join(a.out, "summary.txt"), "w") as f:
        f.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
