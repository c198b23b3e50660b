#!/usr/bin/python3
"""Unit tests for examples/gdn (plain asserts; exit status != 0 on failure).

    /usr/bin/python3 examples/gdn/test_gdn.py

Data-dependent checks use ../shared/data/tactip beside the repository (or $LIESERVO_DATA) and are skipped with a
message when it is absent. Needs only python3-torch, python3-onnx, python3-numpy,
python3-opencv.
"""
from __future__ import annotations

import csv
import math
import os
import sys
import tempfile
import traceback

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import torch  # noqa: E402

torch.set_num_threads(1)

import labels as L  # noqa: E402
from dataset import (DatasetError, default_data_dir, euler6_from_targets, load_image,  # noqa: E402
                     read_json, read_targets)
from model import KERAS_BN, TORCH_BN, beta_nll, build, gdn_nll, keras_init_, softbound, stable_softplus  # noqa: E402

TESTS = []
SKIPPED = []


def test(fn):
    TESTS.append(fn)
    return fn


def data_dir():
    d = os.environ.get('LIESERVO_DATA') or default_data_dir()
    return d if os.path.isfile(os.path.join(d, 'val', 'targets.csv')) else None


def skip(name, why):
    SKIPPED.append(name)
    print(f'SKIP {name}: {why}')


# ---------------------------------------------------------------- labels
@test
def labels_euler_convention():
    e = np.array([1.0, -2.0, 3.0, 10.0, -20.0, 5.0])
    T = L.euler_sxyz_to_matrix(e)
    a, b, g = np.radians(e[3:])
    Rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    Ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    Rz = np.array([[math.cos(g), -math.sin(g), 0], [math.sin(g), math.cos(g), 0], [0, 0, 1]])
    assert np.allclose(T[:3, :3], Rz @ Ry @ Rx, atol=1e-15)
    assert np.allclose(T[:3, 3], e[:3])
    Ti = L.se3_inv(T)
    assert np.allclose(Ti @ T, np.eye(4), atol=1e-14)


@test
def labels_log_exp_round_trip_synthetic():
    rng = np.random.RandomState(1)
    xi = rng.randn(200, 6)
    xi[:50, 3:] *= 1e-9          # tiny angles: series branch
    xi[50:100, 3:] *= 1e-3
    xi[100:, 3:] = xi[100:, 3:] / np.linalg.norm(xi[100:, 3:], axis=1, keepdims=True) \
        * rng.uniform(0.01, math.pi - 1e-3, (100, 1))
    T = L.se3_exp(xi)
    xi2 = L.se3_log(T)
    assert np.abs(xi2 - xi).max() < 1e-9, np.abs(xi2 - xi).max()
    # near pi: compare via exp (sign of axis is ambiguous at exactly pi)
    phi = np.array([[0.0, 0.0, math.pi - 1e-7], [1.0, 1.0, 0.0]])
    phi[1] *= (math.pi - 1e-6) / np.linalg.norm(phi[1])
    R = L.so3_exp(phi)
    assert np.abs(L.so3_exp(L.so3_log(R)) - R).max() < 1e-6
    # identity
    assert np.abs(L.se3_log(np.eye(4))).max() == 0.0


@test
def labels_reference_csv_consistent():
    """labels_reference.csv (for the C++ test) agrees with labels.py, and exp(xi) == X_fs^-1."""
    path = os.path.join(HERE, 'labels_reference.csv')
    assert os.path.isfile(path), path
    with open(path) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 20
    e6 = np.array([[float(r[k]) for k in ('x_mm', 'y_mm', 'z_mm', 'alpha_deg', 'beta_deg', 'gamma_deg')]
                   for r in rows])
    ref = np.array([[float(r[k]) for k in ('rho1_mm', 'rho2_mm', 'rho3_mm', 'phi1_rad', 'phi2_rad',
                                           'phi3_rad')] for r in rows])
    xi = L.xi_from_euler6(e6)
    assert np.abs(xi - ref).max() < 1e-12
    T = L.se3_inv(L.euler_sxyz_to_matrix(e6))
    assert np.abs(L.se3_exp(ref) - T).max() < 1e-12


@test
def labels_real_rows():
    d = data_dir()
    if d is None:
        return skip('labels_real_rows', 'no data set (set LIESERVO_DATA)')
    names, t = read_targets(os.path.join(d, 'val', 'targets.csv'))
    assert len(names) == 2000
    e6 = euler6_from_targets(t)
    # README: pose x, y, Rz and shear z, Rx, Ry are zero
    for c in ('pose_x', 'pose_y', 'pose_Rz', 'shear_z', 'shear_Rx', 'shear_Ry'):
        assert np.all(t[c] == 0), c
    T = L.euler_sxyz_to_matrix(e6)
    xi = L.xi_from_euler6(e6)
    assert np.abs(L.se3_exp(xi) @ T - np.eye(4)).max() < 1e-12       # exp(xi) = X_fs^-1
    assert np.abs(L.se3_log(L.se3_exp(xi)) - xi).max() < 1e-12
    # rotation angle of X_sf equals the total tilt/twist (angles within the sampled ranges)
    assert np.linalg.norm(xi[:, 3:], axis=1).max() < math.radians(40)
    # X_fs = X_par X_perp where X_perp = (rotation alpha, beta; then press in by z along the
    # surface normal of {f}) and X_par = (x, y translation, gamma rotation): the Euler 6-vector
    # of the composition is the README's (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz)
    Tperp = L.euler_sxyz_to_matrix(np.stack([0 * e6[:, 0], 0 * e6[:, 0], e6[:, 2], e6[:, 3], e6[:, 4],
                                             0 * e6[:, 0]], 1))
    Tpar = L.euler_sxyz_to_matrix(np.stack([e6[:, 0], e6[:, 1], 0 * e6[:, 0], 0 * e6[:, 0],
                                            0 * e6[:, 0], e6[:, 5]], 1))
    comp = Tpar @ Tperp
    assert np.allclose(comp[:, :3, :3], T[:, :3, :3], atol=1e-14)
    with open(os.path.join(HERE, 'labels_reference.csv')) as f:
        ref = list(csv.DictReader(f))
    assert [r['sensor_image'] for r in ref] == names[:20]
    refxi = np.array([[float(r[k]) for k in list(r)[7:]] for r in ref])
    assert np.abs(refxi - xi[:20]).max() < 1e-12


# ---------------------------------------------------------------- softplus / softbound
@test
def stable_softplus_matches_torch():
    z = torch.cat([torch.linspace(-200, 200, 4001, dtype=torch.float64),
                   torch.tensor([-1e6, -1e3, 1e3, 1e6], dtype=torch.float64)])
    a = stable_softplus(z)
    b = torch.nn.functional.softplus(z)      # (uses x for x > 20: differs by < exp(-20))
    exact = torch.from_numpy(np.logaddexp(0.0, z.numpy()))
    assert torch.isfinite(a).all()
    assert (a - exact).abs().max() < 1e-12
    assert (a - b).abs().max() < 1e-8
    z32 = z.float()
    a32 = stable_softplus(z32)
    assert torch.isfinite(a32).all() and ((a32.double() - b).abs() / b.clamp(min=1)).max() < 1e-6


@test
def softbound_matches_definition_and_bounds():
    x = torch.linspace(-50, 50, 1001, dtype=torch.float64)
    sp = torch.nn.functional.softplus
    ref = 1e-6 + sp(x - 1e-6) - sp(x - 1e6)
    exact = 1e-6 + np.logaddexp(0, x.numpy() - 1e-6) - np.logaddexp(0, x.numpy() - 1e6)
    assert np.abs(softbound(x).numpy() - exact).max() < 1e-12
    assert (softbound(x) - ref).abs().max() < 1e-8
    big = torch.tensor([-1e9, -1e3, 1e3, 2e6, 1e9], dtype=torch.float32)
    y = softbound(big)
    assert torch.isfinite(y).all()
    assert (y >= 1e-6 * (1 - 1e-6)).all() and (y <= 1e6 * (1 + 1e-6)).all(), y
    assert abs(float(y[0]) - 1e-6) < 1e-9 and abs(float(y[-1]) - 1e6) < 1.0
    assert abs(float(softbound(torch.tensor(50.0))) - 50.0) < 1e-4


# ---------------------------------------------------------------- data reader
@test
def reader_malformed_json_clear_error():
    with tempfile.TemporaryDirectory() as td:
        p = os.path.join(td, 'env_params.json')
        with open(p, 'w') as f:
            f.write('{"robot": "franka",\n "tcp_pose": [0, 0, 72, 0, 0, 225]]}\n')
        try:
            read_json(p)
        except DatasetError as e:
            msg = str(e)
            assert p in msg and 'line 2' in msg and 'column 35' in msg, msg
        else:
            raise AssertionError('no error for malformed JSON')
        q = os.path.join(td, 'meta.json')
        with open(q, 'w') as f:
            f.write('{"z_shear_rng": [-Infinity, -Infinity], "phi": [Infinity, 1]}')
        v = read_json(q)
        assert v['z_shear_rng'][0] == -math.inf and v['phi'][0] == math.inf
        try:
            read_json(os.path.join(td, 'nope.json'))
        except DatasetError as e:
            assert 'nope.json' in str(e)
        else:
            raise AssertionError('no error for missing JSON')
        try:
            load_image(os.path.join(td, 'image_999.png'))
        except DatasetError as e:
            assert 'image_999.png' in str(e)
        else:
            raise AssertionError('no error for missing image')
        try:
            read_targets(os.path.join(td, 'targets.csv'))
        except DatasetError as e:
            assert 'targets.csv' in str(e)
        else:
            raise AssertionError('no error for missing targets.csv')


@test
def reader_real_files():
    d = data_dir()
    if d is None:
        return skip('reader_real_files', 'no data set (set LIESERVO_DATA)')
    meta = read_json(os.path.join(d, 'val', 'meta.json'))
    assert meta['phi_max'] == 25 and math.isinf(meta['z_shear_rng'][0])
    try:
        read_json(os.path.join(d, 'val', 'env_params.json'))
        print('note: env_params.json parsed (no longer malformed?)')
    except DatasetError as e:
        assert 'env_params.json' in str(e) and 'line 1' in str(e)
    img = load_image(os.path.join(d, 'val', 'processed_images', 'image_1.png'))
    assert img.shape == (128, 128) and img.dtype == np.uint8 and 0 < img.mean() < 255


# ---------------------------------------------------------------- ONNX / cv2.dnn
def _export_and_compare(kind, channels=(4, 8, 16), bn=TORCH_BN, var=(0.5, 2.0)):
    import cv2
    from export_onnx import export_model
    torch.manual_seed(3)
    m = build(kind, channels, bn=bn).eval()
    with torch.no_grad():   # give BN non-trivial statistics
        for mod in m.modules():
            if isinstance(mod, torch.nn.BatchNorm2d):
                mod.running_mean.uniform_(-0.1, 0.1)
                mod.running_var.uniform_(*var)
    with tempfile.TemporaryDirectory() as td:
        p = os.path.join(td, f'{kind}.onnx')
        ops = export_model(m, p)
        for bad in ('Where', 'Clip', 'Min', 'Max', 'Reshape', 'Softplus', 'Identity'):
            assert bad not in ops, (bad, ops)
        net = cv2.dnn.readNetFromONNX(p)
        for n in (1, 3):
            x = np.random.RandomState(n).rand(n, 1, 128, 128).astype(np.float32)
            net.setInput(x)
            y_cv = net.forward()
            with torch.no_grad():
                y_pt = m(torch.from_numpy(x)).numpy()
            assert y_cv.shape == y_pt.shape == (n, 12 if kind == 'gdn' else 6), (y_cv.shape, y_pt.shape)
            assert np.abs(y_cv - y_pt).max() < 1e-4, np.abs(y_cv - y_pt).max()


@test
def onnx_tiny_gdn_cv2_matches_torch():
    _export_and_compare('gdn')


@test
def onnx_tiny_cnn_cv2_matches_torch():
    _export_and_compare('cnn')


@test
def keras_batchnorm_options_exported_and_reloaded():
    # The paper's Keras BatchNorm (eps 1e-3): the ONNX export folds BN into Conv with the
    # module's eps (running variances of a few eps, so a fold with PyTorch's 1e-5 would be off
    # by ~10 %: checked to fail), and a checkpoint records the options so export rebuilds the
    # same model.
    _export_and_compare('gdn', bn=KERAS_BN, var=(4e-3, 8e-3))
    from export_onnx import load_ckpt
    m = build('gdn', (4, 8, 16), bn=KERAS_BN)
    bns = [b for b in m.modules() if isinstance(b, torch.nn.BatchNorm2d)]
    assert len(bns) == 3 and all(b.eps == 1e-3 and b.momentum == 0.01 for b in bns)
    with tempfile.TemporaryDirectory() as td:
        p = os.path.join(td, 'gdn_best.pt')
        for ck_bn, want in ((KERAS_BN._asdict(), KERAS_BN), (None, TORCH_BN)):
            ck = {'state_dict': m.state_dict(), 'kind': 'gdn', 'channels': (4, 8, 16)}
            if ck_bn is not None:
                ck['bn'] = ck_bn
            torch.save(ck, p)
            r, _ = load_ckpt(p)
            assert all(b.eps == want.eps and b.momentum == want.momentum
                       for b in r.modules() if isinstance(b, torch.nn.BatchNorm2d))


@test
def keras_init_glorot_uniform_zero_bias():
    # Keras initialisation: every conv/linear kernel ~ U(-b, b) with b = sqrt(6/(fan_in+fan_out))
    # (fans include the 3x3 receptive field), every bias zero; BatchNorm untouched.
    torch.manual_seed(0)
    m = keras_init_(build('gdn', (4, 8, 16), size=32))
    layers = [l for l in m.modules() if isinstance(l, (torch.nn.Conv2d, torch.nn.Linear))]
    assert len(layers) == 3 + 12
    for l in layers:
        rf = l.weight[0, 0].numel()
        b = math.sqrt(6.0 / (l.weight.shape[1] * rf + l.weight.shape[0] * rf))
        w = l.weight.detach()
        assert float(l.bias.abs().max()) == 0.0
        assert float(w.abs().max()) <= b
        if w.numel() >= 200:   # uniform on [-b, b]: std b/sqrt(3), checked to 15 %
            assert abs(float(w.std()) / (b / math.sqrt(3.0)) - 1.0) < 0.15, (l, float(w.std()), b)
    for bn in (l for l in m.modules() if isinstance(l, torch.nn.BatchNorm2d)):
        assert float((bn.weight - 1).abs().max()) == 0.0 and float(bn.bias.abs().max()) == 0.0


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


def _shipped_model_dirs():
    """The exported GDNs: the reproduction model (train only) and the deployed one (train + val)."""
    return [os.path.join(HERE, 'models'), os.path.join(HERE, 'models', 'train_val')]


@test
def train_val_card_lists_the_held_out_rows():
    # The deployed GDN's card: its held_out.csv are exactly the rows train.py --holdout keeps out
    # of each session, the counts agree with data.trained_on, and its numbers are measured there.
    import json
    from train import HOLDOUT_SEEDS, holdout_indices
    from dataset import load_split
    models = os.path.join(HERE, 'models', 'train_val')
    if not os.path.isfile(os.path.join(models, 'model_card.json')):
        return skip('train_val_card_lists_the_held_out_rows', 'models/train_val not exported yet')
    d = data_dir()
    if d is None:
        return skip('train_val_card_lists_the_held_out_rows', 'no data set (set LIESERVO_DATA)')
    with open(os.path.join(models, 'model_card.json')) as f:
        card = json.load(f)
    data = card['data']
    with open(os.path.join(models, data['held_out']['file'])) as f:
        rows = list(csv.DictReader(f))
    gdn = card['models']['gdn']
    assert 'validation' not in gdn and gdn['held_out']['n'] == len(rows)
    for split in ('train', 'val'):
        names = load_split(d, split, verbose=False).names
        k = data['held_out'][split]
        want = [names[i] for i in holdout_indices(len(names), k, HOLDOUT_SEEDS[split])]
        assert [r['sensor_image'] for r in rows if r['split'] == split] == want, split
        assert data['trained_on'][split] + k == data[split] == len(names)
        assert gdn['held_out']['by_split'][split]['n'] == k
    with open(os.path.join(HERE, 'models', 'model_card.json')) as f:
        assert json.load(f)['data']['trained_on'] == {'train': 6000}


@test
def onnx_trained_gdn_reference_outputs():
    for models in _shipped_model_dirs():
        _check_reference_outputs(models)


def _check_reference_outputs(models):
    import cv2
    onnx_path = os.path.join(models, 'gdn.onnx')
    ref_path = os.path.join(models, 'gdn_reference_outputs.csv')
    if not (os.path.isfile(onnx_path) and os.path.isfile(ref_path)):
        return skip('onnx_trained_gdn_reference_outputs', f'{onnx_path} not exported yet')
    d = data_dir()
    if d is None:
        return skip('onnx_trained_gdn_reference_outputs', 'no data set (set LIESERVO_DATA)')
    with open(ref_path) as f:
        rows = list(csv.DictReader(f))
    x = np.stack([load_image(os.path.join(d, 'val', 'processed_images', r['sensor_image']))
                  for r in rows]).astype(np.float32)[:, None] / np.float32(255)
    ref = np.array([[float(v) for k, v in r.items() if k != 'sensor_image'] for r in rows])
    net = cv2.dnn.readNetFromONNX(onnx_path)
    net.setInput(x)
    y = net.forward()
    rel = np.abs(y - ref) / np.maximum(1.0, np.abs(ref))
    assert rel.max() < 1e-4, rel.max()
    assert np.all(y[:, 6:] > 0)


def main():
    passed = failed = 0
    for fn in TESTS:
        try:
            n_skip = len(SKIPPED)
            fn()
            if len(SKIPPED) == n_skip:
                print(f'ok   {fn.__name__}')
                passed += 1
        except Exception:
            failed += 1
            print(f'FAIL {fn.__name__}')
            traceback.print_exc()
    print(f'{passed} passed, {failed} failed' + (f', {len(SKIPPED)} skipped' if SKIPPED else ''))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
