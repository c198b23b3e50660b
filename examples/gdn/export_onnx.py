#!/usr/bin/python3
"""Export trained GDN / CNN checkpoints to ONNX (opset 13, dynamic batch) loadable by
OpenCV 4.6 cv2.dnn.readNetFromONNX, verify cv2.dnn against PyTorch on real validation
images, write the reference outputs for the C++ tests and the model card.

    /usr/bin/python3 examples/gdn/export_onnx.py --gdn-run runs/gdn --cnn-run runs/cnn \
        [--weights best|last]

--weights picks the checkpoint train.py wrote: `best` (lowest validation loss, <kind>_best.pt) or
`last` (the final epoch, <kind>_last.pt -- what Keras's EarlyStopping hands back by default,
restore_best_weights=False).

Which images measure the model follows from what it was trained on (the run's
<kind>_summary.json): a run on `train` only is measured on the whole `val` split (another
recording session), written as the card's "validation"; a run that also trained on `val`
(train.py --sessions train,val --holdout N) is measured on the rows it held out of each session,
written as "held_out", and those rows are listed in held_out.csv beside the card. The card's
data.trained_on says how many images of each split the network saw.

    /usr/bin/python3 examples/gdn/export_onnx.py --gdn-run runs/gdn_trainval --cnn-run /nonexistent \
        --weights last --out-dir models/train_val

Outputs (in --out-dir, default examples/gdn/models/):
    gdn.onnx   input "input" [N,1,128,128] float32 in [0,1]; output "output" [N,12] =
               (mu_1..6, sigma^-1_1..6), units (mm, mm, mm, deg, deg, deg) and their inverses
    cnn.onnx   output [N,6] = xi estimate, (mm, mm, mm, deg, deg, deg)
    gdn_reference_outputs.csv   first 8 val images, PyTorch (eval) outputs, %.17g
    model_card.json
    held_out.csv   (a run trained on val too) split,sensor_image of the rows it never saw
"""
from __future__ import annotations

import argparse
import datetime as dt
import hashlib
import json
import math
import os
import sys

import numpy as np
import torch

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from model import CNN_ALPHA_DEG, TORCH_BN, BatchNormOptions, build  # noqa: E402
from model_card import COMP, PAPER_TABLE1, card_common, model_entry  # noqa: E402

FORBIDDEN_OPS = {'Where', 'Clip', 'Min', 'Max', 'Softplus', 'Reshape'}
MODELS_DIR = os.path.join(HERE, 'models')


def export_model(model: torch.nn.Module, path: str, size: int = 128) -> list:
    """Export in eval mode; returns the list of op types. Raises if a forbidden op appears."""
    import onnx
    model = model.eval()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    x = torch.zeros(1, 1, size, size)
    torch.onnx.export(model, x, path, opset_version=13, input_names=['input'],
                      output_names=['output'], dynamic_axes={'input': {0: 'N'}, 'output': {0: 'N'}},
                      do_constant_folding=True)
    m = onnx.load(path)
    _inline_identity_initializers(m)
    onnx.save(m, path)
    onnx.checker.check_model(m)
    ops = sorted({n.op_type for n in m.graph.node})
    bad = FORBIDDEN_OPS.intersection(ops)
    if bad:
        raise RuntimeError(f'{path}: ops not usable by OpenCV 4.6 cv2.dnn: {sorted(bad)}')
    return ops


def _inline_identity_initializers(m) -> None:
    """The exporter de-duplicates equal initializers and re-creates them with Identity nodes;
    OpenCV 4.6 cannot parse an Identity whose input is an initializer. Replace each such node
    by a copy of the initializer under the output name."""
    import copy
    inits = {t.name: t for t in m.graph.initializer}
    keep = []
    for n in m.graph.node:
        if n.op_type == 'Identity' and len(n.input) == 1 and n.input[0] in inits:
            t = copy.deepcopy(inits[n.input[0]])
            t.name = n.output[0]
            m.graph.initializer.append(t)
        else:
            keep.append(n)
    del m.graph.node[:]
    m.graph.node.extend(keep)


def cv2_forward(path: str, x: np.ndarray) -> np.ndarray:
    import cv2
    net = cv2.dnn.readNetFromONNX(path)
    net.setPreferableBackend(cv2.dnn.DNN_BACKEND_OPENCV)
    net.setPreferableTarget(cv2.dnn.DNN_TARGET_CPU)
    net.setInput(np.ascontiguousarray(x, dtype=np.float32))
    return np.asarray(net.forward())


def torch_forward(model, x: np.ndarray) -> np.ndarray:
    model.eval()
    with torch.no_grad():
        return model(torch.from_numpy(np.ascontiguousarray(x, dtype=np.float32))).numpy()


def load_ckpt(path: str):
    ck = torch.load(path, map_location='cpu')
    bn = BatchNormOptions(**ck['bn']) if 'bn' in ck else TORCH_BN  # older checkpoints: PyTorch's
    m = build(ck['kind'], tuple(ck['channels']), bn=bn)
    m.load_state_dict(ck['state_dict'])
    return m.eval(), ck


def write_reference(path, names, out):
    n = out.shape[1]
    hdr = (['mu_rho1_mm', 'mu_rho2_mm', 'mu_rho3_mm', 'mu_phi1_deg', 'mu_phi2_deg', 'mu_phi3_deg',
            'sinv_rho1_per_mm', 'sinv_rho2_per_mm', 'sinv_rho3_per_mm', 'sinv_phi1_per_deg',
            'sinv_phi2_per_deg', 'sinv_phi3_per_deg'] if n == 12 else COMP)
    with open(path, 'w') as f:
        f.write('sensor_image,' + ','.join(hdr) + '\n')
        for nm, row in zip(names, out):
            f.write(nm + ',' + ','.join('%.17g' % float(v) for v in row) + '\n')


def run_sessions(run: str, kind: str) -> list:
    """The splits a train.py run trained on (its <kind>_summary.json; runs that predate
    --sessions trained on train only)."""
    sp = os.path.join(run, f'{kind}_summary.json')
    if os.path.isfile(sp):
        with open(sp) as f:
            return list(json.load(f).get('sessions', ['train']))
    return ['train']


def run_held_out(run: str) -> dict:
    """{split: sorted row indices} that a train.py --holdout run kept out of training."""
    from train import HOLDOUT_SEEDS, holdout_file
    held = {}
    for split in HOLDOUT_SEEDS:
        p = os.path.join(run, holdout_file(split))
        if os.path.isfile(p):
            held[split] = np.loadtxt(p, dtype=np.int64, ndmin=1)
    return held


def evaluation_rows(sessions, held: dict, n_rows: dict):
    """What the exported model is measured on: ('validation', {'val': all rows}) for a model that
    never saw val (another recording session); ('held_out', {split: rows held out of it}) for a
    model trained on val too -- only rows it never saw, of every session it trained on.
    Also returns data.trained_on, {split: number of images trained on}."""
    unknown = [s for s in sessions if s not in n_rows]
    if unknown or not sessions:
        raise ValueError(f'sessions {sessions}: each must be one of {sorted(n_rows)}')
    trained_on = {s: int(n_rows[s] - len(held.get(s, ()))) for s in sessions}
    if 'val' not in sessions:
        return 'validation', {'val': np.arange(n_rows['val'])}, trained_on
    missing = [s for s in sessions if len(held.get(s, ())) == 0]
    if missing:
        raise ValueError(f'a model trained on {"+".join(sessions)} has no held-out rows of '
                         f'{", ".join(missing)}: nothing unseen to measure it on (train.py --holdout N)')
    return 'held_out', {s: np.asarray(held[s]) for s in sessions}, trained_on


def plan_exports(args, splits, card, card_path):
    """What each run trained on, checked before anything is written: one card describes one
    training set, so two runs trained on different images (or a run and a model the card keeps)
    are refused with the folder untouched. Returns (jobs, trained_on, held)."""
    jobs, data_seen = [], None   # data_seen: (trained_on, held-out rows)
    for kind, run in (('gdn', args.gdn_run), ('cnn', args.cnn_run)):
        ck_path = os.path.join(run, f'{kind}_{args.weights}.pt')
        if not os.path.isfile(ck_path):
            print(f'skip {kind}: no checkpoint {ck_path}')
            continue
        sessions = run_sessions(run, kind)
        held = {s: r for s, r in run_held_out(run).items() if s in sessions}
        try:
            eval_key, eval_rows, trained_on = evaluation_rows(
                sessions, held, {s: len(sp.images) for s, sp in splits.items()})
        except ValueError as e:
            raise SystemExit(f'{run}: {e}')
        seen = (trained_on, {s: r.tolist() for s, r in held.items()})
        if data_seen is not None and seen != data_seen:
            raise SystemExit(f'{run}: trained on other images than the model exported before it; '
                             'one card describes one training set (use another --out-dir)')
        data_seen = seen
        jobs.append((kind, run, ck_path, sessions, eval_key, eval_rows))
    if data_seen is None:
        raise SystemExit('nothing exported: no checkpoint found (--gdn-run, --cnn-run)')
    trained_on, held = data_seen
    kept = [k for k in card['models'] if k not in [j[0] for j in jobs]]
    before = card.get('data', {}).get('trained_on')
    if kept and before is not None and before != trained_on:
        raise SystemExit(f'{card_path} also describes {", ".join(kept)}, trained on {before}, not '
                         f'{trained_on}: one card describes one training set (use another --out-dir)')
    return jobs, trained_on, held


def measure(model, kind, eval_key, eval_rows, splits, labels):
    """The exported weights' errors (torch, eval mode) on images the model never saw: the card's
    `eval_key` entry (n, mae, by_split for held-out rows, and the loss)."""
    outs, ys, by_split = [], [], {}
    for split, rows in eval_rows.items():
        xs = splits[split].images[rows]
        o = np.concatenate([torch_forward(model, xs[i:i + 50]) for i in range(0, len(xs), 50)])
        outs.append(o)
        ys.append(labels[split][rows])
        by_split[split] = {'n': int(len(rows)),
                           'mae': dict(zip(COMP, map(float, np.abs(o[:, :6] - ys[-1]).mean(0))))}
    out, Y = np.concatenate(outs), np.concatenate(ys)
    mae = np.abs(out[:, :6] - Y).mean(0)
    pre = 'val_' if eval_key == 'validation' else ''
    if kind == 'gdn':
        s = out[:, 6:].astype(np.float64)
        nll_deg = float(np.mean(np.sum(0.5 * (s * (Y - out[:, :6])) ** 2 - np.log(s), 1)))
        nll_rad = nll_deg - 3 * math.log(180 / math.pi)
        loss = {pre + 'nll_mm_deg': nll_deg, pre + 'nll_mm_rad': nll_rad,
                pre + 'nll_mm_rad_plus_c': nll_rad + 3 * math.log(2 * math.pi),
                'calibration_frac_within_1sigma': dict(zip(COMP, map(float, np.mean(
                    np.abs(Y - out[:, :6]) * s <= 1.0, 0)))),
                'median_sigma': dict(zip(COMP, map(float, np.median(1.0 / s, 0)))),
                'note': 'mean NLL without c in training units (mm, deg); converted to '
                        'mm/rad (paper units): -3 ln(180/pi); "+c" adds 6/2 ln(2 pi) '
                        '(the paper\'s -7.20 appears to include it)'}
    else:
        mse = float(np.mean(np.sum(np.asarray(CNN_ALPHA_DEG) * (Y - out) ** 2, 1)))
        loss = {pre + 'weighted_mse': mse,
                'note': 'alpha = (1,1,1,100,100,100) with rotations in radians == '
                        'alpha*(pi/180)^2 on degrees; same value as the paper\'s loss'}
    return {'n': int(len(Y)), 'mae': dict(zip(COMP, map(float, mae))),
            **({'by_split': by_split} if eval_key == 'held_out' else {}), **loss}


def read_json(path) -> dict:
    """A run's JSON record, or {} when the run did not write it."""
    if not os.path.isfile(path):
        return {}
    with open(path) as f:
        return json.load(f)


def export_one(args, job, X, splits, labels):
    """Exports one run's checkpoint, checks cv2.dnn against PyTorch and measures it: its card entry."""
    kind, run, ck_path, sessions, eval_key, eval_rows = job
    model, ck = load_ckpt(ck_path)
    onnx_path = os.path.join(args.out_dir, f'{kind}.onnx')
    ops = export_model(model, onnx_path)
    xv = X[:args.n_verify]
    pt = torch_forward(model, xv)
    cv = cv2_forward(onnx_path, xv)
    diff = float(np.abs(pt - cv).max())
    rel = float((np.abs(pt - cv) / np.maximum(1.0, np.abs(pt))).max())
    print(f'{kind}: cv2.dnn vs torch max|diff| = {diff:.3g} (rel {rel:.3g}) on {len(xv)} val images')
    check = {'opencv': __import__('cv2').__version__, 'n_images': int(len(xv)),
             'max_abs_diff': diff, 'max_rel_diff': rel, 'pass_1e-4': bool(rel < 1e-4)}
    measured = measure(model, kind, eval_key, eval_rows, splits, labels)
    if kind == 'gdn':
        write_reference(os.path.join(args.out_dir, 'gdn_reference_outputs.csv'), splits['val'].names[:8], pt[:8])
    summ = read_json(os.path.join(run, f'{kind}_summary.json'))
    hist = read_json(os.path.join(run, f'{kind}_history.json'))
    with open(onnx_path, 'rb') as f:
        digest = hashlib.sha256(f.read()).hexdigest()  # the C++ loader checks it
    return model_entry(kind, ck, summ, hist, args.weights, sessions, digest, ops, eval_key, measured, check)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--gdn-run', default='runs/gdn')
    ap.add_argument('--cnn-run', default='runs/cnn')
    ap.add_argument('--data', default=None)
    ap.add_argument('--weights', choices=['best', 'last'], default='best',
                    help='checkpoint to export: lowest validation loss or final epoch')
    ap.add_argument('--n-verify', type=int, default=64)
    ap.add_argument('--out-dir', default=MODELS_DIR)
    args = ap.parse_args(argv)
    torch.set_num_threads(1)

    from dataset import load_split
    import labels as L
    splits = {s: load_split(args.data, s, verbose=False) for s in ('train', 'val')}
    labels = {s: L.to_train_units(L.xi_from_euler6(sp.euler6)) for s, sp in splits.items()}
    X = splits['val'].images   # the cv2.dnn check and the reference outputs: first val images

    card_path = os.path.join(args.out_dir, 'model_card.json')
    card = read_json(card_path)
    card.setdefault('models', {})
    jobs, trained_on, held = plan_exports(args, splits, card, card_path)
    os.makedirs(args.out_dir, exist_ok=True)
    for job in jobs:
        card['models'][job[0]] = export_one(args, job, X, splits, labels)
    card.update(card_common(trained_on))
    card['data']['trained_on'] = trained_on
    card['data'].pop('held_out', None)
    held_path = os.path.join(args.out_dir, 'held_out.csv')
    if held:
        card['data']['held_out'] = {**{s: len(r) for s, r in held.items()}, 'file': 'held_out.csv'}
        with open(held_path, 'w') as f:
            f.write('split,sensor_image\n')
            for split, rows in held.items():
                f.writelines(f'{split},{splits[split].names[i]}\n' for i in rows)
    elif os.path.isfile(held_path):
        os.remove(held_path)   # a previous model's list; the card no longer names it
    card['paper_table1_note'] = PAPER_TABLE1['note']
    card['generated_utc'] = dt.datetime.now(dt.timezone.utc).strftime('%Y-%m-%dT%H:%M:%SZ')
    with open(card_path, 'w') as f:
        json.dump(card, f, indent=1)
    print('wrote', card_path)


if __name__ == '__main__':
    main()
