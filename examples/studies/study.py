#!/usr/bin/python3
"""Studies at scale: thousands of simulated pushing trials on Dask, their pass rates with Wilson
95 % intervals (docs/studies.md).

    study.py run SPEC [--results CSV] [--scheduler tcp://HOST:PORT] [--workers N]
    study.py report SPEC [--results CSV] [--out DIR]
    study.py trial SPEC CASE INDEX     # one trial alone, as the study ran it (JSON on stdout)
    study.py cases                     # the pushing cases a spec can name

`run` appends each trial to CSV (default: SPEC's name with .csv, in the current folder) as it
arrives; run the same command again after an interruption and it runs only what is missing.
Without --scheduler it starts a local cluster of one worker per core. Needs lieservo.sim on the
path: PYTHONPATH=<build>/python (built with the simulation).

Exit status: 0 done; 1 a trial raised (the rest is recorded); 2 a malformed spec, an unknown case,
a results file of another spec, an unreachable scheduler (the message names the field, file or
address; nothing is written); 130 interrupted by Ctrl-C or SIGTERM (what arrived is recorded).
"""
from __future__ import annotations

import argparse
import json
import os
import shlex
import signal
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from lieservo_study import spec as spec_mod  # noqa: E402
from lieservo_study.results import ResultsError, ResultsFile  # noqa: E402

USAGE = 2


def known_cases() -> list:
    try:
        from lieservo import sim
    except ImportError as e:
        raise SystemExit(f'study.py: cannot import lieservo.sim ({e}); build with the simulation and set '
                         'PYTHONPATH=<build>/python')
    return sim.cases()


def default_results(spec_path: str) -> str:
    return os.path.splitext(os.path.basename(spec_path))[0] + '.csv'


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def main(argv=None) -> int:
    # Ctrl-C, and a SIGTERM (a batch system's time limit), stop a run the same way: what arrived is
    # recorded. Set here too because a shell starts background jobs with SIGINT ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, _interrupt)
    ap = argparse.ArgumentParser(prog='study.py', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest='command', required=True)
    r = sub.add_parser('run', help='run the trials not yet recorded')
    r.add_argument('spec')
    r.add_argument('--results', help='the results CSV (default: the spec\'s name .csv)')
    r.add_argument('--scheduler', help='an existing Dask scheduler, tcp://HOST:PORT (default: a local cluster)')
    r.add_argument('--workers', type=int, help='local cluster: worker processes (default: one per core)')
    r.add_argument('--no-progress', action='store_true', help='no progress bar')
    p = sub.add_parser('report', help='the HTML report of what the results file holds')
    p.add_argument('spec')
    p.add_argument('--results')
    p.add_argument('--out', help='the report\'s folder (default: the results file\'s name without .csv)')
    t = sub.add_parser('trial', help='run one trial alone and print it')
    t.add_argument('spec')
    t.add_argument('case')
    t.add_argument('index', type=int)
    sub.add_parser('cases', help='list the pushing cases')
    args = ap.parse_args(argv)

    cases = known_cases()
    if args.command == 'cases':
        for c in cases:
            print(f'{c["name"]}{"" if c["judged"] else "  (reported, not judged)"}')
        return 0
    try:
        spec = spec_mod.load(args.spec, cases)
    except spec_mod.SpecError as e:
        print(f'study.py: {e}', file=sys.stderr)
        return USAGE

    if args.command == 'trial':
        n = dict(spec.cases).get(args.case)
        if n is None or not 0 <= args.index < n:
            print(f'study.py: {args.case} trial {args.index}: not in {args.spec}', file=sys.stderr)
            return USAGE
        tr = spec_mod.trial(spec, args.case, args.index)
        from lieservo_study.trial import run_trial
        result = run_trial(tr.case, tr.seed, spec.observations, tr.kwargs())
        print(json.dumps({'case': tr.case, 'trial': tr.index, 'seed': tr.seed, 'draws': tr.kwargs(), **result},
                         indent=1))
        return 0

    results = args.results or default_results(args.spec)
    if args.command == 'run':
        if args.workers is not None and args.workers < 1:
            print('study.py: --workers must be >= 1', file=sys.stderr)
            return USAGE
        from lieservo_study.run import ConnectError, run
        try:
            return run(spec, results, args.scheduler, args.workers, progress=not args.no_progress)
        except (ResultsError, ConnectError) as e:
            print(f'study.py: {e}', file=sys.stderr)
            return USAGE

    from lieservo_study import report
    rf = ResultsFile(results, spec)
    try:
        rf.read()
    except ResultsError as e:
        print(f'study.py: {e}', file=sys.stderr)
        return USAGE
    if not rf.rows:
        print(f'study.py: {results}: no trials recorded yet (study.py run {args.spec})', file=sys.stderr)
        return USAGE
    out = args.out or os.path.splitext(results)[0]
    command = 'study.py ' + ' '.join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    try:
        page = report.write(spec, rf.rows, out, command, cases)
    except ValueError as e:
        print(f'study.py: {e}', file=sys.stderr)
        return USAGE
    print(f'report: {page} ({len(rf.rows)} of {len(spec.trials)} trials)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
