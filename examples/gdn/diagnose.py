#!/usr/bin/python3
"""Where the shipped models' errors come from: the numbers behind examples/gdn/README.md,
"Diagnosis". Nothing here is tuned on the validation set; it only measures.

    /usr/bin/python3 examples/gdn/diagnose.py [--holdout-run DIR] [--train-every 3]

0. The label distributions of the two splits (depth bins, mean shear, twist and tilt): the
   validation session samples the same contacts as the training session.
1. MAE by contact depth z on training images the shipped models trained on and on the
   validation set (GDN and CNN): is the shear error a failure to fit or to generalise?
2. Coverage (fraction of |error| <= sigma) of the GDN's sigma by depth, with the network's
   sigma and with the card's constant calibration factors (models.gdn.sigma_calibration).
3. A scalar model of one Bayes-filter correction per component, in the concentrated regime:
   the prior is the truth plus p ~ N(0, sigma_psi^2) (the replay's T_k = exp(psi^) X_k X_{k-1}^-1
   with the filtered error neglected), so the fused error is (1 - w) e + w p with
   w = sigma^2 / (sigma^2 + sigma_psi^2). It shows which depths the filter helps or hurts when
   sigma is wrong, without the SE(3) coupling of lieservo_replay.
4. With --holdout-run (a `train.py --holdout N` run, e.g. run H): a power-law calibration
   sigma' = a sigma^b per component (network units mm, deg), fitted on the held-out training
   rows by quantile regression of log|error| on log sigma at 68.27 %, and its coverage by depth
   on the validation set. A constant factor is the special case b = 1.
5. With --holdout-run: that run's MAE by depth on its held-out training rows and on the
   validation set: at which depths the validation session is harder.
6. With --geometry (alone, in seconds): do the two sessions' images differ as a whole? The
   affine warp between the mean training and the mean validation image (shift, rotation,
   scale; cv2.findTransformECC) and their grey levels, beside the same numbers between the
   two halves of each split (the noise floor).
7. With --slip (alone, in seconds): where the skin slips. The shear the reproduction GDN reads
   from the val session's images, along the labelled shear direction, by depth and by labelled
   shear: once the skin slips the image stops changing, so the read shear levels off at the
   slip radius (docs/simulation.md, "The gel").

Units: mm and degrees (the networks' output units); sigma_psi in mm for rho, degrees for phi,
as in the paper's Table 2.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from calibrate_sigma import COMP, GAUSS_1SIGMA, checked_err_sigma  # noqa: E402

DEPTH_EDGES = (0.5, 1.5, 3.0, 6.0)  # mm: shallow contacts, where the sensor slips, come first


def bin_index(z: np.ndarray, edges=DEPTH_EDGES) -> np.ndarray:
    """Bin of each depth: 0 for edges[0] <= z < edges[1], ...; the last bin is closed on the
    right. Depths outside [edges[0], edges[-1]] raise ValueError."""
    z = np.asarray(z, np.float64)
    if np.any(z < edges[0]) or np.any(z > edges[-1]) or not np.all(np.isfinite(z)):
        raise ValueError(f'depths outside [{edges[0]}, {edges[-1]}]')
    return np.minimum(np.searchsorted(edges, z, side='right') - 1, len(edges) - 2)


def label_summary(euler6: np.ndarray, edges=DEPTH_EDGES) -> np.ndarray:
    """What a split samples, from its labels (x, y, z, alpha, beta, gamma) in mm and deg: the
    fraction of contacts in each depth bin, then the mean shear |(x, y)| (mm), twist |gamma| and
    tilt |(alpha, beta)| (deg). Equal summaries rule out a sampling difference between sessions."""
    e = np.asarray(euler6, np.float64)
    if e.ndim != 2 or e.shape[1] != 6 or len(e) == 0:
        raise ValueError('euler6 must be a non-empty [N, 6] array')
    frac = np.bincount(bin_index(e[:, 2], edges), minlength=len(edges) - 1) / len(e)
    return np.concatenate([frac, [np.hypot(e[:, 0], e[:, 1]).mean(), np.abs(e[:, 5]).mean(),
                                  np.hypot(e[:, 3], e[:, 4]).mean()]])


def mae_by_bin(err: np.ndarray, z: np.ndarray, edges=DEPTH_EDGES):
    """(counts [B], MAE [B, k]) of the rows of err [N, k] per depth bin (NaN for an empty bin)."""
    b = bin_index(z, edges)
    nb = len(edges) - 1
    counts = np.bincount(b, minlength=nb)
    mae = np.full((nb, err.shape[1]), np.nan)
    for i in range(nb):
        if counts[i]:
            mae[i] = np.abs(err[b == i]).mean(0)
    return counts, mae


def coverage_by_bin(err: np.ndarray, sigma: np.ndarray, z: np.ndarray, edges=DEPTH_EDGES) -> np.ndarray:
    """Fraction of |err| <= sigma per depth bin and column ([B, k]; NaN for an empty bin)."""
    b = bin_index(z, edges)
    out = np.full((len(edges) - 1, err.shape[1]), np.nan)
    for i in range(len(edges) - 1):
        if np.any(b == i):
            out[i] = np.mean(np.abs(err[b == i]) <= sigma[b == i], axis=0)
    return out


def fit_power_calibration(err: np.ndarray, sigma: np.ndarray, coverage: float = GAUSS_1SIGMA,
                          exponents=np.arange(0.0, 2.0005, 0.01)):
    """Per column, (a, b) such that |err| <= a sigma^b for `coverage` of the rows, uniformly in
    sigma: the linear quantile regression log|err| ~ log a + b log sigma at that quantile
    (pinball loss). For a given b the best log a is the quantile of log|err| - b log sigma, so
    b is found on the grid `exponents`. Returns arrays a [k], b [k]."""
    err, sigma = checked_err_sigma(err, sigma)
    tau = coverage
    a, b = np.empty(err.shape[1]), np.empty(err.shape[1])
    tiny = np.finfo(np.float64).tiny
    for j in range(err.shape[1]):
        le, ls = np.log(np.maximum(np.abs(err[:, j]), tiny)), np.log(sigma[:, j])
        best = None
        for e in exponents:
            r = le - e * ls
            la = np.quantile(r, tau)
            r = r - la
            loss = np.mean(np.maximum(tau * r, (tau - 1.0) * r))
            if best is None or loss < best[0]:
                best = (loss, e, la)
        b[j], a[j] = best[1], np.exp(best[2])
    return a, b


def scalar_filter_ratio(err: np.ndarray, sigma: np.ndarray, sigma_psi, reps: int = 20,
                        seed: int = 0) -> np.ndarray:
    """MAE of (1 - w) e + w p over MAE of e per column, w = sigma^2 / (sigma^2 + sigma_psi^2),
    p ~ N(0, sigma_psi^2), averaged over `reps` draws of p. sigma_psi: scalar or per column."""
    err, sigma = np.asarray(err, np.float64), np.asarray(sigma, np.float64)
    sp = np.broadcast_to(np.asarray(sigma_psi, np.float64), (err.shape[1],))
    w = sigma ** 2 / (sigma ** 2 + sp ** 2)
    rng = np.random.RandomState(seed)
    base = np.abs(err).mean(0)
    out = np.zeros(err.shape[1])
    for _ in range(reps):
        p = rng.standard_normal(err.shape) * sp
        out += np.abs((1.0 - w) * err + w * p).mean(0)
    return out / reps / base


def session_geometry(a: np.ndarray, b: np.ndarray):
    """The affine warp that aligns image b with image a (cv2.findTransformECC, the enhanced
    correlation coefficient, on the interior: an 8-pixel border is masked out), as the shift of
    the image centre (dx, dy in pixels), the rotation (degrees, counter-clockwise as
    cv2.getRotationMatrix2D) and the scale (square root of the determinant). Returns
    (dx, dy, rotation, scale, correlation)."""
    import cv2
    a = np.asarray(a, np.float32)
    b = np.asarray(b, np.float32)
    if a.ndim != 2 or a.shape != b.shape or min(a.shape) <= 16:
        raise ValueError(f'two equal 2-D images larger than 16 px expected, got {a.shape} and {b.shape}')
    mask = np.zeros(a.shape, np.uint8)
    mask[8:-8, 8:-8] = 1
    crit = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 500, 1e-8)
    cc, W = cv2.findTransformECC(a, b, np.eye(2, 3, dtype=np.float32), cv2.MOTION_AFFINE, crit, mask, 5)
    A = W[:, :2].astype(np.float64)
    c = np.array([(a.shape[1] - 1) / 2.0, (a.shape[0] - 1) / 2.0])
    t = W[:, 2].astype(np.float64) + A @ c - c
    rotation = -np.degrees(np.arctan2(A[1, 0] - A[0, 1], A[0, 0] + A[1, 1]))
    return float(t[0]), float(t[1]), float(rotation), float(np.sqrt(abs(np.linalg.det(A)))), float(cc)


def print_session_geometry(tr, va) -> None:
    a = tr.images_u8.astype(np.float64)
    b = va.images_u8.astype(np.float64)
    print('6. The two sessions as a whole: the affine warp between mean images (128 x 128 input)')
    print(f'{"":24}{"dx px":>8}{"dy px":>8}{"rot deg":>9}{"scale":>8}{"grey mean":>11}{"grey std":>10}')
    for label, x, y in (('val vs train', a, b), ('train: half vs half', a[::2], a[1::2]),
                        ('val: half vs half', b[::2], b[1::2])):
        dx, dy, rot, sc, _ = session_geometry(x.mean(0), y.mean(0))
        grey = f'{y.mean() - x.mean():+.2f}'
        std = f'{y.std() / x.std():.4f}'
        print(f'{label:24}{dx:8.3f}{dy:8.3f}{rot:9.4f}{sc:8.4f}{grey:>11}{std:>10}')
    print('(grey mean: difference of the mean grey level, 0-255; grey std: ratio of the standard deviations)')


SLIP_DEPTHS = (0.5, 1.5, 2.5, 3.5, 4.5, 6.01)   # mm
SLIP_SHEARS = (0.0, 1.0, 2.0, 3.0, 4.0, 5.01)   # mm


def slip_table(read_shear: np.ndarray, euler6: np.ndarray):
    """Mean read shear along the labelled direction, [depth bin][label |s| bin], and counts."""
    s = euler6[:, :2]
    mag = np.linalg.norm(s, axis=1)
    along = np.sum(read_shear * s / np.maximum(mag, 1e-12)[:, None], axis=1)
    z = euler6[:, 2]
    mean = np.full((len(SLIP_DEPTHS) - 1, len(SLIP_SHEARS) - 1), np.nan)
    count = np.zeros_like(mean, dtype=np.int64)
    for i, (a, b) in enumerate(zip(SLIP_DEPTHS[:-1], SLIP_DEPTHS[1:])):
        for j, (c, d) in enumerate(zip(SLIP_SHEARS[:-1], SLIP_SHEARS[1:])):
            m = (z >= a) & (z < b) & (mag >= c) & (mag < d)
            count[i, j] = m.sum()
            if m.any():
                mean[i, j] = along[m].mean()
    return mean, count


def print_slip(read_shear: np.ndarray, euler6: np.ndarray) -> None:
    mean, count = slip_table(read_shear, euler6)
    print('read shear along the label (mm), by depth (rows) and labelled |s| (columns, mm); (n)')
    print('depth      ' + ' '.join('%9s' % f'{c:g}-{d:g}' for c, d in zip(SLIP_SHEARS[:-1], SLIP_SHEARS[1:])))
    for i, (a, b) in enumerate(zip(SLIP_DEPTHS[:-1], SLIP_DEPTHS[1:])):
        print(f'{a:.1f}-{b:.1f}    ' + ' '.join('%5.2f(%3d)' % (mean[i, j], count[i, j]) for j in range(mean.shape[1])))


def _row(label, v, fmt='{:7.3f}'):
    return f'{label:<40}' + ' '.join(fmt.format(x) for x in v)


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--data', default=None)
    ap.add_argument('--models', default=os.path.join(HERE, 'models'))
    ap.add_argument('--train-every', type=int, default=3, help='use every k-th training image (default 3: 2000)')
    ap.add_argument('--holdout-run', default=None, help='a train.py --holdout run: fit a power-law calibration')
    ap.add_argument('--sigma-psi', type=float, default=10.0, help='for the scalar filter model (mm and deg)')
    ap.add_argument('--dump', default=None, help='write the val rows for lieservo_filter_diagnosis to this file')
    ap.add_argument('--dump-sigma', choices=['network', 'card', 'power'], default='network',
                    help='the sigma written by --dump (power needs --holdout-run)')
    ap.add_argument('--geometry', action='store_true', help='only section 6: the two sessions as a whole')
    ap.add_argument('--slip', action='store_true', help='only section 7: where the skin slips')
    args = ap.parse_args(argv)
    if args.dump and args.dump_sigma == 'power' and not args.holdout_run:
        ap.error('--dump-sigma power needs --holdout-run')
    return args


def onnx_outputs(path, x):
    """The network of the ONNX file `path` (through cv2.dnn) on images x, in batches of 100."""
    import cv2
    net = cv2.dnn.readNetFromONNX(path)
    outs = []
    for i in range(0, len(x), 100):
        net.setInput(x[i:i + 100])
        outs.append(net.forward())
    return np.concatenate(outs).astype(np.float64)


def torch_outputs(model, x):
    from export_onnx import torch_forward
    return np.concatenate([torch_forward(model, x[i:i + 100]) for i in range(0, len(x), 100)]).astype(np.float64)


def labels_of(split, idx):
    import labels as L
    return L.to_train_units(L.xi_from_euler6(split.euler6))[idx]   # mm, deg


NB = len(DEPTH_EDGES) - 1
RANGES = [f'{DEPTH_EDGES[i]:g}-{DEPTH_EDGES[i + 1]:g}' for i in range(NB)]
BINS = [f'z {r} mm' for r in RANGES]


def print_by_bin(label, all_values, per_bin):
    print(_row(label, all_values))
    for i in range(NB):
        print(_row(f'  {BINS[i]}', per_bin[i]))


def print_mae_by_depth(label, err, z):
    counts, mae = mae_by_bin(err, z)
    print(_row(f'{label} all (n {len(z)})', np.abs(err).mean(0)))
    for i in range(NB):
        print(_row(f'  {BINS[i]} (n {counts[i]})', mae[i]))


def section_mae(args, tr, va):
    """Sections 0 and 1: the label distributions, and each network's MAE by depth on train and
    val. Returns the GDN's (err, sigma, z) on val, or None without a GDN."""
    print('0. Label distributions: fraction per depth bin; mean |shear| (mm), |twist|, |tilt| (deg)')
    print(_row('', RANGES + ['shear', 'twist', 'tilt'], '{:>7}'))
    for label, split in (('train', tr), ('val', va)):
        print(_row(f'{label} (n {len(split)})', label_summary(split.euler6)))
    print('\n' + _row('', COMP, '{:>7}'))
    splits = [('train (trained on)', tr, np.arange(0, len(tr), args.train_every)),
              ('val', va, np.arange(len(va)))]
    gdn_val = None
    print('\n1. MAE by depth (mm, deg)')
    for model in ('gdn', 'cnn'):
        if not os.path.isfile(os.path.join(args.models, f'{model}.onnx')):
            print(f'{model}.onnx: not found, skipped')
            continue
        for label, split, idx in splits:
            out = onnx_outputs(os.path.join(args.models, f'{model}.onnx'), split.images[idx])
            err = out[:, :6] - labels_of(split, idx)
            z = split.euler6[idx, 2]
            print_mae_by_depth(f'{model} {label}', err, z)
            if model == 'gdn' and split is va:
                gdn_val = (err, 1.0 / out[:, 6:], z)
    return gdn_val


def section_coverage(err, sig, z, scale):
    """Section 2: how often |error| <= sigma, by depth, for the network's and the card's sigma."""
    print('\n2. Coverage of the GDN sigma on val (0.683 for a calibrated Gaussian)')
    for label, s in (('network sigma', sig), ('card factors ' + ' '.join(f'{v:.2f}' for v in scale), sig * scale)):
        print_by_bin(f'{label}: all', np.mean(np.abs(err) <= s, axis=0), coverage_by_bin(err, s, z))
    bz = bin_index(z)
    print_by_bin('q68 |error|/network sigma: all', np.quantile(np.abs(err) / sig, GAUSS_1SIGMA, axis=0),
                 [np.quantile(np.abs(err[bz == i]) / sig[bz == i], GAUSS_1SIGMA, axis=0) for i in range(NB)])


def fit_holdout(args, tr):
    """With --holdout-run: the power-law calibration sigma' = a sigma^b fitted on the run's held-out
    training rows. Returns (a, b, the rows, the run's model, its outputs on them)."""
    import torch
    from export_onnx import load_ckpt
    torch.set_num_threads(2)
    held = np.loadtxt(os.path.join(args.holdout_run, 'holdout.txt'), dtype=np.int64, ndmin=1)
    model, _ = load_ckpt(os.path.join(args.holdout_run, 'gdn_last.pt'))
    out = torch_outputs(model, tr.images[held])
    a, bexp = fit_power_calibration(out[:, :6] - labels_of(tr, held), 1.0 / out[:, 6:])
    return a, bexp, held, model, out


def print_holdout(args, tr, va, err, sig, z, fit):
    """Sections 4 and 5: the power-law calibration's coverage on val, and the session gap by depth."""
    a, bexp, held, model, out = fit
    print(f'\n4. Power-law calibration sigma\' = a sigma^b, fitted on the {len(held)} rows held out of '
          f'{args.holdout_run}')
    print(_row('a', a, '{:7.3f}'))
    print(_row('b', bexp, '{:7.2f}'))
    s = a * sig ** bexp
    print_by_bin('coverage on val: all', np.mean(np.abs(err) <= s, axis=0), coverage_by_bin(err, s, z))
    print(f'\n5. Session gap by depth: MAE of {args.holdout_run} (last epoch) on its held-out training '
          f'rows (same session as its training images) and on val')
    out_v = torch_outputs(model, va.images)
    for label, split, idx, o in (('held out', tr, held, out), ('val', va, np.arange(len(va)), out_v)):
        print_mae_by_depth(label, o[:, :6] - labels_of(split, idx), split.euler6[idx, 2])


def slip_only(args, data) -> int:
    """Section 7 alone (--slip): the read shear against the labelled one, by depth."""
    from dataset import load_split
    import labels as L
    va = load_split(data, 'val', verbose=False)
    out = onnx_outputs(os.path.join(args.models, 'gdn.onnx'), va.images)
    mu = L.from_train_units(out[:, :6])   # mm, rad
    print_slip(L.se3_inv(L.se3_exp(mu))[:, :2, 3], va.euler6)
    return 0


def main(argv=None) -> int:
    from dataset import default_data_dir, load_split

    args = parse_args(argv)
    data = args.data or default_data_dir()
    if args.slip:
        return slip_only(args, data)
    tr = load_split(data, 'train', verbose=False)
    va = load_split(data, 'val', verbose=False)
    if args.geometry:
        print_session_geometry(tr, va)
        return 0
    with open(os.path.join(args.models, 'model_card.json')) as f:
        card = json.load(f)
    scale = np.asarray(card['models']['gdn'].get('sigma_calibration', {}).get('scale', [1.0] * 6))
    gdn_val = section_mae(args, tr, va)
    if gdn_val is None:
        if args.dump:
            raise SystemExit('--dump: no GDN model')
        return 0
    err, sig, z = gdn_val
    section_coverage(err, sig, z, scale)

    print(f'\n3. Scalar filter model on val, sigma_psi = {args.sigma_psi:g}: MAE ratio to unfiltered')
    b = bin_index(z)
    cal = [('network sigma', sig), ('card factors', sig * scale)]
    fit = fit_holdout(args, tr) if args.holdout_run else None
    if fit is not None:
        cal.append(('power law', fit[0] * sig ** fit[1]))
    for label, s in cal:
        print_by_bin(f'{label}: all', scalar_filter_ratio(err, s, args.sigma_psi),
                     [scalar_filter_ratio(err[b == i], s[b == i], args.sigma_psi) for i in range(NB)])
    if fit is not None:
        print_holdout(args, tr, va, err, sig, z, fit)

    if args.dump:
        s = dict(cal)[{'network': 'network sigma', 'card': 'card factors', 'power': 'power law'}[args.dump_sigma]]
        write_dump(args.dump, z, labels_of(va, np.arange(len(va))), err, s, args.dump_sigma)
        print(f'\nwrote {len(z)} rows ({args.dump_sigma} sigma) to {args.dump}')
    return 0


def write_dump(path: str, z, label, err, sigma, what: str) -> None:
    """The rows for lieservo_filter_diagnosis: z (mm), label xi, mean mu = label + err and sigma,
    each [N, 6] given in mm and deg and written in mm and rad, one row per image, %.17g."""
    to_rad = np.array([1.0, 1.0, 1.0, np.pi / 180, np.pi / 180, np.pi / 180])
    rows = np.hstack([np.asarray(z, np.float64)[:, None], label * to_rad, (label + err) * to_rad, sigma * to_rad])
    np.savetxt(path, rows, fmt='%.17g',
               header=f'z_mm xi(6) mu(6) sigma(6) in mm and rad; sigma: {what}; written by examples/gdn/diagnose.py')


if __name__ == '__main__':
    sys.exit(main())
