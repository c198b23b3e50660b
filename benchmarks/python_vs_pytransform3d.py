#!/usr/bin/env python3
"""lieservo's fuse() from Python beside pytransform3d's pose_fusion on the same inputs.

pytransform3d is not a dependency of lieservo: fetch it for the measurement only, e.g.

    git clone https://github.com/dfki-ric/pytransform3d /tmp/pytransform3d
    PYTHONPATH=build/release/python:/tmp/pytransform3d /usr/bin/python3 \
        benchmarks/python_vs_pytransform3d.py

Both fuse two SE(3) concentrated Gaussians with the closed-form J⁻¹ (Barfoot & Furgale's
iteration; Algorithm 3 (alg:se3_data_fusion)). pytransform3d orders exponential coordinates rotation first,
lieservo translation first (ξ = [ρ; φ]): covariances are permuted between the two. Reported:
the largest difference of the fused mean (matrix entries) and covariance, and the median time
per call of each, over 50 seeded input pairs.
"""
import statistics
import sys
import timeit

import numpy as np

import lieservo as ls

try:
    from pytransform3d.uncertainty import pose_fusion
except ImportError:
    print("pytransform3d not found: put a checkout on PYTHONPATH (see the docstring)")
    sys.exit(77)

P = np.r_[3:6, 0:3]  # [ρ; φ] ↔ [φ; ρ]


def to_pt(cov):
    return cov[np.ix_(P, P)]


def case(rng):
    """Two GDN-like observations of one contact: σ 0.2–1 mm and 0.5–2°, means apart by them."""
    xi = np.r_[rng.normal(0, 2, 3), rng.normal(0, 0.2, 3)]
    out = []
    for _ in range(2):
        sigma = np.r_[rng.uniform(0.2, 1.0, 3), np.radians(rng.uniform(0.5, 2.0, 3))]
        out.append(ls.from_tangent_gaussian(xi + sigma * rng.standard_normal(6), sigma))
    return out


def median_us(fn, number):
    return statistics.median(timeit.repeat(fn, number=number, repeat=5)) / number * 1e6


def main():
    rng = np.random.default_rng(7)
    worst_mean = worst_cov = 0.0
    t_ls20, t_pt = [], []
    for _ in range(50):
        a, b = case(rng)
        means = np.array([a.mean.matrix(), b.mean.matrix()])
        covs = np.array([to_pt(a.covariance), to_pt(b.covariance)])
        pt_mean, pt_cov, _ = pose_fusion(means, covs)
        r = ls.fuse(a, b, max_iterations=20, jacobian="closed_form")
        worst_mean = max(worst_mean, np.max(np.abs(r["fused"].mean.matrix() - pt_mean)))
        worst_cov = max(worst_cov, np.max(np.abs(to_pt(r["fused"].covariance) - pt_cov)) / np.max(np.abs(pt_cov)))
        t_ls20.append(median_us(lambda: ls.fuse(a, b, max_iterations=20, jacobian="closed_form"), 200))
        t_pt.append(median_us(lambda: pose_fusion(means, covs), 3))
    pt, l20 = statistics.median(t_pt), statistics.median(t_ls20)
    print("50 seeded pairs of SE(3) Gaussians (σ 0.2–1 mm, 0.5–2°)")
    print(f"largest difference: mean {worst_mean:.1e} (matrix entries), covariance {worst_cov:.1e} (relative)")
    print(f"pytransform3d pose_fusion (20 iterations): {pt:.0f} µs per call")
    print(f"lieservo.fuse, closed form, 20 iterations:  {l20:.2f} µs per call ({pt / l20:.0f}x faster)")


if __name__ == "__main__":
    main()
