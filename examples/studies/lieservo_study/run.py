"""Running a study on Dask: every trial not yet in the results file becomes one task; each result
is appended to the file as it arrives.

Where it runs: an embedded LocalCluster (one single-threaded worker process per core, or
`workers`), or an existing scheduler at `scheduler` (tcp://HOST:PORT) and whatever workers have
joined it. A worker that dies mid-trial has its task rescheduled by Dask's scheduler on another
worker; the trial's result still arrives once, so the file holds it once.
"""
from __future__ import annotations

import logging
import os
import sys

from .results import ResultsFile, row
from .spec import Spec
from .trial import run_trial


class ConnectError(RuntimeError):
    """The scheduler cannot be reached; the message names its address."""


def _worker_path() -> str:
    """PYTHONPATH for the LocalCluster's worker processes: where lieservo and this package are."""
    import lieservo
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    package = os.path.dirname(os.path.dirname(os.path.abspath(lieservo.__file__)))
    return os.pathsep.join(p for p in (package, here, os.environ.get('PYTHONPATH', '')) if p)


def connect(scheduler: str | None, workers: int | None):
    """(client, cluster or None). Raises ConnectError for a scheduler that does not answer."""
    from distributed import Client, LocalCluster
    if scheduler:
        try:
            return Client(scheduler, timeout='10s'), None
        except Exception as e:  # OSError, TimeoutError, ValueError for a malformed address
            raise ConnectError(f'--scheduler {scheduler}: cannot reach the scheduler ({type(e).__name__}: {e})') from None
    os.environ['PYTHONPATH'] = _worker_path()  # inherited by the worker processes
    n = workers or os.cpu_count() or 1
    # The scheduler starts its HTTP server (health and metrics routes) whatever the dashboard
    # setting; with no address it takes port 8787, which another cluster may hold. ':0' lets the
    # system choose a free port.
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=':0',
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def run(spec: Spec, results_path: str, scheduler: str | None = None, workers: int | None = None,
        progress: bool = True) -> int:
    """Runs the trials of `spec` missing from `results_path`. Returns the exit status: 0 when every
    trial is recorded, 1 when some trial raised (the others are recorded), 130 on Ctrl-C (what
    arrived is recorded: the same command resumes). Raises ResultsError or ConnectError before
    anything is written."""
    from distributed import as_completed
    from tqdm import tqdm

    results = ResultsFile(results_path, spec)
    results.read()
    done = results.recorded()
    trials = spec.trials
    pending = [t for t in trials if (t.case, t.index) not in done]
    print(f'{spec.name}: {len(trials)} trials in {len(spec.cases)} cases, {len(done)} already in {results_path}')
    if not pending:
        return 0
    client, cluster = connect(scheduler, workers)
    failed = 0
    bar = None
    try:
        n_workers = len(client.scheduler_info().get('workers', {}))
        print(f'running {len(pending)} trials on {"the cluster at " + scheduler if scheduler else "a local cluster"} '
              f'({n_workers} workers now)')
        results.open()
        futures = {}
        for t in pending:
            f = client.submit(run_trial, t.case, t.seed, spec.observations, t.kwargs(),
                              key=f'lieservo-trial-{spec.digest}-{t.case}-{t.index}')
            futures[f] = t
        bar = tqdm(total=len(trials), initial=len(done), unit='trial', file=sys.stderr, disable=not progress,
                   smoothing=0.05)
        for f in as_completed(futures):
            t = futures[f]
            try:
                results.append(row(spec, t, f.result()))
            except Exception as e:  # the trial raised on its worker: reported, not recorded
                failed += 1
                print(f'\n{t.case} trial {t.index} (seed {t.seed}): {type(e).__name__}: {e}', file=sys.stderr)
            bar.update(1)
        bar.close()
        bar = None
    except KeyboardInterrupt:
        if bar is not None:
            bar.close()
        print(f'\ninterrupted: {len(results.rows)} of {len(trials)} trials recorded in {results_path}; '
              'the same command resumes', file=sys.stderr)
        return 130
    finally:
        results.close()
        client.close()
        if cluster is not None:
            cluster.close()
    if failed:
        print(f'{failed} trials raised (above); they are not recorded: the same command runs them again',
              file=sys.stderr)
        return 1
    print(f'all {len(trials)} trials recorded in {results_path}')
    return 0
