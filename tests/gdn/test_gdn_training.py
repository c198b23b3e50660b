#!/usr/bin/python3
"""Tests of examples/gdn's training side: the sigma calibration, augmentation, the held-out rows,
the losses and optimiser, the diagnosis and the ensemble, and what the export measures on.

    /usr/bin/python3 tests/gdn/test_gdn_training.py

Data-dependent checks use ../shared/data/tactip beside the repository (or $LIESERVO_DATA) and are
skipped with a message when it is absent. Needs only python3-torch, python3-numpy, python3-opencv.
"""
from __future__ import annotations

import math
import sys

import numpy as np

from gdn_testing import run, test

import torch  # noqa: E402

torch.set_num_threads(1)

from model import beta_nll, gdn_nll  # noqa: E402


@test
def sigma_calibration_factors():
    # Errors drawn with std s_j around a network that claims sigma = 1: the factor recovers s_j
    # (quantile of 100000 samples: ~0.5 % standard error), and the scaled sigma covers 68.27 %.
    from calibrate_sigma import GAUSS_1SIGMA, coverage_of, sigma_scale
    rng = np.random.RandomState(3)
    s = np.array([0.5, 1.0, 2.0, 1.0, 3.0, 0.25])
    sig = rng.uniform(0.2, 2.0, size=(100000, 6))          # per-sample sigma, heteroscedastic
    err = rng.standard_normal((100000, 6)) * sig * s
    k = sigma_scale(err, sig)
    assert np.all(np.abs(k / s - 1.0) < 0.02), k
    assert np.all(np.abs(coverage_of(err, sig * k) - GAUSS_1SIGMA) < 1e-3)
    assert abs(coverage_of(err, sig)[1] - GAUSS_1SIGMA) < 0.01   # s = 1: already calibrated
    for bad in (np.zeros((4, 6)), np.full((4, 6), np.nan), -np.ones((4, 6))):
        try:
            sigma_scale(np.ones((4, 6)), bad)
            assert False, 'accepted sigma %r' % bad[0, 0]
        except ValueError:
            pass
    try:
        sigma_scale(np.ones((4, 6)), np.ones((5, 6)))
        assert False, 'accepted mismatched shapes'
    except ValueError:
        pass


@test
def paired_difference_mean_and_standard_error():
    # Two models on the same rows: the run's |error| is the baseline's minus 0.1 plus noise of
    # std 0.2 (|base| >= 1: no sign flips), so the mean difference is -0.1 and its standard
    # error 0.2 / sqrt(N).
    from calibrate_sigma import paired_difference
    rng = np.random.RandomState(5)
    base = rng.uniform(1.0, 2.0, size=(40000, 6)) * np.sign(rng.standard_normal((40000, 6)))
    run = np.sign(base) * (np.abs(base) - 0.1 + 0.2 * rng.standard_normal((40000, 6)))
    d, se = paired_difference(run, base)
    assert np.all(np.abs(d + 0.1) < 5 * 0.2 / 200), d
    assert np.all(np.abs(se / (0.2 / 200) - 1) < 0.02), se
    for a, b in ((np.ones((3, 6)), np.ones((4, 6))), (np.ones((1, 6)), np.ones((1, 6)))):
        try:
            paired_difference(a, b)
            assert False, 'accepted %r and %r' % (a.shape, b.shape)
        except ValueError:
            pass


@test
def augment_presets():
    # Values stay in [0, 1]; black stays black and white stays white under gamma (so the mask's
    # outside stays 0); the same generator seed gives the same batch; 'photometric' moves no
    # marker (the centroid of the image is unchanged to well under a pixel), 'session' does.
    from augment import PRESETS, augment
    assert PRESETS['none'] is None
    x = torch.zeros(8, 1, 32, 32)
    x[:, :, 8:12, 20:24] = 1.0
    x[:, :, 20:23, 5:9] = 0.5
    for name in ('photometric', 'session'):
        a = augment(x, PRESETS[name], torch.Generator().manual_seed(5))
        b = augment(x, PRESETS[name], torch.Generator().manual_seed(5))
        assert torch.equal(a, b), name
        assert a.shape == x.shape and float(a.min()) >= 0.0 and float(a.max()) <= 1.0, name
        assert not torch.equal(a, x), name
    yy, xx = torch.meshgrid(torch.arange(32.0), torch.arange(32.0), indexing='ij')

    def centroid(img):
        w = img[:, 0]
        return torch.stack([(w * xx).sum((1, 2)), (w * yy).sum((1, 2))], 1) / w.sum((1, 2))[:, None]
    no_blur = PRESETS['photometric']._replace(p_blur=0.0)
    p = augment(x, no_blur, torch.Generator().manual_seed(1))
    assert torch.equal(p[x == 0], x[x == 0]) and torch.equal(p[x == 1], x[x == 1])
    blob = torch.zeros(8, 1, 32, 32)
    blob[:, :, 8:12, 20:24] = 1.0          # one marker, away from the edges
    moved = (centroid(augment(blob, PRESETS['photometric'], torch.Generator().manual_seed(2))) - centroid(blob)).norm(dim=1)
    assert float(moved.max()) < 1e-3, moved
    moved = (centroid(augment(blob, PRESETS['session'], torch.Generator().manual_seed(2))) - centroid(blob)).norm(dim=1)
    assert float(moved.max()) > 0.3, moved


@test
def holdout_rows_per_session():
    # Fixed per session, independent of the training seed, sorted, distinct; train keeps the
    # file name calibrate_sigma.py and diagnose.py have always read.
    from train import HOLDOUT_SEEDS, holdout_file, holdout_indices
    a = holdout_indices(2000, 300, HOLDOUT_SEEDS['val'])
    assert np.array_equal(a, holdout_indices(2000, 300, HOLDOUT_SEEDS['val']))
    assert len(np.unique(a)) == 300 and np.all(np.diff(a) > 0) and a.max() < 2000
    assert not np.array_equal(a, holdout_indices(2000, 300, HOLDOUT_SEEDS['train']))
    assert holdout_file('train') == 'holdout.txt' and holdout_file('val') == 'holdout_val.txt'
    for bad in (0, 2000):
        try:
            holdout_indices(2000, bad)
            assert False, bad
        except SystemExit:
            pass


@test
def beta_nll_weights_the_paper_nll():
    """beta = 0 is the paper's NLL; beta = 1 pulls every mean by (mu - y), as a squared error."""
    g = torch.Generator().manual_seed(3)
    y = torch.randn(5, 6, generator=g)
    mu = torch.randn(5, 6, generator=g)
    s = 0.5 + torch.rand(5, 6, generator=g) * 4.0
    out = torch.cat([mu, s], dim=1).requires_grad_(True)
    assert torch.allclose(beta_nll(out, y, 0.0), gdn_nll(out, y))
    beta_nll(out, y, 1.0).backward()
    assert torch.allclose(out.grad[:, :6], (mu - y) / 5, atol=1e-6), out.grad[:, :6]
    out.grad = None
    beta_nll(out, y, 0.5).backward()
    assert torch.allclose(out.grad[:, :6], s * (mu - y) / 5, atol=1e-6)


@test
def weight_decay_optimizer():
    # 0: the paper's Adam without decay; > 0: AdamW with that decoupled decay; < 0 or NaN refused.
    from train import make_optimizer
    w = [torch.nn.Parameter(torch.ones(3))]
    adam = make_optimizer(w, 1e-8, 0.0)
    assert type(adam) is torch.optim.Adam and adam.param_groups[0]['weight_decay'] == 0
    adamw = make_optimizer(w, 1e-8, 0.01)
    assert type(adamw) is torch.optim.AdamW and adamw.param_groups[0]['weight_decay'] == 0.01
    for bad in (-0.1, float('nan')):
        try:
            make_optimizer(w, 1e-8, bad)
            assert False, bad
        except SystemExit:
            pass


@test
def diagnose_power_calibration_recovers_exponent():
    # Errors with std a*sigma^b around a network that claims sigma: the quantile regression
    # recovers (a, b); b = 1 is the constant factor of sigma_calibration_factors. The fitted
    # sigma covers 68.27 % in every sigma range, where the best constant factor does not.
    from diagnose import coverage_by_bin, fit_power_calibration
    from calibrate_sigma import GAUSS_1SIGMA, sigma_scale
    rng = np.random.RandomState(5)
    n = 100000
    sig = np.exp(rng.uniform(np.log(0.05), np.log(3.0), size=(n, 2)))
    a_true, b_true = np.array([1.7, 0.9]), np.array([0.7, 1.3])
    err = rng.standard_normal((n, 2)) * a_true * sig ** b_true
    a, b = fit_power_calibration(err, sig)
    assert np.all(np.abs(b - b_true) <= 0.02), b
    assert np.all(np.abs(a / a_true - 1.0) < 0.03), a
    z = np.clip(sig[:, 0], 0.05, 3.0)              # bin by the claimed sigma (edges in its range)
    edges = (0.05, 0.2, 0.8, 3.0)
    cov_pow = coverage_by_bin(err, a * sig ** b, z, edges)[:, 0]
    cov_const = coverage_by_bin(err, sig * sigma_scale(err, sig), z, edges)[:, 0]
    assert np.all(np.abs(cov_pow - GAUSS_1SIGMA) < 0.015), cov_pow
    # b = 0.7 < 1: the network is over-confident where it claims a small sigma, under- where large
    assert cov_const[0] < 0.55 and cov_const[-1] > 0.8, cov_const
    try:
        fit_power_calibration(err, -sig)
        assert False, 'accepted sigma < 0'
    except ValueError:
        pass


@test
def diagnose_bins_and_scalar_filter_model():
    from diagnose import bin_index, mae_by_bin, scalar_filter_ratio
    z = np.array([0.5, 1.49, 1.5, 2.9, 3.0, 6.0])
    assert bin_index(z).tolist() == [0, 0, 1, 1, 2, 2]
    for bad in (np.array([0.4]), np.array([6.1]), np.array([np.nan])):
        try:
            bin_index(bad)
            assert False, 'accepted depth %r' % bad[0]
        except ValueError:
            pass
    counts, mae = mae_by_bin(np.array([[1.0], [-3.0], [2.0], [0.0], [5.0], [-1.0]]), z)
    assert counts.tolist() == [2, 2, 2] and mae[:, 0].tolist() == [2.0, 1.0, 3.0]
    # With sigma right, the fused MAE is the optimal linear blend: below the unfiltered one.
    # With sigma 3x too large (prior over-weighted), the prior's noise makes it worse.
    rng = np.random.RandomState(7)
    sig = np.full((50000, 1), 2.0)
    err = rng.standard_normal(sig.shape) * sig
    right = scalar_filter_ratio(err, sig, 3.0)[0]
    expected = math.sqrt(3.0 ** 2 / (2.0 ** 2 + 3.0 ** 2))  # sd ratio of the Gaussian blend
    assert abs(right - expected) < 0.01, (right, expected)
    assert scalar_filter_ratio(err / 3.0, sig, 3.0)[0] > 1.2


@test
def diagnose_slip_table_levels_off_at_the_slip_radius():
    # A synthetic sensor whose read shear is the labelled one clipped at 1.2 z: in each depth
    # bin the table's mean equals the clipped shear's mean (1e-12), so the knee sits at 1.2 z.
    from diagnose import slip_table, SLIP_DEPTHS
    rng = np.random.RandomState(5)
    n = 20000
    z = rng.uniform(0.5, 6.0, n)
    r = 5 * np.sqrt(rng.uniform(0, 1, n))
    th = rng.uniform(-np.pi, np.pi, n)
    s = np.stack([r * np.cos(th), r * np.sin(th)], axis=1)
    read = s * (np.minimum(r, 1.2 * z) / r)[:, None]
    e6 = np.zeros((n, 6))
    e6[:, :2], e6[:, 2] = s, z
    mean, count = slip_table(read, e6)
    assert count.sum() == n
    m = (z >= SLIP_DEPTHS[1]) & (z < SLIP_DEPTHS[2]) & (r >= 4) & (r < 5.01)
    assert abs(mean[1, 4] - np.minimum(r[m], 1.2 * z[m]).mean()) < 1e-12
    assert mean[1, 4] < 3.1 and mean[4, 4] > 4.3   # clipped at 1.5-2.5 mm, free at 4.5-6 mm


@test
def diagnose_session_geometry_recovers_known_warps():
    # Criterion (set before the run): a blurred random-dot image warped by known sub-pixel
    # shifts, small rotations and scales is recovered to 0.1 px, 0.05 deg and 0.002 in scale,
    # far finer than the session augmentation's ranges (1.5 px, 1.5 deg, 3 %).
    import cv2
    from diagnose import session_geometry
    rng = np.random.RandomState(11)
    img = np.zeros((128, 128))
    for _ in range(150):
        x, y = rng.uniform(10, 118, 2)
        cv2.circle(img, (int(x * 16), int(y * 16)), 36, 255, -1, cv2.LINE_AA, 4)
    img = cv2.GaussianBlur(img, (0, 0), 1.0)
    for tx, ty, ang, sc in ((0.4, 0.25, 0.0, 1.0), (-0.2, 0.0, 0.8, 1.0), (0.0, -0.35, 0.0, 0.985),
                            (0.15, 0.3, -0.5, 1.008), (0.0, 0.0, 0.0, 1.0)):
        M = cv2.getRotationMatrix2D((63.5, 63.5), ang, sc)
        M[:, 2] += (tx, ty)
        warped = cv2.warpAffine(img, M, (128, 128), flags=cv2.INTER_CUBIC)
        dx, dy, rot, scale, _ = session_geometry(img, warped)
        got = (dx, dy, rot, scale)
        assert abs(dx - tx) <= 0.1 and abs(dy - ty) <= 0.1, (tx, ty, ang, sc, got)
        assert abs(rot - ang) <= 0.05 and abs(scale - sc) <= 0.002, (tx, ty, ang, sc, got)
    try:
        session_geometry(img, img[:64])
        assert False, 'accepted images of different sizes'
    except ValueError:
        pass


@test
def diagnose_label_summary():
    from diagnose import label_summary
    e = np.array([[3.0, 4.0, 1.0, 3.0, 4.0, -2.0],     # shear 5 mm, tilt 5 deg, twist 2 deg
                  [0.0, 0.0, 2.0, 0.0, 0.0, 4.0],
                  [0.0, 1.0, 5.0, 0.0, 1.0, 0.0],
                  [0.0, 0.0, 6.0, 0.0, 0.0, 0.0]])
    s = label_summary(e)
    assert np.allclose(s, [0.25, 0.25, 0.5, 1.5, 1.5, 1.5]), s
    for bad in (np.zeros((0, 6)), np.zeros((3, 5)), e[:, None]):
        try:
            label_summary(bad)
            assert False, 'accepted shape %r' % (bad.shape,)
        except ValueError:
            pass


@test
def ensemble_mixture_and_line_fit():
    # Mixture moments against a Monte Carlo draw of the mixture; precision weighting against
    # hand values; the line fit recovers a known slope and offset; bad shapes are refused.
    from ensemble import line_fit, mixture_moments, precision_weighted_mean
    mu = np.array([[[0.0, 1.0]], [[2.0, 1.0]]])          # K = 2, N = 1, d = 2
    sigma = np.array([[[1.0, 0.5]], [[1.0, 2.0]]])
    m, s = mixture_moments(mu, sigma)
    assert np.allclose(m, [[1.0, 1.0]]) and np.allclose(s, [[np.sqrt(2.0), np.sqrt((0.25 + 4) / 2)]])
    rng = np.random.RandomState(5)
    pick = rng.randint(0, 2, 200000)
    draw = mu[pick, 0] + sigma[pick, 0] * rng.randn(200000, 2)
    assert np.allclose(draw.std(0), s[0], rtol=0.01), (draw.std(0), s[0])
    assert np.allclose(precision_weighted_mean(mu, sigma), [[1.0, 1.0]])
    assert np.allclose(precision_weighted_mean(np.array([[[0.0]], [[3.0]]]), np.array([[[1.0]], [[2.0]]])), [[0.6]])
    x = rng.randn(1000, 3)
    slope, offset = line_fit(x, x * np.array([0.8, 1.0, -2.0]) + np.array([0.1, 0.0, 3.0]))
    assert np.allclose(slope, [0.8, 1.0, -2.0]) and np.allclose(offset, [0.1, 0.0, 3.0])
    for bad in ((mu, sigma[:, :, :1]), (mu, -sigma), (mu[0], sigma[0])):
        try:
            mixture_moments(*bad)
            assert False, 'accepted bad input'
        except ValueError:
            pass


@test
def export_measures_only_unseen_rows():
    # A model trained on train only is measured on all of val; one trained on val too only on
    # the rows it held out of each session, and without held-out rows it cannot be measured.
    from export_onnx import evaluation_rows
    n = {'train': 60, 'val': 20}
    key, rows, seen = evaluation_rows(['train'], {}, n)
    assert key == 'validation' and list(rows) == ['val'] and np.array_equal(rows['val'], np.arange(20))
    assert seen == {'train': 60}
    key, rows, seen = evaluation_rows(['train'], {'train': np.array([1, 5])}, n)   # a --holdout run
    assert key == 'validation' and seen == {'train': 58}
    held = {'train': np.array([0, 7, 9]), 'val': np.array([2, 3])}
    key, rows, seen = evaluation_rows(['train', 'val'], held, n)
    assert key == 'held_out' and seen == {'train': 57, 'val': 18}
    assert np.array_equal(rows['train'], [0, 7, 9]) and np.array_equal(rows['val'], [2, 3])
    for sessions, h in ((['train', 'val'], {'train': np.array([1])}), (['test'], {}), ([], {})):
        try:
            evaluation_rows(sessions, h, n)
            assert False, sessions
        except ValueError:
            pass


if __name__ == '__main__':
    sys.exit(run())
