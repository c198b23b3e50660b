"""A study's report: for each case and criterion the pass rate with its Wilson 95 % interval; for
each parameter the trials drew, the pass rate and the target error against it; the start
placements of the misses over the placement box. An HTML page of SVG figures, as the demo's.
"""
from __future__ import annotations

import html
import math
import os

from .results import CRITERIA
from .spec import Spec

Z95 = 1.959963984540054  # the standard normal's 97.5 % quantile
SINGLE_ARM = ('reached', 'within_error', 'contact_kept')
LABELS = {'passed': 'all criteria', 'reached': 'reached the target', 'within_error': 'error ≤ 10 mm',
          'contact_kept': 'pusher kept contact', 'follower_contact_kept': 'follower kept contact',
          'upright': 'upright (tilt ≤ 10°)', 'opposed': 'normals opposed (≥ 150°)'}
# What each figure's x axis is: the value the trial ran with (results.FIGURES).
PLOTTED = {'support_friction': 'μ_s, support friction', 'skin_friction': 'μ_c, skin friction',
           'gel_stiffness': 'k_gel (N/mm)', 'start_offset': 'start offset (mm)', 'start_yaw_deg': 'start yaw (deg)'}
DEMO_BOX = (-4.0, 4.0)  # the demo's placement: normal, sd 2 mm and 2°, clipped at 2 sd
MARKER = '.lieservo-output'


def wilson(k: int, n: int, z: float = Z95) -> tuple:
    """The Wilson score interval (lo, hi) of k successes in n trials (n > 0)."""
    p = k / n
    d = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / d
    half = z / d * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def criteria_of(case: dict) -> tuple:
    """The criteria that judge a case (an entry of lieservo.sim.cases()): the dual-arm ones hold for two arms."""
    return ('passed',) + (CRITERIA if case['dual_arm'] else SINGLE_ARM)


def group_of(case: dict) -> str:
    """The figures' group of a case (an entry of lieservo.sim.cases()): its arms and follower."""
    if case['dual_arm']:
        return 'centralised dual arm' if case['centralised'] else 'dual arm'
    return 'single arm'


def rates(rows: list, cases: dict) -> dict:
    """{case: {criterion: (k, n, lo, hi)}} over `rows`; `cases`: {name: lieservo.sim.cases()'s entry}."""
    out = {}
    for case in dict.fromkeys(r['case'] for r in rows):
        rs = [r for r in rows if r['case'] == case]
        out[case] = {}
        for c in criteria_of(cases[case]):
            k = sum(1 for r in rs if r[c])
            out[case][c] = (k, len(rs)) + wilson(k, len(rs))
    return out


def claim_folder(out: str) -> None:
    """Makes `out` the report's folder; refuses a folder that is neither empty nor a lieservo output."""
    if os.path.exists(out):
        if not os.path.isdir(out):
            raise ValueError(f'--out {out}: exists and is not a folder')
        if os.listdir(out) and not os.path.exists(os.path.join(out, MARKER)):
            raise ValueError(f'--out {out}: the folder exists, is not empty and was not made by a lieservo '
                             f'program (no {MARKER} in it); it is left untouched: name another folder')
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, MARKER), 'w', encoding='utf-8') as f:
        f.write('written by study.py report; a later run may overwrite what is in this folder\n')


def _figure_parameter(rows, group, p, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 3.8))
    xs = [r[p] for r in rows]
    lo, hi = min(xs), max(xs)
    bins = 8
    width = (hi - lo) / bins
    for g in dict.fromkeys(group(r) for r in rows):
        gr = [r for r in rows if group(r) == g]
        centres, rate, err_lo, err_hi = [], [], [], []
        for i in range(bins):
            left = lo + i * width
            inside = [r for r in gr if left <= r[p] < left + width or (i == bins - 1 and r[p] == hi)]
            if not inside:
                continue
            k = sum(r['passed'] for r in inside)
            w_lo, w_hi = wilson(k, len(inside))
            centres.append(left + width / 2)
            rate.append(k / len(inside))
            err_lo.append(max(0.0, k / len(inside) - w_lo))  # ≥ 0: the ends are rounded at k = 0 and k = n
            err_hi.append(max(0.0, w_hi - k / len(inside)))
        a.errorbar(centres, rate, yerr=[err_lo, err_hi], marker='o', capsize=3, label=g)
    a.set_xlabel(PLOTTED[p])
    a.set_ylabel('pass rate (Wilson 95 %)')
    a.set_ylim(-0.02, 1.02)
    a.legend(fontsize=8)
    a.grid(alpha=0.3)
    ok = [r for r in rows if r['passed']]
    miss = [r for r in rows if not r['passed']]
    b.scatter([r[p] for r in ok], [r['target_error'] for r in ok], s=5, c='0.6', label=f'passed ({len(ok)})')
    b.scatter([r[p] for r in miss], [r['target_error'] for r in miss], s=14, c='#d62728', marker='x',
              label=f'missed ({len(miss)})')
    b.axhline(10.0, ls='--', c='k', lw=0.8)
    b.set_xlabel(PLOTTED[p])
    b.set_ylabel('final target error (mm)')
    b.legend(fontsize=8)
    b.grid(alpha=0.3)
    fig.suptitle(f'Against {PLOTTED[p]}: every trial of the study')
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def _figure_placements(rows, group, spec, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    groups = list(dict.fromkeys(group(r) for r in rows))
    fig, axes = plt.subplots(1, len(groups), figsize=(4.6 * len(groups), 4.2), squeeze=False)
    bx = spec.draw.get('start_offset', DEMO_BOX)
    by = spec.draw.get('start_yaw_deg', DEMO_BOX)
    for ax, g in zip(axes[0], groups):
        gr = [r for r in rows if group(r) == g]
        ok = [r for r in gr if r['passed']]
        miss = [r for r in gr if not r['passed']]
        ax.add_patch(matplotlib.patches.Rectangle((bx[0], by[0]), bx[1] - bx[0], by[1] - by[0], fill=False,
                                                  ls='--', ec='k', lw=0.8))
        ax.scatter([r['start_offset'] for r in ok], [r['start_yaw_deg'] for r in ok], s=4, c='0.7',
                   label=f'passed ({len(ok)})')
        ax.scatter([r['start_offset'] for r in miss], [r['start_yaw_deg'] for r in miss], s=22, c='#d62728',
                   marker='x', label=f'missed ({len(miss)})')
        ax.set_title(g)
        ax.set_xlabel('start offset (mm)')
        ax.set_ylabel('start yaw (deg)')
        ax.legend(fontsize=8, loc='upper right')
        ax.grid(alpha=0.3)
    fig.suptitle('Start placements of the misses (dashed: the placement box)')
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def write(spec: Spec, rows: list, out: str, command: str, known_cases: list) -> str:
    """Writes out/index.html and its figures; returns the page's path. `known_cases`:
    lieservo.sim.cases(), which says each case's arms (the spec has checked the rows' cases)."""
    claim_folder(out)
    cases = {c['name']: c for c in known_cases}
    table = rates(rows, cases)

    def group(row):
        return group_of(cases[row['case']])

    figures = []
    for p in PLOTTED:
        xs = [r[p] for r in rows]
        if xs and max(xs) > min(xs):
            name = f'against_{p}.svg'
            _figure_parameter(rows, group, p, os.path.join(out, name))
            figures.append(name)
    _figure_placements(rows, group, spec, os.path.join(out, 'placements.svg'))
    figures.append('placements.svg')

    e = html.escape
    columns = ('passed',) + CRITERIA
    parts = [f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{e(spec.name)}</title>',
             '<style>body{font-family:sans-serif;margin:2em;max-width:1300px}table{border-collapse:collapse;'
             'font-size:13px}td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}td:first-child'
             '{text-align:left}.low{background:#fde0dc}img{max-width:100%;display:block;margin:1em 0}</style>',
             '</head><body>', f'<h1>{e(spec.name)}</h1>',
             f'<p>{len(rows)} trials in {len(table)} cases; observations: {e(spec.observations)}; spec '
             f'{e(os.path.basename(spec.path))} (digest {spec.digest}, seed {spec.seed}); drawn: '
             + (e(', '.join(f'{p} ∈ [{lo:g}, {hi:g}]' for p, (lo, hi) in spec.draw.items())) or 'nothing')
             + ' (the rest as each trial of the demo draws it).</p>',
             f'<p>Made by <code>{e(command)}</code>.</p>',
             '<h2>Pass rates, with Wilson 95 % intervals</h2>',
             '<table><tr><th>case</th><th>trials</th>' + ''.join(f'<th>{e(LABELS[c])}</th>' for c in columns)
             + '</tr>']
    for case, by in table.items():
        n = next(iter(by.values()))[1]
        cells = []
        for c in columns:
            if c not in by:
                cells.append('<td>—</td>')
                continue
            k, n_, lo, hi = by[c]
            cls = ' class="low"' if k < n_ else ''
            cells.append(f'<td{cls}>{k}/{n_}: {100 * k / n_:.1f} % [{100 * lo:.1f}, {100 * hi:.1f}]</td>')
        parts.append(f'<tr><td>{e(case)}</td><td>{n}</td>' + ''.join(cells) + '</tr>')
    parts.append('</table>')
    parts.append('<h2>Against each drawn parameter, and where the misses started</h2>')
    parts += [f'<img src="{f}" alt="{f}">' for f in figures]
    parts.append('</body></html>\n')
    page = os.path.join(out, 'index.html')
    with open(page, 'w', encoding='utf-8') as f:
        f.write('\n'.join(parts))
    return page
