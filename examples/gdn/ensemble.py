#!/usr/bin/python3
"""Several GDNs on one split: how much their errors have in common, and what averaging them
(a deep ensemble) would gain. The numbers behind examples/gdn/README.md, "A recipe for an
unseen session". It only measures; nothing is tuned on the split.

    /usr/bin/python3 examples/gdn/ensemble.py models/gdn.onnx runs/gdn_wd runs/gdn_photometric \
        [--split val] [--rows FILE] [--weights last] [--frame-time]

A model is an exported .onnx file (run with cv2.dnn) or a train.py run directory (its
gdn_<weights>.pt, run with PyTorch). --rows restricts the split to the rows listed in a file
(one index per line, e.g. a run's holdout.txt: the rows a model never saw). Printed per
component (mm, deg):
  * each model's MAE on the split;
  * (two or more models) the correlation of the models' per-image errors (ρ1, ρ2): near 1 means they make the same
    mistakes, which no average of them removes;
  * the ensemble: the mean of the μ's, and the mixture's σ (the σ of the equally weighted
    mixture of the models' Gaussians: mean of σ² plus the spread of the μ's, the aleatoric and
    epistemic parts); its MAE and the coverage of |error| <= σ (0.683 for a Gaussian);
  * the precision-weighted mean of the μ's (each model weighted by 1/σ²);
  * the slope and offset of a least-squares line of the ensemble's μ against the label: a slope
    below 1 is the shrinkage toward zero of an estimate the image does not pin down;
  * with --frame-time, each .onnx model's time for one image through cv2.dnn (the OpenCV
    backend the C++ adapter uses; median of 200 single-image forward passes, --threads
    threads): what an ensemble of them costs per frame.
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from calibrate_sigma import COMP, coverage_of  # noqa: E402


def mixture_moments(mu: np.ndarray, sigma: np.ndarray):
    """Mean and standard deviation of the equal-weight mixture of K Gaussians per row and
    component. mu, sigma: [K, N, d], sigma > 0. Returns ([N, d], [N, d])."""
    mu, sigma = np.asarray(mu, np.float64), np.asarray(sigma, np.float64)
    if mu.shape != sigma.shape or mu.ndim != 3 or mu.shape[0] < 1:
        raise ValueError(f'mu {mu.shape} and sigma {sigma.shape} must be the same [K, N, d], K >= 1')
    if not (np.all(np.isfinite(sigma)) and np.all(sigma > 0)):
        raise ValueError('sigma must be finite and > 0')
    m = mu.mean(0)
    var = (sigma ** 2).mean(0) + ((mu - m) ** 2).mean(0)
    return m, np.sqrt(var)


def precision_weighted_mean(mu: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """The μ's averaged with weights 1/σ² per row and component ([K, N, d] → [N, d])."""
    w = 1.0 / np.asarray(sigma, np.float64) ** 2
    return (np.asarray(mu, np.float64) * w).sum(0) / w.sum(0)


def line_fit(label: np.ndarray, estimate: np.ndarray):
    """Least-squares estimate ≈ slope · label + offset, per column ([N, d] → two [d] arrays)."""
    label, estimate = np.asarray(label, np.float64), np.asarray(estimate, np.float64)
    if label.shape != estimate.shape or label.ndim != 2 or len(label) < 2:
        raise ValueError(f'label {label.shape} and estimate {estimate.shape} must be the same [N, d], N >= 2')
    lc, ec = label - label.mean(0), estimate - estimate.mean(0)
    slope = (lc * ec).sum(0) / (lc * lc).sum(0)
    return slope, estimate.mean(0) - slope * label.mean(0)


def outputs(model: str, images: np.ndarray, weights: str) -> np.ndarray:
    """[N, 12] GDN outputs (μ, σ⁻¹ in mm and deg) of an .onnx file or a train.py run directory."""
    if model.endswith('.onnx'):
        import cv2
        if not os.path.isfile(model):
            raise SystemExit(f'{model}: not found')
        net = cv2.dnn.readNetFromONNX(model)
        out = []
        for i in range(0, len(images), 100):
            net.setInput(np.ascontiguousarray(images[i:i + 100], dtype=np.float32))
            out.append(np.asarray(net.forward()).copy())
        return np.concatenate(out)
    from export_onnx import load_ckpt, torch_forward
    path = os.path.join(model, f'gdn_{weights}.pt')
    if not os.path.isfile(path):
        raise SystemExit(f'{path}: not found (an .onnx file or a train.py run directory)')
    net, ck = load_ckpt(path)
    if ck['kind'] != 'gdn':
        raise SystemExit(f'{path}: a {ck["kind"]} checkpoint has no sigma')
    return np.concatenate([torch_forward(net, images[i:i + 100]) for i in range(0, len(images), 100)])


def main(argv=None) -> int:
    import torch
    from dataset import default_data_dir, load_split
    import labels as L

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('models', nargs='+', help='.onnx files or train.py run directories (GDNs)')
    ap.add_argument('--split', default='val')
    ap.add_argument('--rows', default=None, help='only these rows of the split (one index per line)')
    ap.add_argument('--weights', choices=['best', 'last'], default='last')
    ap.add_argument('--data', default=None)
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--frame-time', action='store_true', help='time one image through each .onnx model')
    args = ap.parse_args(argv)
    torch.set_num_threads(args.threads)

    sp = load_split(args.data or default_data_dir(), args.split, verbose=False)
    y = L.to_train_units(L.xi_from_euler6(sp.euler6))      # mm, deg
    images = sp.images
    if args.rows:
        rows = np.loadtxt(args.rows, dtype=np.int64, ndmin=1)
        if len(rows) == 0 or rows.min() < 0 or rows.max() >= len(y):
            raise SystemExit(f'{args.rows}: rows must be indices 0..{len(y) - 1} of {args.split}')
        y, images = y[rows], images[rows]
    outs = [outputs(m, images, args.weights) for m in args.models]
    mu = np.stack([o[:, :6] for o in outs]).astype(np.float64)
    sigma = 1.0 / np.stack([o[:, 6:] for o in outs]).astype(np.float64)

    def row(name, values, fmt='7.3f'):
        print(f'{name:<28}' + ' '.join(f'{v:{fmt}}' for v in values))

    print(f'{len(y)} images of {args.split}' + (f' ({args.rows})' if args.rows else '') + f'; {len(args.models)} GDN(s)')
    row('component', COMP, '>9')
    for m, k in zip(args.models, range(len(mu))):
        row(f'MAE {os.path.basename(os.path.normpath(m))}', np.abs(mu[k] - y).mean(0), '9.3f')
    err = mu - y
    for j in (0, 1) if len(mu) > 1 else ():
        c = np.corrcoef(err[:, :, j])
        off = c[~np.eye(len(c), dtype=bool)]
        print(f'error correlation {COMP[j]}: min {off.min():.3f}, max {off.max():.3f}')
    m, s = mixture_moments(mu, sigma)
    row('MAE ensemble mean', np.abs(m - y).mean(0), '9.3f')
    row('MAE precision-weighted', np.abs(precision_weighted_mean(mu, sigma) - y).mean(0), '9.3f')
    row('coverage, mixture sigma', coverage_of(m - y, s), '9.3f')
    slope, offset = line_fit(y, m)
    row('slope of mean on label', slope, '9.3f')
    row('offset', offset, '9.3f')
    if args.frame_time:
        import time
        import cv2
        cv2.setNumThreads(args.threads)
        for model in (m for m in args.models if m.endswith('.onnx')):
            net = cv2.dnn.readNetFromONNX(model)
            one = np.ascontiguousarray(images[:1], dtype=np.float32)
            times = []
            for _ in range(220):
                t0 = time.perf_counter()
                net.setInput(one)
                net.forward()
                times.append(time.perf_counter() - t0)
            print(f'one image through {model} (cv2.dnn, {args.threads} threads): '
                  f'{1e3 * np.median(times[20:]):.2f} ms (median of 200)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
