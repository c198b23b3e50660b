#!/usr/bin/python3
"""Measure how over- or under-confident a GDN's sigma is, on training images it did not train
on, and record per-component factors in the model card (models.gdn.sigma_calibration).

    /usr/bin/python3 examples/gdn/calibrate_sigma.py --run runs/gdn_holdout [--weights last] \
        [--card examples/gdn/models/model_card.json --write]

The run must come from `train.py --holdout N`: its DIR/holdout.txt (and, for a run trained on
train + val, DIR/holdout_val.txt) lists the rows the network never saw; the factors are
measured on all of them together. For a Gaussian, |error| <= sigma for 68.27 % of samples; the factor for
component j is the 68.27 % quantile of |error_j| / sigma_j over the held-out rows, so sigma_j
times it covers 68.27 % of them. A factor > 1 means the network's sigma is too small.

Why held-out rows and not the whole validation set: for a model trained on train only, the
validation set is where we report the paper's tables, and factors fitted there would flatter
the filter results (Table 2). A model trained on both sessions is calibrated on the rows it
held out of both.

--write stores the factors in the card's models.gdn entry, with where they came from. The C++
adapter (ModelCard::sigma_scale) then multiplies the network's sigma by them. The factors may
come from a different run than the exported model (e.g. a run trained like the shipped one on
5/6 of the training set): the source string says so. Re-exporting the GDN drops the entry,
since the factors belong to the weights they were measured for.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

GAUSS_1SIGMA = 0.6826894921370859  # P(|z| <= 1) for z ~ N(0, 1)
COMP = ['rho1', 'rho2', 'rho3', 'phi1', 'phi2', 'phi3']


def checked_err_sigma(err, sigma):
    """(err, sigma) as float64 [N, k] arrays; ValueError unless the shapes match, N > 0, sigma is
    finite and > 0 and err finite."""
    err, sigma = np.asarray(err, np.float64), np.asarray(sigma, np.float64)
    if err.shape != sigma.shape or err.ndim != 2 or len(err) == 0:
        raise ValueError(f'err {err.shape} and sigma {sigma.shape} must be the same [N, k], N > 0')
    if not (np.all(np.isfinite(sigma)) and np.all(sigma > 0) and np.all(np.isfinite(err))):
        raise ValueError('sigma must be finite and > 0, err finite')
    return err, sigma


def sigma_scale(err: np.ndarray, sigma: np.ndarray, coverage: float = GAUSS_1SIGMA) -> np.ndarray:
    """Per-column factor k with mean(|err| <= k sigma) = coverage (the quantile of |err|/sigma).
    err, sigma: [N, 6] in the same units; sigma > 0 and finite."""
    err, sigma = checked_err_sigma(err, sigma)
    return np.quantile(np.abs(err) / sigma, coverage, axis=0)


def coverage_of(err: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """Fraction of |err| <= sigma per column."""
    return np.mean(np.abs(err) <= sigma, axis=0)


def paired_difference(err_run: np.ndarray, err_base: np.ndarray):
    """Per column, the mean of |err_run| − |err_base| over the same rows and its standard error
    (rows paired: both models on the same images). [N, k] arrays, N ≥ 2."""
    err_run, err_base = np.asarray(err_run, np.float64), np.asarray(err_base, np.float64)
    if err_run.shape != err_base.shape or err_run.ndim != 2 or len(err_run) < 2:
        raise ValueError(f'errors {err_run.shape} and {err_base.shape} must be the same [N, k], N >= 2')
    d = np.abs(err_run) - np.abs(err_base)
    return d.mean(0), d.std(0, ddof=1) / np.sqrt(len(d))


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--run', required=True, help='a train.py --holdout run directory')
    ap.add_argument('--weights', choices=['best', 'last'], default='last')
    ap.add_argument('--data', default=None)
    ap.add_argument('--card', default=os.path.join(HERE, 'models', 'model_card.json'))
    ap.add_argument('--write', action='store_true', help='store the factors in --card')
    ap.add_argument('--threads', type=int, default=1)
    ap.add_argument('--baseline-run', default=None,
                    help='another run directory whose GDN is evaluated on the same held-out rows, for '
                    'comparison (its MAE per split is printed; e.g. the same recipe trained on train '
                    'only: on the held-out val rows it shows what seeing the val session gained. Its '
                    'own training rows are not excluded, so compare on splits it did not train on)')
    return ap.parse_args(argv)


def held_out_errors(args, held, model, baseline):
    """Per split: the network's errors and sigma on its held-out rows (network units: mm, deg),
    the split's size, and the baseline's errors on the same rows (when there is one)."""
    from dataset import default_data_dir, load_split
    import labels as L
    from export_onnx import torch_forward

    def outputs(net, x):
        return np.concatenate([torch_forward(net, x[i:i + 100]) for i in range(0, len(x), 100)])

    errs, sigs, n_total, base_errs = {}, {}, {}, {}
    for split, rows in held.items():
        sp = load_split(args.data or default_data_dir(), split, verbose=False)
        n_total[split] = len(sp.images)
        y = L.to_train_units(L.xi_from_euler6(sp.euler6))[rows]          # mm, deg
        x = sp.images[rows]
        out = outputs(model, x)
        errs[split] = out[:, :6] - y                                     # network units (mm, deg)
        sigs[split] = 1.0 / out[:, 6:].astype(np.float64)
        if baseline is not None:
            base_errs[split] = outputs(baseline, x)[:, :6] - y
    return errs, sigs, n_total, base_errs


def print_report(args, held, ck_path, ck, errs, sigs, base_errs, k):
    err = np.concatenate(list(errs.values()))
    sig = np.concatenate(list(sigs.values()))
    before, after = coverage_of(err, sig), coverage_of(err, sig * k)
    what = ' + '.join(f'{len(r)} {s}' for s, r in held.items())
    print(f'held-out images: {what}; {ck_path} (epoch {ck.get("epoch")})')
    print('component      ' + ' '.join(f'{c:>7}' for c in COMP))
    for split in held:
        print(f'MAE {split:<10} ' + ' '.join(f'{v:7.3f}' for v in np.abs(errs[split]).mean(0)))
    print('MAE (mm, deg)  ' + ' '.join(f'{v:7.3f}' for v in np.abs(err).mean(0)))
    for split in base_errs:
        print(f'baseline {split:<5} ' + ' '.join(f'{v:7.3f}' for v in np.abs(base_errs[split]).mean(0))
              + f'   ({args.baseline_run}, {args.weights} weights)')
        diff, se = paired_difference(errs[split], base_errs[split])
        print('  run - base    ' + ' '.join(f'{v:+7.3f}' for v in diff))
        print('  (paired s.e.) ' + ' '.join(f'{v:7.3f}' for v in se))
    print('mean sigma     ' + ' '.join(f'{v:7.3f}' for v in sig.mean(0)))
    print('coverage       ' + ' '.join(f'{v:7.3f}' for v in before) + f'   (Gaussian {GAUSS_1SIGMA:.3f})')
    print('scale          ' + ' '.join(f'{v:7.3f}' for v in k))
    print('coverage after ' + ' '.join(f'{v:7.3f}' for v in after))
    for split in held:
        print(f'cov. {split:<9} ' + ' '.join(f'{v:7.3f}' for v in coverage_of(errs[split], sigs[split] * k)))
    return before, after, what


def write_calibration(args, argv, ck, held, n_total, k, before, after, what):
    """Stores the factors in the card's models.gdn entry, with where they came from."""
    with open(args.card) as f:
        card = json.load(f)
    if 'gdn' not in card.get('models', {}):
        raise SystemExit(f'{args.card}: no models.gdn entry to calibrate')
    hist = {}
    hp = os.path.join(args.run, 'gdn_history.json')
    if os.path.isfile(hp):
        with open(hp) as f:
            hist = json.load(f)
    card['models']['gdn']['sigma_calibration'] = {
        'scale': [round(float(v), 4) for v in k],
        'source': (f'quantile {GAUSS_1SIGMA:.4f} of |error|/sigma per component on the '
                   f'images held out of run {os.path.basename(os.path.normpath(args.run))} '
                   f'({what}; {args.weights} weights, epoch {ck.get("epoch")}; trained on the '
                   'other ' + ' + '.join(f'{n_total[s] - len(r)} {s}' for s, r in held.items()) + ')'),
        'held_out': {s: len(r) for s, r in held.items()},
        'held_out_coverage_before': [round(float(v), 4) for v in before],
        'held_out_coverage_after': [round(float(v), 4) for v in after],
        'run_command': hist.get('args'),
        'command': 'examples/gdn/calibrate_sigma.py ' + ' '.join(argv if argv is not None else sys.argv[1:]),
    }
    with open(args.card, 'w') as f:
        json.dump(card, f, indent=1)
    print('wrote models.gdn.sigma_calibration to', args.card)


def main(argv=None) -> int:
    import torch
    from export_onnx import load_ckpt, run_held_out
    from train import holdout_file

    args = parse_args(argv)
    torch.set_num_threads(args.threads)
    # The held-out rows of every session the run trained on (train only, or train and val).
    held = run_held_out(args.run)
    if 'train' not in held:
        raise SystemExit(f'{os.path.join(args.run, holdout_file("train"))}: not found '
                         '(train the run with --holdout N)')
    ck_path = os.path.join(args.run, f'gdn_{args.weights}.pt')
    model, ck = load_ckpt(ck_path)
    if ck['kind'] != 'gdn':
        raise SystemExit(f'{ck_path}: a {ck["kind"]} checkpoint has no sigma')
    baseline = None
    if args.baseline_run:
        bp = os.path.join(args.baseline_run, f'gdn_{args.weights}.pt')
        if not os.path.isfile(bp):
            raise SystemExit(f'--baseline-run: {bp} not found (a train.py run directory with GDN weights)')
        baseline, _ = load_ckpt(bp)
    errs, sigs, n_total, base_errs = held_out_errors(args, held, model, baseline)
    k = sigma_scale(np.concatenate(list(errs.values())), np.concatenate(list(sigs.values())))
    before, after, what = print_report(args, held, ck_path, ck, errs, sigs, base_errs, k)
    if args.write:
        write_calibration(args, argv, ck, held, n_total, k, before, after, what)
    return 0


if __name__ == '__main__':
    sys.exit(main())
