#!/usr/bin/python3
"""Train the paper's GDN (or the CNN-regression baseline) pose-and-shear model on the TacTip
data set, keep the best-validation-loss weights, and export ONNX (see export_onnx.py).

    /usr/bin/python3 examples/gdn/train.py --model gdn --epochs 30 --threads 1 \
        --out runs/gdn --channels 16,32,64,128,256

Labels: xi = log(X_fs^-1)^vee = (rho [mm], phi [DEGREES]) -- see labels.py / model card.
Schedule (LRPD): lr 1e-5 -> 1e-3 linearly over 3 epochs (per step), hold 1 epoch, then
lr = (1e-3 - 1e-7) sqrt(1 - d / (e_max - 4)) + 1e-7 with d the epochs since the hold, so that
the schedule reaches 1e-7 at epoch e_max (paper: e_max = 50). Early stopping: patience 25.
"""
from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import os
import sys
import time

import numpy as np
import torch

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from augment import PRESETS as AUGMENT_PRESETS, augment  # noqa: E402
from dataset import default_data_dir, load_split  # noqa: E402
import labels as L  # noqa: E402
from model import CNN_ALPHA_DEG, KERAS_BN, TORCH_BN, beta_nll, build, gdn_nll, keras_init_, weighted_mse  # noqa: E402

COMP = ['rho1_mm', 'rho2_mm', 'rho3_mm', 'phi1_deg', 'phi2_deg', 'phi3_deg']


def lrpd(e: float, e_max: float, lr0=1e-5, lr1=1e-3, lr_end=1e-7, ramp=3.0, hold=1.0) -> float:
    """LRPD schedule at (fractional) epoch e."""
    if e < ramp:
        return lr0 + (lr1 - lr0) * e / ramp
    if e < ramp + hold:
        return lr1
    span = max(e_max - ramp - hold, 1e-9)
    f = max(0.0, 1.0 - (e - ramp - hold) / span)
    return (lr1 - lr_end) * math.sqrt(f) + lr_end


def evaluate(model, kind, X, Y, alpha, bs=32):
    model.eval()
    outs = []
    with torch.no_grad():
        for i in range(0, len(X), bs):
            outs.append(model(X[i:i + bs]))
    out = torch.cat(outs)
    loss = gdn_nll(out, Y) if kind == 'gdn' else weighted_mse(out, Y, alpha)
    mae = (out[:, :6] - Y).abs().mean(0)
    return float(loss), mae.numpy().astype(float), out


# One fixed seed per session, independent of --seed, so every run holds out the same rows.
HOLDOUT_SEEDS = {'train': 20221122, 'val': 20221123}


def holdout_file(split: str) -> str:
    """The file (in a run directory) listing the rows of `split` that --holdout kept out."""
    return 'holdout.txt' if split == 'train' else f'holdout_{split}.txt'


def holdout_indices(n: int, k: int, seed: int = HOLDOUT_SEEDS['train']) -> np.ndarray:
    """The k rows of a split that --holdout keeps out (sorted)."""
    if not 0 < k < n:
        raise SystemExit(f'--holdout {k}: must be between 1 and {n - 1}')
    return np.sort(np.random.RandomState(seed).permutation(n)[:k])


def make_optimizer(params, eps: float, weight_decay: float):
    """Adam (the paper's), or AdamW when weight_decay > 0: decoupled weight decay, which shrinks
    the weights by lr * weight_decay per step apart from the gradient. The learning rate is set
    per step by the schedule."""
    if not (weight_decay >= 0 and math.isfinite(weight_decay)):
        raise SystemExit(f'--weight-decay {weight_decay}: must be finite and >= 0')
    if weight_decay > 0:
        return torch.optim.AdamW(params, lr=1e-5, eps=eps, weight_decay=weight_decay)
    return torch.optim.Adam(params, lr=1e-5, eps=eps)


def parse_deadline(s):
    if not s:
        return None
    now = dt.datetime.now(dt.timezone.utc)
    hh, mm = (int(v) for v in s.split(':'))
    d = now.replace(hour=hh, minute=mm, second=0, microsecond=0)
    if d < now - dt.timedelta(hours=12):
        d += dt.timedelta(days=1)
    return d.timestamp()


def parse_args(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--model', choices=['gdn', 'cnn'], default='gdn')
    ap.add_argument('--epochs', type=int, default=50, help='max epochs to run')
    ap.add_argument('--e-max', type=float, default=None,
                    help='epoch at which the LRPD schedule reaches 1e-7 (default: --epochs)')
    ap.add_argument('--patience', type=int, default=25)
    ap.add_argument('--lr-max', type=float, default=1e-3, help='peak learning rate (paper 1e-3)')
    ap.add_argument('--channels', default='16,32,64,128,256')
    ap.add_argument('--batch', type=int, default=16)
    ap.add_argument('--bn', choices=['torch', 'keras'], default='keras',
                    help='BatchNorm eps/momentum: PyTorch defaults (1e-5, 0.1) or the paper\'s '
                    'TensorFlow/Keras defaults (1e-3, 0.01 in PyTorch terms)')
    ap.add_argument('--init', choices=['torch', 'keras'], default='torch',
                    help='weight initialisation: PyTorch defaults, or Keras (Glorot-uniform, zero bias)')
    ap.add_argument('--adam-eps', type=float, default=1e-8,
                    help='Adam epsilon (PyTorch default 1e-8; Keras 1e-7)')
    ap.add_argument('--sessions', default='train',
                    help='comma-separated splits (recording sessions) to train on: train, or '
                    'train,val for the shipped model (needs --holdout; the held-out rows of '
                    'every session then replace val as the monitored set)')
    ap.add_argument('--holdout', type=int, default=0,
                    help='keep this many images of each trained-on session (a seeded random '
                    'choice, listed in DIR/holdout.txt for train and DIR/holdout_<split>.txt for '
                    'the others) out of training, for calibrate_sigma.py')
    ap.add_argument('--augment', choices=sorted(AUGMENT_PRESETS), default='none',
                    help='training-image augmentation preset (augment.py); none = the paper')
    ap.add_argument('--weight-decay', type=float, default=0.0,
                    help='decoupled weight decay (AdamW) per unit learning rate; 0 = Adam, as the paper')
    ap.add_argument('--beta-nll', type=float, default=0.0,
                    help='GDN training loss: NLL terms weighted by sigma^(2 beta) (0: the paper\'s NLL)')
    ap.add_argument('--threads', type=int, default=1)
    ap.add_argument('--seed', type=int, default=0)
    ap.add_argument('--out', required=True, help='run directory (checkpoints, history)')
    ap.add_argument('--data', default=None, help='data dir with train/ and val/ (default: '
                    'LIESERVO_DATA, else ../shared/data/tactip from the repo root)')
    ap.add_argument('--deadline', default=None,
                    help='HH:MM UTC; do not start an epoch that would end after it')
    ap.add_argument('--max-batches', type=int, default=None, help='(timing) batches per epoch')
    ap.add_argument('--export', default=None, help='write ONNX here at the end')
    args = ap.parse_args(argv)
    args.session_list = [v for v in args.sessions.split(',') if v]
    sessions = args.session_list
    if not sessions or len(set(sessions)) != len(sessions) or any(v not in ('train', 'val') for v in sessions):
        raise SystemExit(f'--sessions {args.sessions}: a list of distinct splits from train, val')
    if not (0.0 <= args.beta_nll <= 1.0) or (args.beta_nll and args.model != 'gdn'):
        raise SystemExit(f'--beta-nll {args.beta_nll}: a GDN option between 0 and 1')
    if 'val' in sessions and not args.holdout:
        raise SystemExit('--sessions with val needs --holdout N: the held-out rows are the monitored set')
    return args


def training_sets(args, data):
    """(Xtr, Ytr, Xva, Yva, monitor): the trained-on sessions less their held-out rows, and the
    monitored set (val, or the held-out rows of every session when val is trained on)."""
    sessions = args.session_list

    def xy(split):
        s = load_split(data, split)
        y = L.to_train_units(L.xi_from_euler6(s.euler6)).astype(np.float32)
        return torch.from_numpy(s.images), torch.from_numpy(y)

    parts, held_parts = [], []
    for split in sessions:
        X, Y = xy(split)
        if args.holdout:
            # Rows are ordered by depth, so the held-out set must be a random choice, not a tail.
            held = holdout_indices(len(X), args.holdout, seed=HOLDOUT_SEEDS[split])
            keep = np.setdiff1d(np.arange(len(X)), held)
            np.savetxt(os.path.join(args.out, holdout_file(split)), held, fmt='%d')
            held_parts.append((X[held], Y[held]))
            X, Y = X[keep], Y[keep]
        parts.append((X, Y))
    Xtr = torch.cat([p[0] for p in parts])
    Ytr = torch.cat([p[1] for p in parts])
    if 'val' in sessions:   # monitor the held-out rows of every session
        Xva = torch.cat([p[0] for p in held_parts])
        Yva = torch.cat([p[1] for p in held_parts])
        return Xtr, Ytr, Xva, Yva, 'held-out rows of ' + '+'.join(sessions)
    Xva, Yva = xy('val')
    return Xtr, Ytr, Xva, Yva, 'val'


def fit_deadline(ep, e_max, ep_times, deadline, args):
    """(stop, e_max): whether the next epoch would end after the deadline, and the schedule's
    end, shortened so that lr still reaches ~1e-7 at the last epoch that fits (never lengthened)."""
    if deadline is None or not ep_times:
        return False, e_max
    est = float(np.mean(ep_times[-3:]))
    if time.time() + est > deadline:
        print(f'stopping before epoch {ep + 1}: deadline {args.deadline} UTC '
              f'(~{est:.0f} s/epoch)', flush=True)
        return True, e_max
    med = float(np.median(ep_times))   # robust to one slow (contended) epoch
    fit = ep + int((deadline - time.time()) // (med * 1.05))
    if fit < e_max and fit >= 4:
        if fit < e_max - 0.5:
            print(f'  deadline: shortening schedule e_max {e_max} -> {fit}', flush=True)
        e_max = float(fit)
    return False, e_max


class Trainer:
    """The model, its optimiser and the shuffling and augmentation streams, seeded from --seed."""

    def __init__(self, args, channels, Xtr, Ytr):
        self.args, self.Xtr, self.Ytr = args, Xtr, Ytr
        self.bn = KERAS_BN if args.bn == 'keras' else TORCH_BN
        self.model = build(args.model, channels, bn=self.bn)
        if args.init == 'keras':
            keras_init_(self.model)
        self.n_par = sum(p.numel() for p in self.model.parameters())
        self.opt = make_optimizer(self.model.parameters(), args.adam_eps, args.weight_decay)
        self.rng = np.random.RandomState(args.seed)
        self.aug = AUGMENT_PRESETS[args.augment]
        self.aug_gen = torch.Generator().manual_seed(args.seed + 1)
        self.alpha = torch.tensor(CNN_ALPHA_DEG, dtype=torch.float32)
        self.n = len(Xtr)
        self.steps = self.n // args.batch + (1 if self.n % args.batch else 0)
        if args.max_batches:
            self.steps = min(self.steps, args.max_batches)

    def epoch(self, ep, e_max):
        """One epoch over a fresh permutation, lr per step from the schedule: (mean loss, last lr)."""
        args, model, opt, steps = self.args, self.model, self.opt, self.steps
        model.train()
        perm = self.rng.permutation(self.n)
        tot, cnt = 0.0, 0
        for b in range(steps):
            idx = torch.from_numpy(perm[b * args.batch:(b + 1) * args.batch])
            lr = lrpd(ep + b / steps, e_max, lr1=args.lr_max)
            for g in opt.param_groups:
                g['lr'] = lr
            xb = self.Xtr[idx] if self.aug is None else augment(self.Xtr[idx], self.aug, self.aug_gen)
            out = model(xb)
            if args.model == 'cnn':
                loss = weighted_mse(out, self.Ytr[idx], self.alpha)
            else:
                loss = beta_nll(out, self.Ytr[idx], args.beta_nll) if args.beta_nll else gdn_nll(out, self.Ytr[idx])
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
            tot += float(loss) * len(idx)
            cnt += len(idx)
        return tot / cnt, lr

    def checkpoint(self, channels, ep, vloss, vmae):
        return {'state_dict': self.model.state_dict(), 'kind': self.args.model, 'channels': channels,
                'bn': self.bn._asdict(), 'epoch': ep + 1, 'val_loss': vloss, 'val_mae': list(vmae)}


def main(argv=None):
    args = parse_args(argv)
    torch.set_num_threads(args.threads)
    try:
        torch.set_num_interop_threads(1)
    except RuntimeError:
        pass
    torch.manual_seed(args.seed)
    np.random.seed(args.seed)
    channels = tuple(int(c) for c in args.channels.split(','))
    e_max = args.e_max if args.e_max is not None else float(args.epochs)
    deadline = parse_deadline(args.deadline)
    os.makedirs(args.out, exist_ok=True)
    sessions = args.session_list
    Xtr, Ytr, Xva, Yva, monitor = training_sets(args, args.data or default_data_dir())
    t = Trainer(args, channels, Xtr, Ytr)
    bn, n_par = t.bn, t.n_par
    print(f'model={args.model} channels={channels} params={n_par} train={t.n} val={len(Xva)} '
          f'batch={args.batch} steps/epoch={t.steps} e_max={e_max} threads={args.threads} '
          f'seed={args.seed} bn={args.bn}{tuple(bn)} init={args.init} adam_eps={args.adam_eps:g} '
          f'holdout={args.holdout} augment={args.augment} weight_decay={args.weight_decay:g} beta_nll={args.beta_nll:g} sessions={"+".join(sessions)} '
          f'monitor={monitor}', flush=True)

    hist = []
    best = (math.inf, -1)
    best_path = os.path.join(args.out, f'{args.model}_best.pt')
    t_start = time.time()
    ep_times = []
    for ep in range(args.epochs):
        stop, e_max = fit_deadline(ep, e_max, ep_times, deadline, args)
        if stop:
            break
        t0 = time.time()
        train_loss, lr = t.epoch(ep, e_max)
        t_train = time.time() - t0
        vloss, vmae, _ = evaluate(t.model, args.model, Xva, Yva, t.alpha)
        sec = time.time() - t0
        ep_times.append(sec)
        hist.append(dict(epoch=ep + 1, train_loss=train_loss, val_loss=vloss, val_mae=list(vmae),
                         lr=lr, e_max=e_max, seconds=sec, train_seconds=t_train))
        improved = vloss < best[0]
        ck = t.checkpoint(channels, ep, vloss, vmae)
        if improved:
            best = (vloss, ep + 1)
            torch.save(ck, best_path)
        torch.save(ck, os.path.join(args.out, f'{args.model}_last.pt'))
        print(f'ep {ep + 1:3d} train {train_loss:9.4f} val {vloss:9.4f} mae '
              + ' '.join(f'{m:.3f}' for m in vmae)
              + f' lr {lr:.2e} {sec:6.1f}s{" *" if improved else ""}', flush=True)
        with open(os.path.join(args.out, f'{args.model}_history.json'), 'w') as f:
            json.dump(dict(args=history_args(args), channels=channels, params=n_par, history=hist,
                           best_epoch=best[1], best_val_loss=best[0]), f, indent=1)
        if ep + 1 - best[1] >= args.patience:
            print(f'early stop: no improvement for {args.patience} epochs', flush=True)
            break
        if ep + 1 >= e_max:
            print(f'schedule finished (lr reached 1e-7 at e_max={e_max:g})', flush=True)
            break

    # final metrics from the best weights
    ck = torch.load(best_path)
    t.model.load_state_dict(ck['state_dict'])
    vloss, vmae, _ = evaluate(t.model, args.model, Xva, Yva, t.alpha)
    summary = dict(kind=args.model, channels=channels, params=n_par, seed=args.seed,
                   sessions=sessions, monitor=monitor, augment=args.augment, weight_decay=args.weight_decay,
                   beta_nll=args.beta_nll,
                   epochs_run=len(hist), e_max=e_max, best_epoch=best[1],
                   seconds_per_epoch=float(np.mean(ep_times)) if ep_times else None,
                   total_seconds=time.time() - t_start, threads=args.threads,
                   batch=args.batch, bn=bn._asdict(), val_loss=vloss, val_mae=dict(zip(COMP, map(float, vmae))))
    with open(os.path.join(args.out, f'{args.model}_summary.json'), 'w') as f:
        json.dump(summary, f, indent=1)
    print('best:', json.dumps(summary), flush=True)
    if args.export:
        from export_onnx import export_model
        export_model(t.model, args.export)
        print('exported', args.export, flush=True)


def history_args(args):
    """The command line as the history records it (argparse's names only)."""
    return {k: v for k, v in vars(args).items() if k != 'session_list'}


if __name__ == '__main__':
    main()
