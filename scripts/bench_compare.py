#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Compares two builds' benchmarks in one run: `deepcut_bench --json` of OLD and NEW, alternated
ROUNDS times (so both see the same machine load), each case's best median kept per build.

    python3 scripts/bench_compare.py OLD_BENCH NEW_BENCH [--rounds 3] [--quick] [--filter REGEX]

Prints one line per case and peer: old ms, new ms and new/old; exits 0 (it reports, it does not
judge: a refactor's "no case more than 5% slower" is read off the table).
"""
import argparse
import json
import subprocess
import sys


def run(binary, quick, regex):
    cmd = [binary, "--json"] + (["--quick"] if quick else [])
    if regex:
        cmd.append("--benchmark_filter=" + regex)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    times = {}
    for case in json.loads(out)["cases"]:
        key = f"{case['name']} {case['size']}"
        if case.get("ours_ms") is not None:  # memory entries carry sizes, not times
            times[key + " ours"] = case["ours_ms"]
        if case.get("peer_ms") is not None:
            times[f"{key} {case['peer']}"] = case["peer_ms"]
    return times


def best(runs):
    merged = {}
    for times in runs:
        for key, ms in times.items():
            merged[key] = min(ms, merged.get(key, float("inf")))
    return merged


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="skip the 1M-triangle cases")
    parser.add_argument("--filter", default="", help="Google Benchmark filter regex")
    args = parser.parse_args()
    old_runs, new_runs = [], []
    for r in range(args.rounds):
        print(f"round {r + 1}/{args.rounds}", file=sys.stderr)
        old_runs.append(run(args.old, args.quick, args.filter))
        new_runs.append(run(args.new, args.quick, args.filter))
    old, new = best(old_runs), best(new_runs)
    print(f"{'case':44} {'old ms':>10} {'new ms':>10} {'new/old':>8}")
    for key in sorted(set(old) | set(new)):
        o, n = old.get(key), new.get(key)
        ratio = f"{n / o:8.3f}" if o and n else "       -"
        fmt = lambda v: f"{v:10.3f}" if v is not None else "         -"
        print(f"{key:44} {fmt(o)} {fmt(n)} {ratio}")


if __name__ == "__main__":
    main()
