"""Reader for the TacTip pose-and-shear data set (dexterousrobot/tactile_data_shear,
franka_tactip_1/surface_3d) as laid out in the shared data's README (../shared/data/tactip/README.md from the
repository root).

    split_dir/
      processed_images/image_N.png   8-bit binarised images, 445 x 440
      targets.csv                    sensor_image, pose_*, shear_* (mm, degrees, sxyz Euler)
      *.json                         parameter files (may contain Infinity; env_params.json
                                     in the public data is malformed)

Pre-processing (paper, sec. "Pre- and post-processing"): resize the 8-bit image to
128 x 128 with cv2.INTER_AREA (on the uint8 image, result rounded to uint8, exactly what
OpenCV does on the C++ side), then scale to [0, 1] as float32 (x / 255).

Preprocessed images are cached as uint8 .npy files in the system's temporary folder
(never in the repository),
so later runs load in about a second.

Usage:
    from dataset import load_split
    s = load_split(default_data_dir(), 'val')
    s.images   # float32 [N, 1, 128, 128] in [0, 1]
    s.targets  # dict column -> float64 [N]
    s.euler6   # float64 [N, 6] = (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz), mm/deg
"""
from __future__ import annotations

import csv
import hashlib
import json
import os
import sys
import tempfile
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

IMAGE_SIZE = 128
TARGET_COLUMNS = ['pose_x', 'pose_y', 'pose_z', 'pose_Rx', 'pose_Ry', 'pose_Rz',
                  'shear_x', 'shear_y', 'shear_z', 'shear_Rx', 'shear_Ry', 'shear_Rz']
CACHE_DIR = os.environ.get('LIESERVO_CACHE', os.path.join(tempfile.gettempdir(), 'lieservo_gdn_cache'))


class DatasetError(RuntimeError):
    """Clear, user-facing error about a data file (names the path)."""


def default_data_dir() -> str:
    """LIESERVO_DATA, else <repo>/../shared/data/tactip (returned even when absent: the
    readers then name the missing path)."""
    env = os.environ.get('LIESERVO_DATA')
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    repo = os.path.abspath(os.path.join(here, '..', '..'))
    cand = os.path.abspath(os.path.join(repo, '..', 'shared', 'data', 'tactip'))
    return cand


def read_json(path: str):
    """Read a JSON parameter file. Accepts Infinity/-Infinity/NaN (Python json does).
    A missing or malformed file raises DatasetError naming the file, line and column."""
    if not os.path.isfile(path):
        raise DatasetError(f'missing JSON file: {path}')
    with open(path, 'r', encoding='utf-8') as f:
        text = f.read()
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        lines = text.splitlines() or ['']
        line = lines[e.lineno - 1] if 0 < e.lineno <= len(lines) else ''
        snippet = line[max(0, e.colno - 30):e.colno + 10]
        raise DatasetError(
            f'malformed JSON in {path}: line {e.lineno}, column {e.colno} '
            f'(char {e.pos}): {e.msg}; near ...{snippet!r}') from e


def read_json_params(split_dir: str, names=('collect_params.json', 'meta.json',
                                            'processed_image_params.json', 'env_params.json'),
                     strict: bool = False) -> Dict[str, object]:
    """Read the parameter files of a split. With strict=False a malformed/missing file is
    reported on stderr (clear message) and mapped to None; strict=True re-raises."""
    out = {}
    for n in names:
        try:
            out[n] = read_json(os.path.join(split_dir, n))
        except DatasetError as e:
            if strict:
                raise
            print(f'warning: {e}', file=sys.stderr)
            out[n] = None
    return out


def read_targets(path: str):
    """Read targets.csv -> (image names list, dict column -> float64 array)."""
    if not os.path.isfile(path):
        raise DatasetError(f'missing targets file: {path}')
    names: List[str] = []
    cols: Dict[str, List[float]] = {c: [] for c in TARGET_COLUMNS}
    with open(path, newline='') as f:
        reader = csv.DictReader(f)
        if reader.fieldnames is None:
            raise DatasetError(f'empty targets file: {path}')
        header = [h.strip() for h in reader.fieldnames]
        missing = [c for c in ['sensor_image'] + TARGET_COLUMNS if c not in header]
        if missing:
            raise DatasetError(f'{path}: missing columns {missing} (header: {header})')
        for lineno, row in enumerate(reader, start=2):
            row = {k.strip(): v for k, v in row.items() if k is not None}
            names.append(row['sensor_image'].strip())
            for c in TARGET_COLUMNS:
                try:
                    cols[c].append(float(row[c]))
                except (TypeError, ValueError):
                    raise DatasetError(f'{path}: line {lineno}: bad value {row[c]!r} '
                                       f'in column {c}') from None
    return names, {c: np.asarray(v, dtype=np.float64) for c, v in cols.items()}


def euler6_from_targets(t: Dict[str, np.ndarray]) -> np.ndarray:
    """(x, y, z, alpha, beta, gamma) = (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz),
    mm and degrees (README: X_fs = X_par * X_perp)."""
    return np.stack([t['shear_x'], t['shear_y'], t['pose_z'],
                     t['pose_Rx'], t['pose_Ry'], t['shear_Rz']], axis=1)


def preprocess_image(img_u8: np.ndarray, size: int = IMAGE_SIZE) -> np.ndarray:
    """uint8 grayscale HxW -> uint8 size x size via cv2.INTER_AREA (the paper's resize).
    Divide by 255 afterwards for the network input."""
    import cv2
    if img_u8.ndim == 3:
        img_u8 = cv2.cvtColor(img_u8, cv2.COLOR_BGR2GRAY)
    return cv2.resize(img_u8, (size, size), interpolation=cv2.INTER_AREA)


def load_image(path: str, size: int = IMAGE_SIZE) -> np.ndarray:
    import cv2
    if not os.path.isfile(path):
        raise DatasetError(f'missing image file: {path}')
    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    if img is None:
        raise DatasetError(f'could not decode image file: {path}')
    return preprocess_image(img, size)


def to_input(img_u8: np.ndarray) -> np.ndarray:
    """uint8 [..., H, W] -> float32 in [0, 1]."""
    return img_u8.astype(np.float32) / np.float32(255.0)


@dataclass
class Split:
    split_dir: str
    names: List[str]
    targets: Dict[str, np.ndarray]
    images_u8: np.ndarray            # uint8 [N, 128, 128]
    params: Dict[str, object] = field(default_factory=dict)

    @property
    def images(self) -> np.ndarray:  # float32 [N, 1, 128, 128] in [0, 1]
        return to_input(self.images_u8)[:, None, :, :]

    @property
    def euler6(self) -> np.ndarray:
        return euler6_from_targets(self.targets)

    def __len__(self):
        return len(self.names)


def _cache_path(split_dir: str, names: List[str], size: int) -> str:
    h = hashlib.sha1()
    h.update(os.path.abspath(split_dir).encode())
    h.update(str(size).encode())
    h.update('\n'.join(names).encode())
    return os.path.join(CACHE_DIR, f'{os.path.basename(os.path.normpath(split_dir))}_'
                                   f'{size}_{h.hexdigest()[:12]}.npy')


def load_split(data_dir: Optional[str], split: str, size: int = IMAGE_SIZE,
               use_cache: bool = True, read_params: bool = True,
               limit: Optional[int] = None, verbose: bool = True) -> Split:
    """Load one split ('train' or 'val'). The JSON parameter files are read tolerantly
    (a malformed env_params.json only gives a warning; training does not need it)."""
    data_dir = data_dir or default_data_dir()
    split_dir = os.path.join(data_dir, split)
    if not os.path.isdir(split_dir):
        raise DatasetError(f'missing split directory: {split_dir}')
    names, targets = read_targets(os.path.join(split_dir, 'targets.csv'))
    if limit is not None:
        names = names[:limit]
        targets = {k: v[:limit] for k, v in targets.items()}
    params = read_json_params(split_dir) if read_params else {}
    img_dir = os.path.join(split_dir, 'processed_images')
    cpath = _cache_path(split_dir, names, size)
    imgs = None
    if use_cache and os.path.isfile(cpath):
        try:
            imgs = np.load(cpath)
            if imgs.shape != (len(names), size, size) or imgs.dtype != np.uint8:
                imgs = None
        except Exception:  # corrupt cache: rebuild
            imgs = None
    if imgs is None:
        if verbose:
            print(f'preprocessing {len(names)} images from {img_dir} ...', flush=True)
        imgs = np.empty((len(names), size, size), dtype=np.uint8)
        for i, n in enumerate(names):
            imgs[i] = load_image(os.path.join(img_dir, n), size)
        if use_cache:
            os.makedirs(CACHE_DIR, exist_ok=True)
            tmp = cpath + f'.tmp{os.getpid()}.npy'
            np.save(tmp, imgs)
            os.replace(tmp, cpath)
            if verbose:
                print(f'cached -> {cpath}', flush=True)
    return Split(split_dir, names, targets, imgs, params)


if __name__ == '__main__':
    import argparse
    ap = argparse.ArgumentParser(description='Check/cache the TacTip data set.')
    ap.add_argument('--data', default=None)
    args = ap.parse_args()
    for sp in ('train', 'val'):
        s = load_split(args.data, sp)
        print(sp, len(s), s.images_u8.shape, 'mean pixel', float(s.images_u8.mean()) / 255,
              'params ok:', {k: v is not None for k, v in s.params.items()})
