#!/usr/bin/env python3
"""Per-call cost of the lieservo Python module (median of repetitions, seconds → µs).

    PYTHONPATH=build/release/python /usr/bin/python3 benchmarks/python_bench.py

Times: SE3.exp, SE3.log, fuse (paper and closed form, 5 iterations), a filter step, and the
batch exp/log per element over 10 000 rows, beside the same SE(3) exp and fusion written in
NumPy (benchmarks/numpy_baseline.py).
"""
import statistics
import sys
import timeit

import numpy as np

import lieservo as ls

sys.path.insert(0, __file__.rsplit("/", 1)[0])
import numpy_baseline as nb  # noqa: E402  (the NumPy reference implementation)


def per_call_us(fn, number, repeat=7):
    return statistics.median(timeit.repeat(fn, number=number, repeat=repeat)) / number * 1e6


def main():
    rng = np.random.default_rng(1)
    xi = np.array([1.0, 2.0, 3.0, 0.1, 0.2, 0.3])
    X = ls.SE3.exp(xi)
    sigma = np.array([0.5, 0.5, 0.5, 0.02, 0.02, 0.02])
    a = ls.from_tangent_gaussian(xi, sigma)
    b = ls.from_tangent_gaussian(xi + 0.1, sigma)
    f = ls.DiscriminativeBayesFilter()
    f.step(ls.SE3(), a)
    pose = ls.SE3.exp(np.array([0.1, 0, 0, 0, 0, 0]))
    rows = rng.normal(size=(10000, 6)) * 0.5
    Ms = ls.SE3.exp_batch(rows)
    print("operation | µs per call (median of 7)")
    print(f"SE3.exp | {per_call_us(lambda: ls.SE3.exp(xi), 20000):.2f}")
    print(f"SE3.log | {per_call_us(lambda: X.log(), 20000):.2f}")
    print(f"fuse (paper, 5 it.) | {per_call_us(lambda: ls.fuse(a, b), 5000):.2f}")
    print(f"fuse (closed form, 5 it.) | {per_call_us(lambda: ls.fuse(a, b, jacobian='closed_form'), 5000):.2f}")
    print(f"filter step | {per_call_us(lambda: f.step(pose, b), 5000):.2f}")
    print(f"SE3.exp_batch, per row of 10 000 | {per_call_us(lambda: ls.SE3.exp_batch(rows), 20) / 1e4:.3f}")
    print(f"SE3.log_batch, per row of 10 000 | {per_call_us(lambda: ls.SE3.log_batch(Ms), 20) / 1e4:.3f}")
    A_m, B_m = a.mean.matrix(), b.mean.matrix()
    A_c, B_c = a.covariance, b.covariance
    print(f"NumPy SE(3) exp (numpy_baseline.py) | {per_call_us(lambda: nb.se3_exp(xi), 5000):.2f}")
    print(f"NumPy fuse (numpy_baseline.py, series N = 2, 5 it.) | "
          f"{per_call_us(lambda: nb.fuse([A_m, B_m], [A_c, B_c], 2, 5), 200):.2f}")


if __name__ == "__main__":
    main()
