#!/usr/bin/env python3
"""benchmarks/peer_ratios.py — lieservo's time over the best peer's, per operation.

Runs lieservo_bench_peers several rounds in a row. In each round every selected benchmark runs
--reps repetitions in random interleaved order (Google Benchmark's
--benchmark_enable_random_interleaving), so that a slow spell of the machine falls on all
libraries alike, and each keeps its median. For every operation it prints the median over the
rounds of each library's time and of the ratio lieservo ÷ best peer (formed within each round).

    benchmarks/peer_ratios.py build-peers/benchmarks/lieservo_bench_peers \
        --filter 'SO3._(exp|log)_(full|small|near_pi)/' --rounds 5
"""
import argparse
import json
import statistics
import subprocess
import sys


SETS = {  # the inputs of each benchmark name's suffix (bench_peers.cpp)
    "exp": "θ ≤ 1 rad", "log": "θ ≤ 25°", "exp_large": "θ ∈ (π/2, π)",
    "exp_full": "θ ∈ [0, π)", "log_full": "θ ∈ [0, π)",
    "exp_small": "θ ∈ [1e-8, 1e-2]", "log_small": "θ ∈ [1e-8, 1e-2]",
    "exp_near_pi": "π − θ ∈ [1e-8, 1e-2]", "log_near_pi": "π − θ ∈ [1e-8, 1e-2]",
    "exp_matrix": "θ ≤ 1 rad, peers as a matrix", "log_matrix": "θ ≤ 25°, peers as a matrix",
}


ORDER = ["exp", "log", "leftJacobian", "leftJacobianInverse", "Ad", "compose", "inverse", "act",
         "exp_matrix", "log_matrix", "exp_large", "exp_full", "log_full", "exp_small", "log_small",
         "exp_near_pi", "log_near_pi"]


def sort_key(op):
    """Double before float, SE(3) before SO(3), then the order of ORDER."""
    group, _, what = op.partition("_")
    return (group[-1] != "d", not group.startswith("SE3"), ORDER.index(what) if what in ORDER else len(ORDER), op)


def label(op):
    """SO3d_exp_full -> 'SO3d exp, θ ∈ [0, π)'; SE(3) operations keep their name."""
    group, _, what = op.partition("_")
    if group.startswith("SO3") and what in SETS:
        return f"{group} {what.split('_')[0]}, {SETS[what]}"
    return f"{group} {what}"


def one_round(binary, pattern, reps, min_time):
    out = subprocess.run([binary, f"--benchmark_filter={pattern}", f"--benchmark_repetitions={reps}",
                          "--benchmark_report_aggregates_only=true", f"--benchmark_min_time={min_time}",
                          "--benchmark_enable_random_interleaving=true",
                          "--benchmark_format=json"], check=True, capture_output=True, text=True).stdout
    times = {}
    for b in json.loads(out[out.index("{"):])["benchmarks"]:  # the accuracy report comes first
        if b.get("aggregate_name") == "median":
            op, library = b["run_name"].rsplit("/", 1)
            times.setdefault(op, {})[library] = b["cpu_time"]
    return times


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("binary")
    ap.add_argument("--filter", default=".")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--min-time", type=float, default=0.05)
    a = ap.parse_args()
    rounds = [one_round(a.binary, a.filter, a.reps, a.min_time) for _ in range(a.rounds)]
    print("| operation | lieservo (ns) | Sophus (ns) | manif (ns) | lieservo ÷ best peer |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for op in sorted(rounds[0], key=sort_key):
        med = {lib: statistics.median(r[op][lib] for r in rounds) for lib in rounds[0][op]}
        peers = [lib for lib in med if lib != "lieservo"]
        if op.endswith("_matrix"):  # lieservo's own row is the plain op of the same set
            base = op[: -len("_matrix")]
            med["lieservo"] = statistics.median(r[base]["lieservo"] for r in rounds)
            for r in rounds:
                r[op]["lieservo"] = r[base]["lieservo"]
        if "lieservo" not in med or not peers:
            continue
        ratio = statistics.median(r[op]["lieservo"] / min(r[op][p] for p in peers) for r in rounds)
        worst = max(worst, ratio)
        cell = lambda lib: f"{med[lib]:.3g}" if lib in med else "-"
        print(f"| {label(op)} | {cell('lieservo')} | {cell('sophus')} | {cell('manif')} | {ratio:.2f} |")
    print(f"\nworst ratio: {worst:.2f} ({a.rounds} rounds of {a.reps} repetitions)", file=sys.stderr)


if __name__ == "__main__":
    main()
