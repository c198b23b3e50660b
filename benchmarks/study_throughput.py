#!/usr/bin/python3
"""Throughput of a study on Dask: simulated trials per second with 1 and with 2 local workers,
and the scaling efficiency (rate with 2 / (2 × rate with 1)). docs/studies.md states its figures.

    PYTHONPATH=build/release/python /usr/bin/python3 benchmarks/study_throughput.py [--trials 40] [--repetitions 3]

Each measurement: a LocalCluster of N single-threaded worker processes (as study.py starts it),
one warm-up trial per worker (the import and the observations' set-up), then the study's trials
timed from the first submission to the last result; the median over the repetitions. The trials
are those of examples/studies/specs/small.toml's cases, with the spec's draws and the trial seeds
of a study, so that every repetition runs the same work. Cluster start-up is not counted.
"""
from __future__ import annotations

import argparse
import logging
import os
import platform
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'examples', 'studies'))

from lieservo_study import spec as spec_mod  # noqa: E402
from lieservo_study.run import _worker_path  # noqa: E402
from lieservo_study.trial import run_trial  # noqa: E402


def measure(trials, spec, workers: int) -> float:
    """Trials per second of `trials` on a fresh LocalCluster of `workers`."""
    from distributed import Client, LocalCluster, wait
    os.environ['PYTHONPATH'] = _worker_path()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        client.wait_for_workers(workers)
        warm = [client.submit(run_trial, trials[0].case, trials[0].seed, spec.observations, trials[0].kwargs(),
                              pure=False, workers=[w]) for w in client.scheduler_info()['workers']]
        wait(warm)
        t0 = time.perf_counter()
        futures = [client.submit(run_trial, t.case, t.seed, spec.observations, t.kwargs(), pure=False)
                   for t in trials]
        client.gather(futures)
        return len(trials) / (time.perf_counter() - t0)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--trials', type=int, default=40, help='trials per measurement (default 40)')
    ap.add_argument('--repetitions', type=int, default=3, help='measurements per worker count (default 3)')
    args = ap.parse_args()
    from lieservo import sim
    spec = spec_mod.load(os.path.join(ROOT, 'examples', 'studies', 'specs', 'small.toml'), sim.cases())
    cases = [c for c, _ in spec.cases]
    trials = [spec_mod.trial(spec, cases[i % len(cases)], i // len(cases)) for i in range(args.trials)]
    print(f'{platform.node()}: {os.cpu_count()} cores, {platform.processor() or platform.machine()}; '
          f'{args.trials} trials of {", ".join(cases)} ({spec.observations} observations), '
          f'median of {args.repetitions}')
    rates = {}
    for n in (1, 2):
        runs = [measure(trials, spec, n) for _ in range(args.repetitions)]
        rates[n] = statistics.median(runs)
        print(f'  {n} worker{"s" if n > 1 else ""}: {rates[n]:.2f} trials/s '
              f'(runs: {", ".join(f"{r:.2f}" for r in runs)})')
    print(f'  scaling efficiency with 2 workers: {rates[2] / (2 * rates[1]):.2f}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
