#!/usr/bin/python3
"""benchmarks/numpy_baseline.py — a straightforward NumPy implementation of the SE(3) data
fusion (Algorithm 3, alg:se3_data_fusion) and one discriminative-Bayes-filter step (Algorithm 2, alg:se3_bayes_filter),
as a reader of the paper would write it: 4x4 / 6x6 NumPy arrays, explicit inverses, the
information-form normal equations.

  numpy_baseline.py --check CASES.csv   compare with the C++ results dumped by
                                        `lieservo_speed_error_report --dump CASES.csv`;
                                        exit 1 if any relative difference exceeds 1e-9
  numpy_baseline.py --bench CASES.csv   also time fusion (5 iterations) and a filter step
                                        (median over repetitions, one CSV line per case kind)

Conventions as the C++ library: xi = [rho; phi] (translation first), left perturbation,
Ad(X) = [[C, r^C], [0, C]], ad(xi) = [[phi^, rho^], [0, phi^]].
"""
import argparse
import math
import os
import sys
import time

# Single-threaded BLAS: 6x6 problems gain nothing from threads, and on a loaded machine
# OpenBLAS's thread pool makes every tiny call pay for a wake-up.
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import numpy as np  # noqa: E402

TOL = 1e-9
BERNOULLI_OVER_FACTORIAL = [1.0, -0.5, 1.0 / 12.0, 0.0, -1.0 / 720.0]


def hat3(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def so3_exp(phi):
    th = np.linalg.norm(phi)
    P = hat3(phi)
    if th < 1e-8:
        return np.eye(3) + P + 0.5 * P @ P
    return np.eye(3) + math.sin(th) / th * P + (1 - math.cos(th)) / th**2 * P @ P


def so3_jac(phi):
    th = np.linalg.norm(phi)
    P = hat3(phi)
    if th < 1e-5:
        return np.eye(3) + 0.5 * P + P @ P / 6.0
    return np.eye(3) + (1 - math.cos(th)) / th**2 * P + (th - math.sin(th)) / th**3 * P @ P


def so3_jac_inv(phi):
    th = np.linalg.norm(phi)
    P = hat3(phi)
    if th < 1e-5:
        return np.eye(3) - 0.5 * P + P @ P / 12.0
    return np.eye(3) - 0.5 * P + (1 - th * math.sin(th) / (2 * (1 - math.cos(th)))) / th**2 * P @ P


def so3_log(C):
    c = np.clip((np.trace(C) - 1) / 2, -1.0, 1.0)
    th = math.acos(c)
    w = np.array([C[2, 1] - C[1, 2], C[0, 2] - C[2, 0], C[1, 0] - C[0, 1]])
    if th < 1e-8:
        return 0.5 * w
    return th / (2 * math.sin(th)) * w


def se3_exp(xi):
    X = np.eye(4)
    X[:3, :3] = so3_exp(xi[3:])
    X[:3, 3] = so3_jac(xi[3:]) @ xi[:3]
    return X


def se3_log(X):
    phi = so3_log(X[:3, :3])
    return np.concatenate([so3_jac_inv(phi) @ X[:3, 3], phi])


def se3_inv(X):
    Y = np.eye(4)
    Y[:3, :3] = X[:3, :3].T
    Y[:3, 3] = -X[:3, :3].T @ X[:3, 3]
    return Y


def se3_ad(xi):
    A = np.zeros((6, 6))
    A[:3, :3] = A[3:, 3:] = hat3(xi[3:])
    A[:3, 3:] = hat3(xi[:3])
    return A


def se3_Ad(X):
    A = np.zeros((6, 6))
    A[:3, :3] = A[3:, 3:] = X[:3, :3]
    A[:3, 3:] = hat3(X[:3, 3]) @ X[:3, :3]
    return A


def Q_block(rho, phi):
    th = np.linalg.norm(phi)
    P, R = hat3(phi), hat3(rho)
    if th < 1e-3:  # series of Barfoot's coefficients
        x = th * th
        c1, c2, c3 = 1 / 6 - x / 120, 1 / 24 - x / 720, 1 / 120 - x / 2520
    else:
        c1 = (th - math.sin(th)) / th**3
        c2 = (th**2 + 2 * math.cos(th) - 2) / (2 * th**4)
        c3 = (2 * th - 3 * math.sin(th) + th * math.cos(th)) / (2 * th**5)
    PR, RP, PRP = P @ R, R @ P, P @ R @ P
    return 0.5 * R + c1 * (PR + RP + PRP) + c2 * (P @ PR + RP @ P - 3 * PRP) + c3 * (PRP @ P + P @ PRP)


def jac_inv(xi, order):
    """Inverse left Jacobian: closed form (order -1) or Bernoulli series of the given order."""
    if order < 0:
        Ji = so3_jac_inv(xi[3:])
        J = np.zeros((6, 6))
        J[:3, :3] = J[3:, 3:] = Ji
        J[:3, 3:] = -Ji @ Q_block(xi[:3], xi[3:]) @ Ji
        return J
    ad = se3_ad(xi)
    J, P = np.eye(6), np.eye(6)
    for n in range(1, order + 1):
        P = P @ ad
        J = J + BERNOULLI_OVER_FACTORIAL[n] * P
    return J


def fuse(means, covs, order, iterations):
    """Algorithm 3 (alg:se3_data_fusion), information form, operating point starting at means[0]."""
    X = means[0].copy()
    infos = [np.linalg.inv(S) for S in covs]
    for _ in range(iterations):
        H = np.zeros((6, 6))
        g = np.zeros(6)
        for Xi, W in zip(means, infos):
            xi = se3_log(X @ se3_inv(Xi))
            Ji = jac_inv(xi, order)
            H += Ji.T @ W @ Ji
            g += Ji.T @ W @ xi
        Sigma = np.linalg.inv(H)
        mu = -Sigma @ g
        X = se3_exp(mu) @ X
    return X, 0.5 * (Sigma + Sigma.T)


def filter_step(S_prev, fil_mean, fil_cov, S_now, obs_mean, obs_cov, Q, order, iterations):
    """Algorithm 2 (alg:se3_bayes_filter): predict with T = S_now⁻¹ S_prev, then fuse(obs, belief)."""
    T = se3_inv(S_now) @ S_prev
    A = se3_Ad(T)
    bel_mean = T @ fil_mean
    bel_cov = A @ fil_cov @ A.T + Q
    bel_cov = 0.5 * (bel_cov + bel_cov.T)
    return fuse([obs_mean, bel_mean], [obs_cov, bel_cov], order, iterations)


def parse(path):
    rows = []
    with open(path) as f:
        for line in f:
            parts = line.strip().split(",")
            if len(parts) < 3:
                continue
            kind, order, iters = parts[0], int(parts[1]), int(parts[2])
            vals = np.array([float(v) for v in parts[3:]])
            rows.append((kind, order, iters, vals))
    return rows


def take(vals, pos, shape):
    n = shape[0] * shape[1]
    return vals[pos:pos + n].reshape(shape), pos + n


def unpack(kind, vals):
    shapes = {"fuse": [(4, 4), (6, 6), (4, 4), (6, 6), (4, 4), (6, 6)],
              "filter": [(4, 4), (4, 4), (6, 6), (4, 4), (4, 4), (6, 6), (6, 6), (4, 4), (6, 6)]}[kind]
    out, pos = [], 0
    for s in shapes:
        m, pos = take(vals, pos, s)
        out.append(m)
    assert pos == len(vals), f"{kind}: {len(vals)} values, expected {pos}"
    return out


def run_case(kind, order, iters, mats):
    if kind == "fuse":
        A, SA, B, SB = mats[:4]
        return fuse([A, B], [SA, SB], order, iters)
    return filter_step(*mats[:7], order, iters)


def rel_diff(a, b):
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--check", required=True, help="CSV written by lieservo_speed_error_report --dump")
    ap.add_argument("--bench", action="store_true", help="also time fusion and filter step")
    ap.add_argument("--reps", type=int, default=15)
    args = ap.parse_args()
    rows = parse(args.check)
    if not rows:
        print("no cases in", args.check)
        return 1
    worst = 0.0
    for kind, order, iters, vals in rows:
        mats = unpack(kind, vals)
        X, S = run_case(kind, order, iters, mats)
        d = max(rel_diff(X, mats[-2]), rel_diff(S, mats[-1]))
        worst = max(worst, d)
        if d > TOL:
            print(f"MISMATCH {kind} order={order} iterations={iters}: relative difference {d:.3e}")
    print(f"numpy baseline vs C++: {len(rows)} cases, worst relative difference {worst:.3e} (tolerance {TOL:g})")
    if worst > TOL:
        return 1
    if args.bench:
        # Timing: the paper's configuration (series N = 2, 5 iterations).
        for kind in ("fuse", "filter"):
            cases = [unpack(k, v) for k, o, i, v in rows if k == kind and o == 2 and i == 5]
            times = []
            for _ in range(args.reps):
                t0 = time.perf_counter()
                for m in cases:
                    run_case(kind, 2, 5, m)
                times.append((time.perf_counter() - t0) / len(cases))
            print(f"numpy_time,{kind},series2_5it,{1e9 * float(np.median(times)):.0f} ns")
    return 0


if __name__ == "__main__":
    sys.exit(main())
