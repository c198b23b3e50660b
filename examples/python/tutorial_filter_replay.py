#!/usr/bin/env python3
"""Tutorial (Python): the SE(3) Bayes filter on real TacTip images, as the paper's Table 2.

What you will see: the GDN (the project's ONNX model, run by OpenCV's dnn module as its model card
says: input size, output units, σ calibration, SHA-256) predicts the contact pose and shear ξ with
an uncertainty σ from each tactile image; `lieservo` turns each
(μ, σ) into a concentrated Gaussian on SE(3) and filters the sequence. The filter knows how the
sensor moved between two images (the robot's own motion, with noise of σψ), so the smaller σψ,
the more it can average the network's errors away.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/tutorial_filter_replay.py \
        [--data ../shared/data/tactip] [--n 300] [--check]

The data set: the shared TacTip validation split (an unseen session for the network). Exits
77 (CTest's "skipped") with a message when the data or the model is not there.
"""
import argparse
import csv
import hashlib
import json
import math
import os
import sys

import cv2
import numpy as np

import lieservo as ls

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DEG = math.pi / 180


# ---- 1. the data: images and their labels ---------------------------------------------------
def read_split(split_dir, n):
    """First n rows of targets.csv: image paths and labels ξ = log(X_fs⁻¹)^∨ (mm, rad)."""
    paths, labels = [], []
    with open(os.path.join(split_dir, "targets.csv"), newline="") as f:
        for row in csv.DictReader(f):
            # The contact pose X_fs as extrinsic x-y-z Euler angles (mm, deg): shear x, y, depth
            # z, tilts α, β, twist γ (paper Section 3.1.3 (sec:pre_post_processing)).
            e = np.array([float(row[k]) for k in
                          ("shear_x", "shear_y", "pose_z", "pose_Rx", "pose_Ry", "shear_Rz")])
            labels.append(ls.SE3.from_euler_xyz6_degrees(e).inverse().log())
            paths.append(os.path.join(split_dir, "processed_images", row["sensor_image"]))
            if len(paths) == n:
                break
    return paths, np.array(labels)


# ---- 2. the network's card: what it takes and what its outputs mean --------------------------
UNIT = {"mm": 1.0, "deg": DEG, "degree": DEG, "degrees": DEG, "rad": 1.0, "radian": 1.0, "radians": 1.0}


def read_card(models_dir):
    """The GDN's entry of model_card.json, read as the C++ adapters read it (ModelCard): its ONNX
    file (checked against the card's SHA-256), its input size, the unit of each μ component
    (library units are mm and rad) and its σ calibration (1 when the card has none)."""
    path = os.path.join(models_dir, "model_card.json")
    gdn = json.load(open(path))["models"]["gdn"]
    onnx = os.path.join(models_dir, gdn.get("file", "gdn.onnx"))
    digest = hashlib.sha256(open(onnx, "rb").read()).hexdigest()
    if gdn.get("sha256") and digest != gdn["sha256"]:
        raise SystemExit(f"{onnx}: SHA-256 {digest} does not match the card's {gdn['sha256']}")
    units = gdn["output"]["units"]  # "mu: mm, mm, mm, deg, deg, deg; sigma_inv: ..." or a list
    if isinstance(units, str):
        units = units.split("mu:")[-1].split(";")[0].split(",")
    scale = gdn.get("sigma_calibration", {}).get("scale", [1.0] * 6)
    return {"onnx": onnx, "size": int(gdn["input"]["shape"][-1]),
            "to_library": np.array([UNIT[u.strip()] for u in units[:6]]), "sigma_scale": np.array(scale, float)}


# ---- 3. the network: μ and σ for every image -------------------------------------------------
def run_gdn(card, paths, batch=50):
    """The GDN's (μ, σ) in library units (mm, rad), σ calibrated as its card says. Pre-processing
    as the card says: 8-bit grey → size × size (INTER_AREA) → float32 / 255."""
    net = cv2.dnn.readNetFromONNX(card["onnx"])
    size = card["size"]
    mu, sigma = [], []
    for start in range(0, len(paths), batch):
        images = []
        for p in paths[start:start + batch]:
            img = cv2.imread(p, cv2.IMREAD_GRAYSCALE)
            if img is None:
                raise SystemExit(f"cannot read {p}")
            images.append(cv2.resize(img, (size, size), interpolation=cv2.INTER_AREA).astype(np.float32) / 255)
        net.setInput(np.stack(images)[:, None, :, :])
        out = net.forward().astype(np.float64)   # (N, 12): μ then σ⁻¹, in the card's units
        m = out[:, :6] * card["to_library"]       # e.g. deg → rad
        s = card["sigma_scale"] / out[:, 6:] * card["to_library"]
        mu.append(m)
        sigma.append(s)
    return np.vstack(mu), np.vstack(sigma)


def report_units(xi):
    """mm and degrees, for printing."""
    out = np.array(xi, dtype=float)
    out[..., 3:] /= DEG
    return out


# ---- 4. the filter over the sequence ----------------------------------------------------------
def filter_sequence(labels, observations, sigma_psi, rng):
    """The Table 2 experiment: the sensor's motion between images k−1 and k is the true relative
    motion X_k X_{k−1}⁻¹ disturbed by exp(ψ^), ψ ~ N(0, σψ² 1) (eq. 23, eqn:se3_filter_exp_state_trans_model);
    the filter's process noise is the same Σψ. Returns the filtered means' tangent vectors."""
    sd = np.array([sigma_psi] * 3 + [sigma_psi * DEG] * 3)
    f = ls.DiscriminativeBayesFilter(process_noise=np.diag(sd ** 2))
    X = [ls.SE3.exp(xi) for xi in labels]
    out = []
    for k, obs in enumerate(observations):
        if k == 0:
            f.step(ls.SE3(), obs)                       # the first step initialises
        else:
            T = ls.SE3.exp(sd * rng.standard_normal(6)) * X[k] * X[k - 1].inverse()
            f.predict(T)                                # belief: where the motion takes the state
            f.correct(obs)                              # fused with the network's estimate
        out.append(f.filtered.mean.log())
    return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=os.environ.get("LIESERVO_DATA_DIR",
                                                     os.path.join(ROOT, "..", "shared", "data", "tactip")))
    ap.add_argument("--models", default=os.path.join(ROOT, "examples", "gdn", "models"))
    ap.add_argument("--n", type=int, default=300, help="images of the validation split (first n)")
    ap.add_argument("--sigmas", default="10,1,0.1,0.01", help="σψ values (mm and deg)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless the smallest σψ lowers the error of every component")
    a = ap.parse_args()
    split = os.path.join(a.data, "val")
    for need in (os.path.join(split, "targets.csv"), os.path.join(a.models, "model_card.json"),
                 os.path.join(a.models, "gdn.onnx")):
        if not os.path.exists(need):
            print(f"tutorial skipped: {need} is missing")
            return 77

    paths, labels = read_split(split, a.n)
    mu, sigma = run_gdn(read_card(a.models), paths)
    # Each network output as a concentrated Gaussian: X̄ = exp(μ^), Σ = J(μ) diag(σ²) J(μ)ᵀ.
    observations = [ls.from_tangent_gaussian(m, s) for m, s in zip(mu, sigma)]

    names = ["rho_x mm", "rho_y mm", "rho_z mm", "phi_x deg", "phi_y deg", "phi_z deg"]
    truth = report_units(labels)
    gdn_mae = np.mean(np.abs(report_units(mu) - truth), axis=0)
    print(f"{len(paths)} validation images, GDN on OpenCV dnn, filter from lieservo (Python)\n")
    print(f"{'mean absolute error':24s}" + "".join(f"{n:>11s}" for n in names))
    print(f"{'GDN alone':24s}" + "".join(f"{v:11.3f}" for v in gdn_mae))
    rng = np.random.default_rng(a.seed)
    rows = []
    for sig in (float(s) for s in a.sigmas.split(",")):
        est = filter_sequence(labels, observations, sig, rng)
        mae = np.mean(np.abs(report_units(est) - truth), axis=0)
        rows.append((sig, mae))
        print(f"{'filter, sigma_psi ' + format(sig, 'g'):24s}" + "".join(f"{v:11.3f}" for v in mae))
    if a.check:
        smallest = min(rows, key=lambda r: r[0])[1]
        if not np.all(np.isfinite(smallest)) or not np.all(smallest < gdn_mae):
            print("check FAILED: the smallest sigma_psi does not lower every component's error")
            return 1
        print("\ncheck: the smallest sigma_psi lowers every component's error")
    return 0


if __name__ == "__main__":
    sys.exit(main())
