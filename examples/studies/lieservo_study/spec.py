"""A study's spec: which pushing cases, how many trials each, and which parameters each trial draws.

A spec is a TOML or JSON file (by its extension):

    name = "single-arm pushing, 200 trials"
    seed = 1                       # the study's seed: each trial's own seed derives from it
    observations = "gaussian"      # or "real" (lieservo.sim.push_trial)
    trials = 200                   # per case, unless the case says otherwise
    cases = ["pushing_single_*", {pattern = "pushing_dual_short_foam_*", trials = 50}]
    exclude = ["*_centralised_*"]  # patterns of cases to leave out
    judged_only = true             # patterns match the judged cases only (the default)

    [draw]                         # uniform ranges [min, max]; a parameter left out keeps the
    skin_friction = [0.5, 1.0]     # trial's own draw (the demo's: docs/simulation.md)

Each trial's seed is a hash of (study seed, case, trial index), and its draws come from that seed
alone, so any one trial can be re-run by itself (study.py trial) and gives the same result.
"""
from __future__ import annotations

import dataclasses
import fnmatch
import hashlib
import json
import math
import os
import random

try:
    import tomllib  # Python 3.11
except ImportError:  # pragma: no cover - Debian 12 has 3.11
    tomllib = None

# The parameters a spec may draw: the range each must stay in (within what the simulation
# accepts: TaskOptions::validate, ContactParams::validate), whether its lower end is open, and
# what it is.
PARAMETERS = {
    'support_friction_scale': ((0.0, 3.0), True, "factor on the support's friction mu_s (the demo: 0.9-1.1)"),
    'skin_friction': ((0.0, 2.0), False, 'mu_c, skin on object (default 0.8)'),
    'gel_stiffness': ((0.0, 10.0), True, 'k_gel, N/mm (default 0.8)'),
    'start_offset': ((-50.0, 50.0), False, "the object's sideways start offset, mm (the demo: normal, sd 2, clipped at 4)"),
    'start_yaw_deg': ((-45.0, 45.0), False, "the object's start yaw, deg (the demo: normal, sd 2, clipped at 4)"),
}
OBSERVATIONS = ('gaussian', 'real')
KEYS = {'name', 'seed', 'observations', 'trials', 'cases', 'exclude', 'judged_only', 'draw'}


class SpecError(ValueError):
    """A spec that cannot be run; the message names the file and the field."""


@dataclasses.dataclass(frozen=True)
class Trial:
    case: str
    index: int  # 0-based within its case
    seed: int
    draws: tuple  # ((parameter, value), ...) in PARAMETERS order

    def kwargs(self) -> dict:
        return dict(self.draws)


@dataclasses.dataclass
class Spec:
    path: str
    name: str
    seed: int
    observations: str
    draw: dict       # parameter -> (lo, hi)
    cases: list      # [(case name, trials)] in the simulation's order
    digest: str      # identifies the spec's content (the results file records it)

    @property
    def trials(self) -> list:
        return [trial(self, c, i) for c, n in self.cases for i in range(n)]


def trial_seed(study_seed: int, case: str, index: int) -> int:
    """The trial's own seed: 63 bits of sha256("seed:case:index")."""
    h = hashlib.sha256(f'{study_seed}:{case}:{index}'.encode()).digest()
    return int.from_bytes(h[:8], 'little') >> 1


def trial(spec: Spec, case: str, index: int) -> Trial:
    s = trial_seed(spec.seed, case, index)
    rng = random.Random(s)
    draws = tuple((p, rng.uniform(*spec.draw[p])) for p in PARAMETERS if p in spec.draw)
    return Trial(case, index, s, draws)


def _read(path: str) -> dict:
    if not os.path.isfile(path):
        raise SpecError(f'{path}: no such file')
    ext = os.path.splitext(path)[1].lower()
    try:
        if ext == '.toml':
            if tomllib is None:
                raise SpecError(f'{path}: TOML needs Python 3.11 (tomllib); write the spec as JSON')
            with open(path, 'rb') as f:
                return tomllib.load(f)
        if ext == '.json':
            with open(path, encoding='utf-8') as f:
                data = json.load(f)
            if not isinstance(data, dict):
                raise SpecError(f'{path}: the spec must be a JSON object')
            return data
    except (ValueError, UnicodeDecodeError) as e:
        if isinstance(e, SpecError):
            raise
        raise SpecError(f'{path}: not valid {ext[1:].upper()}: {e}') from None
    raise SpecError(f'{path}: a spec is a .toml or .json file')


def _integer(path, field, v, lo):
    if isinstance(v, bool) or not isinstance(v, int) or v < lo:
        raise SpecError(f'{path}: {field} must be an integer >= {lo}, not {v!r}')
    return v


def load(path: str, known_cases: list) -> Spec:
    """Reads and checks the spec at `path` against `known_cases` (lieservo.sim.cases()); raises
    SpecError naming the field."""
    data = _read(path)
    unknown = sorted(set(data) - KEYS)
    if unknown:
        raise SpecError(f'{path}: unknown field {unknown[0]!r} (fields: {", ".join(sorted(KEYS))})')
    name = data.get('name')
    if not isinstance(name, str) or not name.strip():
        raise SpecError(f'{path}: name must be a non-empty string')
    seed = _integer(path, 'seed', data.get('seed', 1), 0)
    observations = data.get('observations', 'gaussian')
    if observations not in OBSERVATIONS:
        raise SpecError(f'{path}: observations must be one of {", ".join(OBSERVATIONS)}, not {observations!r}')
    default_trials = _integer(path, 'trials', data.get('trials', 1), 1)
    judged_only = data.get('judged_only', True)
    if not isinstance(judged_only, bool):
        raise SpecError(f'{path}: judged_only must be true or false')

    draw = {}
    table = data.get('draw', {})
    if not isinstance(table, dict):
        raise SpecError(f'{path}: draw must be a table of parameter = [min, max]')
    for p, r in table.items():
        if p not in PARAMETERS:
            raise SpecError(f'{path}: draw.{p}: unknown parameter (parameters: {", ".join(PARAMETERS)})')
        if (not isinstance(r, list) or len(r) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, float))
                                                          for x in r)):
            raise SpecError(f'{path}: draw.{p} must be [min, max], two numbers')
        lo, hi = float(r[0]), float(r[1])
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise SpecError(f'{path}: draw.{p}: the range must be finite')
        if lo > hi:
            raise SpecError(f'{path}: draw.{p}: min {lo:g} > max {hi:g}')
        (a, b), open_below, _ = PARAMETERS[p]
        if lo < a or hi > b or (open_below and lo <= a):
            bound = f'in ({a:g}, {b:g}]' if open_below else f'in [{a:g}, {b:g}]'
            raise SpecError(f'{path}: draw.{p}: [{lo:g}, {hi:g}] must lie {bound}')
        draw[p] = (lo, hi)

    entries = data.get('cases')
    if not isinstance(entries, list) or not entries:
        raise SpecError(f'{path}: cases must be a non-empty list of case names or patterns')
    exclude = data.get('exclude', [])
    if not isinstance(exclude, list) or not all(isinstance(x, str) for x in exclude):
        raise SpecError(f'{path}: exclude must be a list of case patterns')
    names = [c['name'] for c in known_cases if (c['judged'] or not judged_only)
             and not any(fnmatch.fnmatchcase(c['name'], x) for x in exclude)]
    chosen = {}
    for i, e in enumerate(entries):
        field = f'cases[{i}]'
        if isinstance(e, str):
            pattern, n = e, default_trials
        elif isinstance(e, dict):
            extra = sorted(set(e) - {'pattern', 'trials'})
            if extra or not isinstance(e.get('pattern'), str):
                raise SpecError(f'{path}: {field} must be a pattern or a table {{pattern = "...", trials = N}}')
            pattern, n = e['pattern'], _integer(path, f'{field}.trials', e.get('trials', default_trials), 1)
        else:
            raise SpecError(f'{path}: {field} must be a pattern or a table {{pattern = "...", trials = N}}')
        matched = [c for c in names if fnmatch.fnmatchcase(c, pattern)]
        if not matched:
            which = 'judged case' if judged_only else 'case'
            raise SpecError(f'{path}: {field}: {pattern!r} names no {which} (study.py cases lists them)')
        for c in matched:
            chosen[c] = n
    cases = [(c, chosen[c]) for c in names if c in chosen]

    canonical = json.dumps({'name': name, 'seed': seed, 'observations': observations, 'draw': draw,
                            'cases': cases}, sort_keys=True)
    digest = hashlib.sha256(canonical.encode()).hexdigest()[:16]
    return Spec(path, name, seed, observations, draw, cases, digest)
