"""CNN-regression and GDN pose-and-shear models (Lloyd & Lepora, sec. "cnn_model"/"gdn_model"),
written so that the exported ONNX graph loads in OpenCV 4.6 cv2.dnn:
torch.flatten(x, 1), torch.cat for the heads, no Where/Clip/Min/Max-with-constant ops,
softplus written as relu(z) + log(1 + exp(-|z|)).
"""
from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import torch
import torch.nn as nn

P_MU = (0.7, 0.7, 0.1, 0.0, 0.0, 0.4)          # paper: dropout on the mu heads
P_SIGMA_INV = (0.1, 0.1, 0.0, 0.0, 0.0, 0.05)  # paper: dropout on the sigma^-1 heads
SIGMA_INV_MIN = 1e-6
SIGMA_INV_MAX = 1e6
# Paper CNN loss weights (1,1,1,100,100,100) assume rotations in RADIANS. We train with
# rotations in degrees, so the equivalent weights (same loss value) are 100 * (pi/180)^2.
CNN_ALPHA_RAD = (1.0, 1.0, 1.0, 100.0, 100.0, 100.0)
CNN_ALPHA_DEG = tuple(a if i < 3 else a * (math.pi / 180.0) ** 2 for i, a in enumerate(CNN_ALPHA_RAD))


class BatchNormOptions(NamedTuple):
    """BatchNorm eps and running-statistics momentum (PyTorch meaning: weight of the new batch)."""
    eps: float
    momentum: float


TORCH_BN = BatchNormOptions(eps=1e-5, momentum=0.1)
# The paper trained with TensorFlow 2.4 / Keras, whose BatchNormalization defaults are
# epsilon = 1e-3 and momentum = 0.99 (weight of the OLD average), i.e. PyTorch momentum 0.01:
# the evaluation statistics average ~100 batches instead of ~10.
KERAS_BN = BatchNormOptions(eps=1e-3, momentum=0.01)


def stable_softplus(z: torch.Tensor) -> torch.Tensor:
    """log(1 + exp(z)) = relu(z) + log(1 + exp(-|z|)); never overflows."""
    return torch.relu(z) + torch.log(1.0 + torch.exp(-torch.abs(z)))


def softbound(x: torch.Tensor, xmin: float = SIGMA_INV_MIN, xmax: float = SIGMA_INV_MAX) -> torch.Tensor:
    """Paper eq. 6 (eqn:softbound_def): xmin + softplus(x - xmin) - softplus(x - xmax)."""
    return xmin + stable_softplus(x - xmin) - stable_softplus(x - xmax)


class ConvBase(nn.Module):
    """Blocks of [3x3 conv (pad 1) -> BatchNorm -> ReLU -> 2x2 maxpool], doubling channels."""

    def __init__(self, channels: Sequence[int] = (16, 32, 64, 128, 256), in_ch: int = 1,
                 bn: BatchNormOptions = TORCH_BN):
        super().__init__()
        layers = []
        c = in_ch
        for k in channels:
            layers += [nn.Conv2d(c, k, 3, padding=1),
                       nn.BatchNorm2d(k, eps=bn.eps, momentum=bn.momentum), nn.ReLU(inplace=False),
                       nn.MaxPool2d(2)]
            c = k
        self.body = nn.Sequential(*layers)
        self.out_channels = c

    def forward(self, x):
        return self.body(x)


def n_features(channels: Sequence[int], size: int = 128) -> int:
    return channels[-1] * (size >> len(channels)) ** 2


class CNNRegression(nn.Module):
    def __init__(self, channels=(16, 32, 64, 128, 256), size: int = 128, p: float = 0.1,
                 bn: BatchNormOptions = TORCH_BN):
        super().__init__()
        self.base = ConvBase(channels, bn=bn)
        self.drop = nn.Dropout(p)
        self.fc = nn.Linear(n_features(channels, size), 6)

    def forward(self, x):
        return self.fc(self.drop(torch.flatten(self.base(x), 1)))


class GDN(nn.Module):
    """Output [N, 12] = (mu_1..6, sigma^-1_1..6); 12 single-output heads, each with its own
    dropout (multi-dropout), sigma^-1 through softbound into [1e-6, 1e6]."""

    def __init__(self, channels=(16, 32, 64, 128, 256), size: int = 128,
                 p_mu=P_MU, p_sigma_inv=P_SIGMA_INV, bn: BatchNormOptions = TORCH_BN):
        super().__init__()
        self.base = ConvBase(channels, bn=bn)
        F = n_features(channels, size)
        self.mu_drop = nn.ModuleList([nn.Dropout(p) for p in p_mu])
        self.mu_fc = nn.ModuleList([nn.Linear(F, 1) for _ in p_mu])
        self.si_drop = nn.ModuleList([nn.Dropout(p) for p in p_sigma_inv])
        self.si_fc = nn.ModuleList([nn.Linear(F, 1) for _ in p_sigma_inv])

    def forward(self, x):
        h = torch.flatten(self.base(x), 1)
        mu = torch.cat([fc(d(h)) for d, fc in zip(self.mu_drop, self.mu_fc)], dim=1)
        si = torch.cat([fc(d(h)) for d, fc in zip(self.si_drop, self.si_fc)], dim=1)
        return torch.cat([mu, softbound(si)], dim=1)


def gdn_nll(out: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    """Paper eq. 5 (eqn:gdn_mean_nll_loss_def) without the constant c:
    mean_i sum_j [ 0.5 (s_ij (y_ij - mu_ij))^2 - ln s_ij ]."""
    mu, s = out[:, :6], out[:, 6:]
    return (0.5 * (s * (y - mu)) ** 2 - torch.log(s)).sum(dim=1).mean()


def beta_nll(out: torch.Tensor, y: torch.Tensor, beta: float) -> torch.Tensor:
    """The NLL of gdn_nll with each term weighted by sigma^(2 beta), the weight held constant in
    the gradient (Seitzer et al. 2022, "On the pitfalls of heteroscedastic uncertainty
    estimation"). The plain NLL pulls a mean by (y - mu) / sigma^2, so the images whose sigma is
    large (shallow contacts) barely train the mean; beta = 1 gives every mean the squared-error
    gradient, beta = 0 is gdn_nll."""
    mu, s = out[:, :6], out[:, 6:]
    w = s.detach() ** (-2.0 * beta)
    return (w * (0.5 * (s * (y - mu)) ** 2 - torch.log(s))).sum(dim=1).mean()


def weighted_mse(out: torch.Tensor, y: torch.Tensor, alpha: torch.Tensor) -> torch.Tensor:
    """Paper eq. 3 (eqn:mse_loss_def): mean_i sum_j alpha_j (y_ij - xi_ij)^2."""
    return (alpha * (y - out) ** 2).sum(dim=1).mean()


def keras_init_(model: nn.Module) -> nn.Module:
    """Re-initialise like Keras (the paper's framework): Glorot-uniform kernels and zero biases for
    every Conv2d and Linear layer (PyTorch's default is Kaiming-uniform(a=sqrt 5) with random
    biases). BatchNorm keeps gamma = 1, beta = 0 in both frameworks."""
    for m in model.modules():
        if isinstance(m, (nn.Conv2d, nn.Linear)):
            nn.init.xavier_uniform_(m.weight)
            nn.init.zeros_(m.bias)
    return model


def build(kind: str, channels=(16, 32, 64, 128, 256), size: int = 128,
          bn: BatchNormOptions = TORCH_BN) -> nn.Module:
    if kind == 'gdn':
        return GDN(channels, size, bn=bn)
    if kind == 'cnn':
        return CNNRegression(channels, size, bn=bn)
    raise ValueError(f'unknown model kind {kind!r}')
