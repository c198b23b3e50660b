"""A study's results file: CSV, one row per trial, appended as each trial arrives.

Nothing lost, nothing twice: a row is written whole and flushed to disk before the next, and a
run first reads what the file holds, so a resumed study runs only the trials not yet recorded.
The one row a killed client can leave half-written (no end of line) is dropped on resume and
its trial run again. Every row carries the spec's digest; a file written for another spec, or
that is not a results file, is refused and left as it is.
"""
from __future__ import annotations

import csv
import io
import math
import os

from .spec import PARAMETERS, Spec

CRITERIA = ('reached', 'within_error', 'contact_kept', 'follower_contact_kept', 'upright', 'opposed')
FIGURES = ('target_error', 'final_distance', 'duration', 'max_tilt', 'min_opposition', 'support_friction',
           'skin_friction', 'gel_stiffness', 'start_offset', 'start_yaw_deg')
COLUMNS = (('spec', 'case', 'trial', 'seed') + tuple(f'draw_{p}' for p in PARAMETERS) + ('passed',) + CRITERIA
           + FIGURES)


class ResultsError(ValueError):
    """A results file that cannot be used for this spec; the message names the file."""


def row(spec: Spec, trial, result: dict) -> dict:
    """The CSV row of one trial: its identity, its draws and what lieservo.sim.push_trial returned."""
    r = {'spec': spec.digest, 'case': trial.case, 'trial': trial.index, 'seed': trial.seed}
    draws = trial.kwargs()
    for p in PARAMETERS:
        r[f'draw_{p}'] = draws.get(p, math.nan)
    for k in ('passed',) + CRITERIA + FIGURES:
        r[k] = result[k]
    return r


def _text(v) -> str:
    if isinstance(v, bool):
        return '1' if v else '0'
    if isinstance(v, float):
        return '' if math.isnan(v) else repr(v)
    return str(v)


def parse(r: dict) -> dict:
    """A row read back: numbers as numbers, flags as bools, empty draws as NaN."""
    out = {'spec': r['spec'], 'case': r['case'], 'trial': int(r['trial']), 'seed': int(r['seed'])}
    for k in COLUMNS[4:]:
        v = r[k]
        if k == 'passed' or k in CRITERIA:
            out[k] = v == '1'
        else:
            out[k] = math.nan if v == '' else float(v)
    return out


class ResultsFile:
    def __init__(self, path: str, spec: Spec):
        self.path, self.spec = path, spec
        self.rows = []   # parsed rows already in the file
        self._file = None

    def read(self) -> None:
        """Reads what the file holds (nothing when it does not exist); raises ResultsError for a
        file that is not this spec's. Writes nothing."""
        if not os.path.exists(self.path):
            return
        if not os.path.isfile(self.path):
            raise ResultsError(f'{self.path}: exists and is not a file')
        with open(self.path, encoding='utf-8', newline='') as f:
            text = f.read()
        if not text:
            return
        complete = text if text.endswith('\n') else text[:text.rfind('\n') + 1]  # drop a half-written row
        lines = list(csv.reader(io.StringIO(complete)))
        if not lines or tuple(lines[0]) != COLUMNS:
            raise ResultsError(f'{self.path}: not a study results file (its header is not the runner\'s); '
                               'it is left untouched: name another file with --results')
        seen = set()
        for n, cells in enumerate(lines[1:], start=2):
            if len(cells) != len(COLUMNS):
                raise ResultsError(f'{self.path}: line {n} has {len(cells)} fields, not {len(COLUMNS)}')
            r = parse(dict(zip(COLUMNS, cells)))
            if r['spec'] != self.spec.digest:
                raise ResultsError(f'{self.path}: written by a different spec (digest {r["spec"]}; '
                                   f'{self.spec.path} is {self.spec.digest}); it is left untouched: '
                                   'name another file with --results')
            key = (r['case'], r['trial'])
            if key in seen:
                raise ResultsError(f'{self.path}: line {n}: {key[0]} trial {key[1]} is recorded twice')
            seen.add(key)
            self.rows.append(r)
        self._truncate_to = len(complete.encode('utf-8'))
        self._had_partial = len(complete) != len(text)

    def recorded(self) -> set:
        return {(r['case'], r['trial']) for r in self.rows}

    def open(self) -> None:
        """Opens for appending: writes the header to a new file; drops a half-written last row."""
        new = not os.path.exists(self.path) or os.path.getsize(self.path) == 0
        if not new and getattr(self, '_had_partial', False):
            with open(self.path, 'r+b') as f:
                f.truncate(self._truncate_to)
        self._file = open(self.path, 'a', encoding='utf-8', newline='')
        self._writer = csv.writer(self._file, lineterminator='\n')
        if new:
            self._writer.writerow(COLUMNS)
            self._sync()

    def append(self, r: dict) -> None:
        self._writer.writerow([_text(r[k]) for k in COLUMNS])
        self._sync()
        self.rows.append(parse({k: _text(r[k]) for k in COLUMNS}))

    def _sync(self) -> None:
        self._file.flush()
        os.fsync(self._file.fileno())

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
