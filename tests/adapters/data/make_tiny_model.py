#!/usr/bin/python3
"""Generate the tiny ONNX test models used by tests/adapters (committed, < 50 kB).

    /usr/bin/python3 tests/adapters/data/make_tiny_model.py

Writes, next to this script:
  tiny_gdn.onnx   [N,1,128,128] -> [N,12] = (mu_1..6, sigma^-1_1..6), same layer types as the
                  project's GDN (conv3x3/BN/ReLU/maxpool blocks, flatten, 12 single-output
                  linear heads, softbound on sigma^-1), but 2 channels per block: random weights.
  tiny_cnn.onnx   [N,1,128,128] -> [N,6]
  tiny_model_card.json   in the project's model-card layout (units mm and deg)
  tiny_reference.csv     PyTorch outputs for the synthetic inputs below (%.9g)

Synthetic input k (k = 0, 1, 2), float32, 128 x 128:
  x_k[i, j] = (0.4 + 0.3 k) ((i * (7 + k) + j * 13 + 3 * k) mod 17) / 16
The C++ test builds the same images and compares cv::dnn against these numbers.
Export rules for OpenCV 4.6 cv::dnn: opset 13, torch.flatten, no Where/Clip/Min/Max.
"""
import hashlib
import json
import os

import numpy as np
import torch
import torch.nn as nn

HERE = os.path.dirname(os.path.abspath(__file__))
CH = (2, 2, 2, 2, 2)
SIZE = 128


def softplus(z):
    return torch.relu(z) + torch.log(1.0 + torch.exp(-torch.abs(z)))


def softbound(x, lo=1e-6, hi=1e6):
    return lo + softplus(x - lo) - softplus(x - hi)


class Base(nn.Module):
    def __init__(self):
        super().__init__()
        layers, c = [], 1
        for k in CH:
            layers += [nn.Conv2d(c, k, 3, padding=1), nn.BatchNorm2d(k), nn.ReLU(), nn.MaxPool2d(2)]
            c = k
        self.body = nn.Sequential(*layers)

    def forward(self, x):
        return torch.flatten(self.body(x), 1)


FEATURES = CH[-1] * (SIZE >> len(CH)) ** 2


class TinyGDN(nn.Module):
    def __init__(self):
        super().__init__()
        self.base = Base()
        self.mu = nn.ModuleList([nn.Linear(FEATURES, 1) for _ in range(6)])
        self.si = nn.ModuleList([nn.Linear(FEATURES, 1) for _ in range(6)])

    def forward(self, x):
        h = self.base(x)
        mu = torch.cat([f(h) for f in self.mu], dim=1)
        si = torch.cat([f(h) for f in self.si], dim=1)
        return torch.cat([mu, softbound(si)], dim=1)


class TinyCNN(nn.Module):
    def __init__(self):
        super().__init__()
        self.base = Base()
        self.fc = nn.Linear(FEATURES, 6)

    def forward(self, x):
        return self.fc(self.base(x))


def randomise_bn(model, gen):
    for m in model.modules():
        if isinstance(m, nn.BatchNorm2d):
            m.running_mean.copy_(0.1 * torch.randn(m.num_features, generator=gen))
            m.running_var.copy_(0.5 + torch.rand(m.num_features, generator=gen))
            m.weight.data.copy_(1.0 + 0.2 * torch.randn(m.num_features, generator=gen))
            m.bias.data.copy_(0.1 * torch.randn(m.num_features, generator=gen))


def synthetic(k):
    i = np.arange(SIZE)[:, None]
    j = np.arange(SIZE)[None, :]
    return ((0.4 + 0.3 * k) * (((i * (7 + k) + j * 13 + 3 * k) % 17) / 16.0)).astype(np.float32)


def export(model, path):
    model.eval()
    torch.onnx.export(model, torch.zeros(1, 1, SIZE, SIZE), path, opset_version=13,
                      input_names=['input'], output_names=['output'],
                      dynamic_axes={'input': {0: 'N'}, 'output': {0: 'N'}}, do_constant_folding=True)
    try:
        import onnx
        ops = sorted({n.op_type for n in onnx.load(path).graph.node})
        bad = {'Where', 'Clip', 'Min', 'Max', 'Softplus', 'Identity'} & set(ops)
        if bad:
            raise RuntimeError(f'{path}: ops OpenCV 4.6 cannot run: {sorted(bad)}')
    except ImportError:
        pass


def main():
    torch.manual_seed(1234)
    gen = torch.Generator().manual_seed(99)
    gdn, cnn = TinyGDN(), TinyCNN()
    with torch.no_grad():
        for m in (gdn, cnn):
            randomise_bn(m, gen)
        # Heads: scale up so the outputs are O(1) and sigma^-1 is clearly positive.
        for f in gdn.mu:
            f.weight.mul_(20.0)
        for f in gdn.si:
            f.weight.mul_(5.0)
            f.bias.add_(2.0)
        cnn.fc.weight.mul_(20.0)
    export(gdn, os.path.join(HERE, 'tiny_gdn.onnx'))
    export(cnn, os.path.join(HERE, 'tiny_cnn.onnx'))

    x = np.stack([synthetic(k) for k in range(3)])[:, None]
    with torch.no_grad():
        yg = gdn.eval()(torch.from_numpy(x)).numpy()
        yc = cnn.eval()(torch.from_numpy(x)).numpy()
    with open(os.path.join(HERE, 'tiny_reference.csv'), 'w') as f:
        f.write('model,input,' + ','.join(f'out{j}' for j in range(12)) + '\n')
        for k in range(3):
            f.write('gdn,%d,' % k + ','.join('%.9g' % v for v in yg[k]) + '\n')
        for k in range(3):
            f.write('cnn,%d,' % k + ','.join('%.9g' % v for v in yc[k]) + '\n')

    def sha256(name):  # checked by the C++ loader
        with open(os.path.join(HERE, name), 'rb') as f:
            return hashlib.sha256(f.read()).hexdigest()

    card = {
        'name': 'tiny random test models (NOT trained) for tests/adapters',
        'models': {
            'gdn': {'file': 'tiny_gdn.onnx', 'sha256': sha256('tiny_gdn.onnx'),
                    'input': {'name': 'input', 'shape': ['N', 1, SIZE, SIZE], 'dtype': 'float32'},
                    'output': {'name': 'output', 'shape': ['N', 12],
                               'units': 'mu: mm, mm, mm, deg, deg, deg; sigma_inv: 1/mm x3, 1/deg x3'}},
            'cnn': {'file': 'tiny_cnn.onnx', 'sha256': sha256('tiny_cnn.onnx'),
                    'input': {'name': 'input', 'shape': ['N', 1, SIZE, SIZE], 'dtype': 'float32'},
                    'output': {'name': 'output', 'shape': ['N', 6], 'units': 'mm, mm, mm, deg, deg, deg'}},
        },
    }
    with open(os.path.join(HERE, 'tiny_model_card.json'), 'w') as f:
        json.dump(card, f, indent=1)
    for n in ('tiny_gdn.onnx', 'tiny_cnn.onnx'):
        print(n, os.path.getsize(os.path.join(HERE, n)), 'bytes')


if __name__ == '__main__':
    main()
