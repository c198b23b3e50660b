"""Image augmentation that mimics a change of recording session (train.py --augment).

Between sessions a TacTip is re-mounted and re-lit: the marker pattern sits a little shifted,
turned and scaled in the camera image, and the binarisation threshold and focus differ, so the
marker blobs are a little larger or smaller and sharper or softer. The contact itself, and so
the label, is unchanged. Each training image therefore gets, independently:

* a small similarity transform about the image centre: shift, rotation, scale;
* a gamma on the grey levels (the 128 x 128 images are area-averaged binary images, so
  x -> x^gamma grows (gamma < 1) or shrinks (gamma > 1) the blobs, as a threshold change does);
* with probability `p_blur`, a Gaussian blur.

The strength is one named preset per level so that a run's command records it exactly.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import torch
import torch.nn.functional as F


class AugmentOptions(NamedTuple):
    shift_px: float      # max |shift| per axis, pixels of the 128 x 128 input
    rot_deg: float       # max |rotation|
    scale: float         # max |scale - 1|
    gamma: float         # gamma drawn log-uniformly in [1/gamma, gamma]
    p_blur: float        # probability of a blur
    blur_sigma_px: float  # blur sigma drawn uniformly in [0.3, blur_sigma_px]


PRESETS = {
    'none': None,
    # geometry and grey levels: shift, turn and scale the whole pattern, gamma, blur
    'session': AugmentOptions(shift_px=1.5, rot_deg=1.5, scale=0.03, gamma=1.5, p_blur=0.3,
                              blur_sigma_px=0.8),
    # grey levels only (threshold and focus): the markers stay where they are, so shear and
    # twist, which the network reads from marker displacements, are untouched
    'photometric': AugmentOptions(shift_px=0.0, rot_deg=0.0, scale=0.0, gamma=1.5, p_blur=0.3,
                                  blur_sigma_px=0.8),
}


def _blur(x: torch.Tensor, sigma: torch.Tensor) -> torch.Tensor:
    """Per-image separable Gaussian blur (5 taps) of x [B,1,H,W] with sigma [B] in pixels."""
    b = x.shape[0]
    t = torch.arange(-2, 3, dtype=x.dtype)
    k = torch.exp(-0.5 * (t[None, :] / sigma[:, None]) ** 2)
    k = k / k.sum(1, keepdim=True)                         # [B,5]
    y = x.transpose(0, 1)                                  # [1,B,H,W]: one group per image
    y = F.conv2d(F.pad(y, (2, 2, 0, 0), mode='replicate'), k.view(b, 1, 1, 5), groups=b)
    y = F.conv2d(F.pad(y, (0, 0, 2, 2), mode='replicate'), k.view(b, 1, 5, 1), groups=b)
    return y.transpose(0, 1)


def augment(x: torch.Tensor, opt: AugmentOptions, gen: torch.Generator) -> torch.Tensor:
    """A new batch: x [B,1,H,W] float in [0,1], each image transformed independently."""
    b = x.shape[0]

    def uniform(lo, hi):
        return lo + (hi - lo) * torch.rand(b, generator=gen)

    if opt.shift_px == 0 and opt.rot_deg == 0 and opt.scale == 0:
        y = x
    else:
        y = _similarity(x, opt, uniform)
    g = torch.exp(uniform(-math.log(opt.gamma), math.log(opt.gamma)))
    y = y.clamp(0.0, 1.0).pow(g.view(b, 1, 1, 1))

    if opt.p_blur > 0:
        blur = torch.rand(b, generator=gen) < opt.p_blur
        if bool(blur.any()):
            sig = uniform(0.3, opt.blur_sigma_px)
            y[blur] = _blur(y[blur], sig[blur])
    return y


def _similarity(x: torch.Tensor, opt: AugmentOptions, uniform) -> torch.Tensor:
    """Each image shifted, turned and scaled about its centre (bilinear, zero outside)."""
    _, _, h, w = x.shape
    ang = uniform(-opt.rot_deg, opt.rot_deg) * (math.pi / 180.0)
    s = 1.0 + uniform(-opt.scale, opt.scale)
    # affine_grid maps output coordinates in [-1, 1] to input coordinates: the inverse map.
    c, sn = torch.cos(ang) / s, torch.sin(ang) / s
    tx = uniform(-opt.shift_px, opt.shift_px) * (2.0 / w)
    ty = uniform(-opt.shift_px, opt.shift_px) * (2.0 / h)
    theta = torch.stack([torch.stack([c, -sn, tx], 1), torch.stack([sn, c, ty], 1)], 1)
    grid = F.affine_grid(theta, list(x.shape), align_corners=False)
    return F.grid_sample(x, grid, mode='bilinear', padding_mode='zeros', align_corners=False)
