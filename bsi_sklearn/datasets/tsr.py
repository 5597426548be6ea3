"""Task-space regions (Berenson et al., 2011): pose constraints in SE(3)."""

from __future__ import annotations

import numpy as np
from sklearn.utils import check_random_state

__all__ = ["TaskSpaceRegion", "make_pose", "rpy_to_matrix", "matrix_to_rpy"]

_TWO_PI = 2.0 * np.pi
_BOUND_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")


def rpy_to_matrix(roll, pitch, yaw):
    """Rotation matrices ``Rz(yaw) @ Ry(pitch) @ Rx(roll)`` (fixed-axis roll, pitch, yaw).

    Parameters
    ----------
    roll, pitch, yaw : float or array-like
        Angles in radians; arrays broadcast together.

    Returns
    -------
    R : ndarray of shape (..., 3, 3)

    Examples
    --------
    >>> import numpy as np
    >>> np.round(rpy_to_matrix(0.0, 0.0, np.pi / 2), 6) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    r, p, y = np.broadcast_arrays(
        np.asarray(roll, float), np.asarray(pitch, float), np.asarray(yaw, float)
    )
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    R = np.empty(r.shape + (3, 3))
    R[..., 0, 0] = cy * cp
    R[..., 0, 1] = cy * sp * sr - sy * cr
    R[..., 0, 2] = cy * sp * cr + sy * sr
    R[..., 1, 0] = sy * cp
    R[..., 1, 1] = sy * sp * sr + cy * cr
    R[..., 1, 2] = sy * sp * cr - cy * sr
    R[..., 2, 0] = -sp
    R[..., 2, 1] = cp * sr
    R[..., 2, 2] = cp * cr
    return R


def matrix_to_rpy(R):
    """Roll, pitch, yaw of rotation matrices, with pitch in ``[-pi/2, pi/2]``.

    The inverse of :func:`rpy_to_matrix` away from gimbal lock (``|pitch| = pi/2``), where
    roll is set to 0 and only ``roll - yaw`` (``roll + yaw``) is determined.

    Parameters
    ----------
    R : array-like of shape (..., 3, 3)

    Returns
    -------
    rpy : ndarray of shape (..., 3)

    Examples
    --------
    >>> import numpy as np
    >>> np.round(matrix_to_rpy(rpy_to_matrix(0.1, -0.2, 3.0)), 6)
    array([ 0.1, -0.2,  3. ])
    """
    R = np.asarray(R, float)
    s = np.clip(-R[..., 2, 0], -1.0, 1.0)
    pitch = np.arcsin(s)
    roll = np.arctan2(R[..., 2, 1], R[..., 2, 2])
    yaw = np.arctan2(R[..., 1, 0], R[..., 0, 0])
    lock = np.abs(s) > 1.0 - 1e-12
    if np.any(lock):
        # pitch = +pi/2: R depends on roll - yaw; pitch = -pi/2: on roll + yaw.
        c = np.arctan2(R[..., 0, 1], R[..., 1, 1])
        c_neg = np.arctan2(-R[..., 0, 1], R[..., 1, 1])
        roll = np.where(lock, 0.0, roll)
        yaw = np.where(lock, np.where(s > 0, -c, c_neg), yaw)
    return np.stack([roll, pitch, yaw], axis=-1)


def make_pose(xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)):
    """Homogeneous transforms from translations and roll-pitch-yaw angles.

    Parameters
    ----------
    xyz : array-like of shape (..., 3), default=(0, 0, 0)
    rpy : array-like of shape (..., 3), default=(0, 0, 0)
        Roll, pitch, yaw in radians (see :func:`rpy_to_matrix`).

    Returns
    -------
    pose : ndarray of shape (..., 4, 4)

    Examples
    --------
    >>> make_pose([1.0, 2.0, 3.0])[:3, 3]
    array([1., 2., 3.])
    """
    xyz = np.asarray(xyz, float)
    rpy = np.asarray(rpy, float)
    if xyz.shape[-1:] != (3,) or rpy.shape[-1:] != (3,):
        raise ValueError("xyz and rpy must have a last dimension of size 3")
    shape = np.broadcast_shapes(xyz.shape[:-1], rpy.shape[:-1])
    T = np.zeros(shape + (4, 4))
    T[..., :3, :3] = rpy_to_matrix(rpy[..., 0], rpy[..., 1], rpy[..., 2])
    T[..., :3, 3] = xyz
    T[..., 3, 3] = 1.0
    return T


def _inverse(T):
    Ti = np.zeros_like(T)
    Rt = np.swapaxes(T[..., :3, :3], -1, -2)
    Ti[..., :3, :3] = Rt
    Ti[..., :3, 3] = -np.einsum("...ij,...j->...i", Rt, T[..., :3, 3])
    Ti[..., 3, 3] = 1.0
    return Ti


def _check_pose(T, name, allow_batch=True, atol=1e-6):
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a numeric array of 4x4 poses") from None
    if T.ndim < 2 or T.shape[-2:] != (4, 4) or (not allow_batch and T.ndim != 2):
        shape = "(4, 4)" if not allow_batch else "(..., 4, 4)"
        raise ValueError(f"{name} must have shape {shape}, got {T.shape}")
    if not np.all(np.isfinite(T)):
        raise ValueError(f"{name} has non-finite values")
    if not np.allclose(T[..., 3, :], [0.0, 0.0, 0.0, 1.0], atol=atol):
        raise ValueError(f"{name} is not homogeneous: its last row must be [0, 0, 0, 1]")
    R = T[..., :3, :3]
    RtR = np.einsum("...ki,...kj->...ij", R, R)
    if not np.allclose(RtR, np.eye(3), atol=atol) or np.any(np.linalg.det(R) < 0):
        raise ValueError(f"{name} has a rotation block that is not a proper rotation")
    return T


def _angle_in(angle, lo, hi, atol):
    """Whether ``angle`` lies in ``[lo, hi]`` modulo 2*pi (bounds may wrap around)."""
    width = hi - lo
    if width >= _TWO_PI - atol:
        return np.ones(np.shape(angle), dtype=bool)
    d = np.mod(angle - lo, _TWO_PI)
    return (d <= width + atol) | (d >= _TWO_PI - atol)


class TaskSpaceRegion:
    """A task-space region: a frame and bounds on the displacement from it.

    Following Berenson, Srinivasa and Kuffner (2011), a pose ``T`` (object or end-effector
    in the world frame) is inside the region when its displacement in the TSR frame,
    ``D = inv(T0_w) @ T @ inv(Tw_e)``, has a translation ``(x, y, z)`` and roll-pitch-yaw
    angles (``R = Rz(yaw) Ry(pitch) Rx(roll)``) within the bounds ``Bw``.

    Angle bounds are read modulo 2*pi, so ``[pi - 0.1, pi + 0.1]`` contains a yaw of
    ``-pi + 0.05``; a bound of width 2*pi or more leaves that angle free. Since a rotation
    has two roll-pitch-yaw representations (``(r, p, y)`` and ``(r + pi, pi - p, y + pi)``),
    a pose is inside when either lies within the bounds; at gimbal lock
    (``|pitch| = pi/2``) every admissible split of ``roll -/+ yaw`` is considered. Bounds
    are closed, up to ``atol``.

    Parameters
    ----------
    T0_w : array-like of shape (4, 4), default=None
        Pose of the TSR frame in the world frame (identity when None).
    Bw : array-like of shape (6, 2), default=None
        ``[min, max]`` rows for x, y, z (world units) and roll, pitch, yaw (radians).
        ``None`` is the single pose ``T0_w`` (all bounds zero). Infinite translation bounds
        are allowed.
    Tw_e : array-like of shape (4, 4), default=None
        Offset of the constrained frame (end effector, object) in the TSR frame (identity
        when None).
    atol : float, default=1e-9
        Tolerance at the bounds.

    Attributes
    ----------
    T0_w, Bw, Tw_e : ndarray
        Read-only copies of the parameters.

    References
    ----------
    D. Berenson, S. Srinivasa, J. Kuffner, "Task Space Regions: A framework for
    pose-constrained manipulation planning", IJRR 30(12), 2011.

    Examples
    --------
    >>> import numpy as np
    >>> tsr = TaskSpaceRegion(
    ...     T0_w=make_pose([1.0, 0.0, 0.0]),
    ...     Bw=[[-0.1, 0.1], [-0.1, 0.1], [0, 0.05], [0, 0], [0, 0], [-np.pi, np.pi]],
    ... )
    >>> bool(tsr.contains(make_pose([1.05, 0.0, 0.02], [0.0, 0.0, 2.0])))
    True
    >>> tsr.contains(make_pose([[1.0, 0.0, 0.0], [1.2, 0.0, 0.0]]))
    array([ True, False])
    """

    def __init__(self, T0_w=None, Bw=None, Tw_e=None, *, atol=1e-9):
        T0_w = np.eye(4) if T0_w is None else _check_pose(T0_w, "T0_w", allow_batch=False)
        Tw_e = np.eye(4) if Tw_e is None else _check_pose(Tw_e, "Tw_e", allow_batch=False)
        if Bw is None:
            Bw = np.zeros((6, 2))
        try:
            Bw = np.array(Bw, dtype=float)
        except (TypeError, ValueError):
            raise ValueError("Bw must be a numeric (6, 2) array of [min, max] bounds") from None
        if Bw.shape != (6, 2):
            raise ValueError(f"Bw must have shape (6, 2), got {Bw.shape}")
        if np.any(np.isnan(Bw)) or np.any(np.isinf(Bw[3:])):
            raise ValueError("Bw has NaN values or infinite angle bounds")
        for k, name in enumerate(_BOUND_NAMES):
            if Bw[k, 0] > Bw[k, 1]:
                raise ValueError(f"Bw row {k} ({name}) has min {Bw[k, 0]} > max {Bw[k, 1]}")
        if not (np.isscalar(atol) and np.isfinite(atol) and atol >= 0):
            raise ValueError(f"atol must be a non-negative number, got {atol!r}")
        for arr in (T0_w, Bw, Tw_e):
            arr.setflags(write=False)
        self.T0_w, self.Bw, self.Tw_e, self.atol = T0_w, Bw, Tw_e, float(atol)
        self._T0_w_inv = _inverse(T0_w)
        self._Tw_e_inv = _inverse(Tw_e)

    def __repr__(self):
        return (
            f"TaskSpaceRegion(origin={np.round(self.T0_w[:3, 3], 4).tolist()}, "
            f"Bw={np.round(self.Bw, 4).tolist()})"
        )

    def displacement(self, pose):
        """Displacement ``inv(T0_w) @ pose @ inv(Tw_e)`` as ``(x, y, z, roll, pitch, yaw)``.

        Parameters
        ----------
        pose : array-like of shape (..., 4, 4)
            Homogeneous poses in the world frame.

        Returns
        -------
        d : ndarray of shape (..., 6)
            Pitch in ``[-pi/2, pi/2]``, roll and yaw in ``(-pi, pi]``.
        """
        D = self._relative(_check_pose(pose, "pose"))
        return np.concatenate([D[..., :3, 3], matrix_to_rpy(D[..., :3, :3])], axis=-1)

    def _relative(self, T):
        return self._T0_w_inv @ T @ self._Tw_e_inv

    def contains(self, pose):
        """Whether poses lie inside the region.

        Parameters
        ----------
        pose : array-like of shape (4, 4) or (..., 4, 4)
            Homogeneous poses in the world frame.

        Returns
        -------
        inside : bool or ndarray of bool of shape (...)
        """
        T = _check_pose(pose, "pose")
        D = self._relative(T)
        B, atol = self.Bw, self.atol
        inside = np.ones(D.shape[:-2], dtype=bool)
        for k in range(3):
            v = D[..., k, 3]
            inside &= (v >= B[k, 0] - atol) & (v <= B[k, 1] + atol)
        R = D[..., :3, :3]
        s = np.clip(-R[..., 2, 0], -1.0, 1.0)
        p1 = np.arcsin(s)
        r1 = np.arctan2(R[..., 2, 1], R[..., 2, 2])
        y1 = np.arctan2(R[..., 1, 0], R[..., 0, 0])

        def ok(r, p, y):
            return (
                _angle_in(r, B[3, 0], B[3, 1], atol)
                & _angle_in(p, B[4, 0], B[4, 1], atol)
                & _angle_in(y, B[5, 0], B[5, 1], atol)
            )

        rot_ok = ok(r1, p1, y1) | ok(r1 + np.pi, np.pi - p1, y1 + np.pi)
        lock = np.abs(s) > 1.0 - 1e-9
        if np.any(lock):
            rot_ok = np.where(lock, self._gimbal_ok(R, s), rot_ok)
        inside &= rot_ok
        return bool(inside) if inside.ndim == 0 else inside

    def _gimbal_ok(self, R, s):
        """Rotation test at pitch = +-pi/2, where only roll -+ yaw is determined."""
        B, atol = self.Bw, self.atol
        up = s > 0
        pitch = np.where(up, np.pi / 2, -np.pi / 2)
        pitch_ok = _angle_in(pitch, B[4, 0], B[4, 1], atol)
        # the other representation of pitch +-pi/2 is the same angle: nothing more to try
        free = (B[3, 1] - B[3, 0] >= _TWO_PI - atol) | (B[5, 1] - B[5, 0] >= _TWO_PI - atol)
        c_up = np.arctan2(R[..., 0, 1], R[..., 1, 1])  # roll - yaw
        c_dn = np.arctan2(-R[..., 0, 1], R[..., 1, 1])  # roll + yaw
        lo_up, hi_up = B[3, 0] - B[5, 1], B[3, 1] - B[5, 0]
        lo_dn, hi_dn = B[3, 0] + B[5, 0], B[3, 1] + B[5, 1]
        combo = np.where(
            up, _angle_in(c_up, lo_up, hi_up, atol), _angle_in(c_dn, lo_dn, hi_dn, atol)
        )
        return pitch_ok & (free | combo)

    def sample(self, n=None, random_state=None):
        """Draw poses uniformly in the bounds (translation and roll-pitch-yaw).

        Parameters
        ----------
        n : int, default=None
            Number of poses; ``None`` returns a single ``(4, 4)`` pose.
        random_state : int, RandomState instance or None, default=None

        Returns
        -------
        poses : ndarray of shape (4, 4) or (n, 4, 4)
            World-frame poses, every one inside the region.
        """
        if not np.all(np.isfinite(self.Bw[:3])):
            raise ValueError("cannot sample a TSR with infinite translation bounds (Bw)")
        if n is not None and (isinstance(n, bool) or not isinstance(n, (int, np.integer))
                              or n < 1):
            raise ValueError(f"n must be a positive integer or None, got {n!r}")
        rng = check_random_state(random_state)
        lo = self.Bw[:, 0].copy()
        hi = self.Bw[:, 1].copy()
        hi[3:] = np.minimum(hi[3:], lo[3:] + _TWO_PI)
        size = (1 if n is None else int(n), 6)
        d = lo + (hi - lo) * rng.random_sample(size)
        poses = self.T0_w @ make_pose(d[:, :3], d[:, 3:]) @ self.Tw_e
        return poses[0] if n is None else poses
