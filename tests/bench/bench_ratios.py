#!/usr/bin/env python3
"""The README's ratio table from a pfx_bench results.tsv.

For one scene, variant and error metric: a peer's best run is its smallest finite error
(over every time step, iteration count and sub-step count in the file); the ratio is pfx's
cheapest wall time among its runs with an error equal to or better than that, divided by
the peer's wall time at its best. Below 1, pfx reaches the peer's best accuracy sooner.
pfx's runs can be restricted to one thread count, so that a table compares like with like.

usage: bench_ratios.py results.tsv [--threads N] SCENE:VARIANT:METRIC [...]
"""
import argparse
import csv
import math
import sys


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f, delimiter="\t"))


def runs(rows, scene, variant, metric, engine, threads=None):
    """(error, wall s per simulated s, settings) of every finished run."""
    found = []
    for row in rows:
        if (row["scene"], row["variant"], row["metric"], row["engine"]) != (
            scene, variant, metric, engine):
            continue
        if threads is not None and int(row["threads"]) != threads:
            continue
        error, wall = float(row["value"]), float(row["wall_s_per_sim_s"])
        if math.isfinite(error) and math.isfinite(wall):
            settings = "dt %.4g, %s it, %s thr" % (float(row["dt"]), row["iterations"],
                                                  row["threads"])
            found.append((error, wall, settings))
    return found


def ratio_cell(pfx_runs, peer_runs):
    if not peer_runs:
        return "no finished run"
    peer_error, peer_wall, _ = min(peer_runs, key=lambda r: (r[0], r[1]))
    good = [r for r in pfx_runs if r[0] <= peer_error]
    if not good:
        best = min(pfx_runs)[0] if pfx_runs else float("nan")
        return "not reached (%.2g against %.2g)" % (best, peer_error)
    error, wall, settings = min(good, key=lambda r: r[1])
    return "%.2f (%.2g against %.2g; %s)" % (wall / peer_wall, error, peer_error, settings)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--threads", type=int, default=None)
    parser.add_argument("--peers", default="bullet,ode,mujoco")
    parser.add_argument("cases", nargs="+", help="SCENE:VARIANT:METRIC")
    args = parser.parse_args()
    rows = read_rows(args.results)
    peers = args.peers.split(",")
    print("| scene, error | " + " | ".join("vs " + p for p in peers) + " |")
    print("|---" * (len(peers) + 1) + "|")
    for case in args.cases:
        scene, variant, metric = case.split(":")
        pfx_runs = runs(rows, scene, variant, metric, "pfx", args.threads)
        if not pfx_runs:
            sys.exit("no pfx run of %s" % case)
        cells = [ratio_cell(pfx_runs, runs(rows, scene, variant, metric, peer)) for peer in peers]
        label = scene if variant == "-" else "%s %s" % (scene, variant)
        print("| `%s`, %s | %s |" % (label, metric, " | ".join(cells)))


if __name__ == "__main__":
    main()
