"""Pose-and-shear training labels (paper sec. "Pre- and post-processing"), in numpy.

    X_fs = [R | t],  R = Rz(gamma) Ry(beta) Rx(alpha)  (extrinsic xyz Euler, "sxyz"),
                     t = (x, y, z),
    with (x, y, z, alpha, beta, gamma) = (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz)
    X_sf = X_fs^-1
    xi   = log(X_sf)^vee = [rho; phi]   (translation first)
           phi = log(R_sf)^vee (axis-angle, radians), rho = V(phi)^-1 t_sf (mm),
           V = left Jacobian of SO(3).

Units: the functions here work in mm and radians. The networks are trained on
xi_train = (rho [mm], phi [deg]) -- see to_train_units / from_train_units and the model card.
"""
from __future__ import annotations

import numpy as np

DEG = np.pi / 180.0


def hat3(w: np.ndarray) -> np.ndarray:
    """[..., 3] -> [..., 3, 3] skew-symmetric."""
    w = np.asarray(w, dtype=np.float64)
    O = np.zeros(w.shape[:-1] + (3, 3))
    O[..., 0, 1] = -w[..., 2]; O[..., 0, 2] = w[..., 1]
    O[..., 1, 0] = w[..., 2];  O[..., 1, 2] = -w[..., 0]
    O[..., 2, 0] = -w[..., 1]; O[..., 2, 1] = w[..., 0]
    return O


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    R = np.zeros(np.shape(a) + (3, 3)); R[..., 0, 0] = 1
    R[..., 1, 1] = c; R[..., 1, 2] = -s; R[..., 2, 1] = s; R[..., 2, 2] = c
    return R


def rot_y(b):
    c, s = np.cos(b), np.sin(b)
    R = np.zeros(np.shape(b) + (3, 3)); R[..., 1, 1] = 1
    R[..., 0, 0] = c; R[..., 0, 2] = s; R[..., 2, 0] = -s; R[..., 2, 2] = c
    return R


def rot_z(g):
    c, s = np.cos(g), np.sin(g)
    R = np.zeros(np.shape(g) + (3, 3)); R[..., 2, 2] = 1
    R[..., 0, 0] = c; R[..., 0, 1] = -s; R[..., 1, 0] = s; R[..., 1, 1] = c
    return R


def euler_sxyz_to_matrix(e6_mm_deg: np.ndarray) -> np.ndarray:
    """[..., 6] (x, y, z [mm], alpha, beta, gamma [deg], extrinsic xyz) -> [..., 4, 4]."""
    e = np.asarray(e6_mm_deg, dtype=np.float64)
    a, b, g = e[..., 3] * DEG, e[..., 4] * DEG, e[..., 5] * DEG
    T = np.zeros(e.shape[:-1] + (4, 4))
    T[..., :3, :3] = rot_z(g) @ rot_y(b) @ rot_x(a)
    T[..., :3, 3] = e[..., :3]
    T[..., 3, 3] = 1.0
    return T


def se3_inv(T: np.ndarray) -> np.ndarray:
    R = T[..., :3, :3]; t = T[..., :3, 3]
    Ri = np.swapaxes(R, -1, -2)
    out = np.zeros_like(T)
    out[..., :3, :3] = Ri
    out[..., :3, 3] = -np.einsum('...ij,...j->...i', Ri, t)
    out[..., 3, 3] = 1.0
    return out


def so3_log(R: np.ndarray) -> np.ndarray:
    """[..., 3, 3] -> [..., 3] axis-angle (radians). Robust for small angles (series) and
    for angles near pi (uses the symmetric part)."""
    R = np.asarray(R, dtype=np.float64)
    w = 0.5 * np.stack([R[..., 2, 1] - R[..., 1, 2],
                        R[..., 0, 2] - R[..., 2, 0],
                        R[..., 1, 0] - R[..., 0, 1]], axis=-1)      # sin(th) * axis
    s = np.linalg.norm(w, axis=-1)
    c = 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0)
    th = np.arctan2(s, c)
    small = th < 1e-4
    # th / sin(th) ~ 1 + th^2/6 + 7 th^4/360
    with np.errstate(divide='ignore', invalid='ignore'):
        f = np.where(small, 1.0 + th * th / 6.0 + 7.0 * th ** 4 / 360.0, th / np.where(small, 1.0, s))
    phi = f[..., None] * w
    near_pi = c < -0.99
    if np.any(near_pi):
        Rp = R[near_pi]; thp = th[near_pi]
        B = 0.5 * (Rp + np.swapaxes(Rp, -1, -2)) - np.eye(3) * c[near_pi][:, None, None]
        # B = (1 - cos th) a a^T
        k = np.argmax(np.stack([B[:, 0, 0], B[:, 1, 1], B[:, 2, 2]], -1), -1)
        a = B[np.arange(len(k)), k, :]
        a = a / np.linalg.norm(a, axis=-1, keepdims=True)
        sign = np.sign(np.einsum('ij,ij->i', a, w[near_pi]))
        sign[sign == 0] = 1.0
        phi[near_pi] = a * (sign * thp)[:, None]
    return phi


def so3_exp(phi: np.ndarray) -> np.ndarray:
    phi = np.asarray(phi, dtype=np.float64)
    th = np.linalg.norm(phi, axis=-1)
    small = th < 1e-4
    ts = np.where(small, 1.0, th)
    A = np.where(small, 1 - th ** 2 / 6 + th ** 4 / 120, np.sin(ts) / ts)
    B = np.where(small, 0.5 - th ** 2 / 24 + th ** 4 / 720, (1 - np.cos(ts)) / ts ** 2)
    P = hat3(phi)
    return np.eye(3) + A[..., None, None] * P + B[..., None, None] * (P @ P)


def so3_left_jacobian(phi: np.ndarray) -> np.ndarray:
    phi = np.asarray(phi, dtype=np.float64)
    th = np.linalg.norm(phi, axis=-1)
    small = th < 1e-4
    ts = np.where(small, 1.0, th)
    B = np.where(small, 0.5 - th ** 2 / 24 + th ** 4 / 720, (1 - np.cos(ts)) / ts ** 2)
    C = np.where(small, 1.0 / 6 - th ** 2 / 120 + th ** 4 / 5040, (ts - np.sin(ts)) / ts ** 3)
    P = hat3(phi)
    return np.eye(3) + B[..., None, None] * P + C[..., None, None] * (P @ P)


def so3_left_jacobian_inv(phi: np.ndarray) -> np.ndarray:
    """V^-1 = I - 1/2 P + D P^2, D = 1/th^2 - (1 + cos th) / (2 th sin th)."""
    phi = np.asarray(phi, dtype=np.float64)
    th = np.linalg.norm(phi, axis=-1)
    small = th < 1e-3
    ts = np.where(small, 1.0, th)
    D = np.where(small, 1.0 / 12 + th ** 2 / 720 + th ** 4 / 30240,
                 1.0 / ts ** 2 - (1 + np.cos(ts)) / (2 * ts * np.sin(ts)))
    P = hat3(phi)
    return np.eye(3) - 0.5 * P + D[..., None, None] * (P @ P)


def se3_log(T: np.ndarray) -> np.ndarray:
    """[..., 4, 4] -> [..., 6] = [rho; phi] (translation first)."""
    phi = so3_log(T[..., :3, :3])
    rho = np.einsum('...ij,...j->...i', so3_left_jacobian_inv(phi), T[..., :3, 3])
    return np.concatenate([rho, phi], axis=-1)


def se3_exp(xi: np.ndarray) -> np.ndarray:
    xi = np.asarray(xi, dtype=np.float64)
    T = np.zeros(xi.shape[:-1] + (4, 4))
    T[..., :3, :3] = so3_exp(xi[..., 3:])
    T[..., :3, 3] = np.einsum('...ij,...j->...i', so3_left_jacobian(xi[..., 3:]), xi[..., :3])
    T[..., 3, 3] = 1.0
    return T


def xi_from_euler6(e6_mm_deg: np.ndarray) -> np.ndarray:
    """Labels xi = log(X_fs^-1)^vee in mm and RADIANS, [..., 6]."""
    return se3_log(se3_inv(euler_sxyz_to_matrix(e6_mm_deg)))


# ---- training units: rho in mm, phi in degrees ---------------------------------------
def to_train_units(xi_mm_rad: np.ndarray) -> np.ndarray:
    out = np.array(xi_mm_rad, dtype=np.float64, copy=True)
    out[..., 3:] /= DEG
    return out


def from_train_units(xi_mm_deg: np.ndarray) -> np.ndarray:
    out = np.array(xi_mm_deg, dtype=np.float64, copy=True)
    out[..., 3:] *= DEG
    return out


def write_reference_csv(path: str, names, xi_mm_rad: np.ndarray, euler6=None):
    """image name, (optionally the Euler 6-vector), xi (mm, rad) with 17 significant digits."""
    with open(path, 'w') as f:
        cols = ['sensor_image']
        if euler6 is not None:
            cols += ['x_mm', 'y_mm', 'z_mm', 'alpha_deg', 'beta_deg', 'gamma_deg']
        cols += ['rho1_mm', 'rho2_mm', 'rho3_mm', 'phi1_rad', 'phi2_rad', 'phi3_rad']
        f.write(','.join(cols) + '\n')
        for i, n in enumerate(names):
            vals = ([] if euler6 is None else list(euler6[i])) + list(xi_mm_rad[i])
            f.write(n + ',' + ','.join('%.17g' % v for v in vals) + '\n')


if __name__ == '__main__':
    import os, sys
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from dataset import default_data_dir, read_targets, euler6_from_targets
    d = default_data_dir()
    names, t = read_targets(os.path.join(d, 'val', 'targets.csv'))
    e6 = euler6_from_targets(t)[:20]
    xi = xi_from_euler6(e6)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'labels_reference.csv')
    write_reference_csv(out, names[:20], xi, e6)
    print('wrote', out)
