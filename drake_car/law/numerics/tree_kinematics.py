"""Forward kinematics of a tree of joints, compiled with numba: the pose and spatial velocity in
world of each body from the generalized positions and velocities. No Drake here: the tree
comes as rows (``pack_joint``) in the conventions of Drake's joints (``systems.tyre`` packs a
MultibodyPlant's paths to the wheels and checks the result against the plant's own kinematics).

Why: reading the poses and velocities of a few bodies from a MultibodyPlant in Python costs two
list-valued port reads of every body, each converted to Python objects, every step; the state
vector is one cheap read and the kinematics of a dozen bodies costs about a microsecond
compiled. Everything compiled lives in this one module (numba's on-disk cache follows the file
holding a function only).

Per joint, from its parent body P to its child body C, with its frame F fixed on P and M fixed
on C: X_WC = X_WP X_PF X_FM(q) X_MC. X_FM(q) and the joint's velocities v:
  weld: identity (its fixed X_FM is folded into X_PF);
  revolute: rotation by q about the unit axis a (in F = M), w_FM = a v;
  prismatic: translation q along the unit axis a, v_FM = a v;
  universal: R_FM = R_x(q0) R_y(q1), w_FM = v0 F_x + v1 R_x(q0) F_y;
  quaternion_floating: q = [w, x, y, z, p_FM], R_FM from the quaternion (normalized as
  Drake does), v = [w_FM, v_FM] expressed in F.
"""

import enum
import math

import numba
import numpy as np

JOINT_TYPES = ("weld", "revolute", "prismatic", "universal", "quaternion_floating")
J = enum.IntEnum("J", {name: i for i, name in enumerate((
    "PARENT", "TYPE", "Q", "V", "AXIS_X", "AXIS_Y", "AXIS_Z",
    "PF_00", "PF_01", "PF_02", "PF_X", "PF_10", "PF_11", "PF_12", "PF_Y",
    "PF_20", "PF_21", "PF_22", "PF_Z",
    "MC_00", "MC_01", "MC_02", "MC_X", "MC_10", "MC_11", "MC_12", "MC_Y",
    "MC_20", "MC_21", "MC_22", "MC_Z"))})


def pack_joint(parent, joint_type, q_start, v_start, X_PF, X_MC, axis=(0.0, 0.0, 0.0)):
    """One body's row: ``parent`` the row of its parent body (-1: world; parents come first),
    its inboard joint's type (``JOINT_TYPES``), its entries in q and v, the fixed poses X_PF and
    X_MC as 3 x 4 arrays [R | p], the unit axis of a revolute or prismatic joint."""
    row = np.zeros(len(J))
    row[J.PARENT], row[J.TYPE] = parent, JOINT_TYPES.index(joint_type)
    row[J.Q], row[J.V] = q_start, v_start
    row[J.AXIS_X:J.AXIS_Z + 1] = axis
    row[J.PF_00:J.PF_Z + 1] = np.asarray(X_PF, dtype=float).ravel()
    row[J.MC_00:J.MC_Z + 1] = np.asarray(X_MC, dtype=float).ravel()
    return row


_jit = numba.njit(cache=True)


@_jit
def _compose(a, b, out):
    """out = a b for 3 x 4 poses [R | p]."""
    for i in range(3):
        for j in range(3):
            out[i, j] = a[i, 0] * b[0, j] + a[i, 1] * b[1, j] + a[i, 2] * b[2, j]
        out[i, 3] = a[i, 0] * b[0, 3] + a[i, 1] * b[1, 3] + a[i, 2] * b[2, 3] + a[i, 3]


@_jit
def _joint_pose(row, q, out):
    """X_FM(q) into ``out``."""
    out[:, :] = 0.0
    kind = int(row[J.TYPE])
    if kind == 0:
        out[0, 0] = out[1, 1] = out[2, 2] = 1.0
    elif kind == 1:  # Rodrigues: R = I cos + sin [a]x + (1 - cos) a a^T
        ax, ay, az = row[J.AXIS_X], row[J.AXIS_Y], row[J.AXIS_Z]
        theta = q[int(row[J.Q])]
        c, s = math.cos(theta), math.sin(theta)
        t = 1.0 - c
        out[0, 0], out[0, 1], out[0, 2] = (c + t * ax * ax, t * ax * ay - s * az,
                                           t * ax * az + s * ay)
        out[1, 0], out[1, 1], out[1, 2] = (t * ax * ay + s * az, c + t * ay * ay,
                                           t * ay * az - s * ax)
        out[2, 0], out[2, 1], out[2, 2] = (t * ax * az - s * ay, t * ay * az + s * ax,
                                           c + t * az * az)
    elif kind == 2:
        d = q[int(row[J.Q])]
        out[0, 0] = out[1, 1] = out[2, 2] = 1.0
        out[0, 3], out[1, 3], out[2, 3] = row[J.AXIS_X] * d, row[J.AXIS_Y] * d, row[J.AXIS_Z] * d
    elif kind == 3:  # R_x(q0) R_y(q1)
        i = int(row[J.Q])
        c0, s0, c1, s1 = math.cos(q[i]), math.sin(q[i]), math.cos(q[i + 1]), math.sin(q[i + 1])
        out[0, 0], out[0, 1], out[0, 2] = c1, 0.0, s1
        out[1, 0], out[1, 1], out[1, 2] = s0 * s1, c0, -s0 * c1
        out[2, 0], out[2, 1], out[2, 2] = -c0 * s1, s0, c0 * c1
    else:
        i = int(row[J.Q])
        w, x, y, z = q[i], q[i + 1], q[i + 2], q[i + 3]
        s = 2.0 / (w * w + x * x + y * y + z * z)
        out[0, 0], out[0, 1], out[0, 2] = (1.0 - s * (y * y + z * z), s * (x * y - w * z),
                                           s * (x * z + w * y))
        out[1, 0], out[1, 1], out[1, 2] = (s * (x * y + w * z), 1.0 - s * (x * x + z * z),
                                           s * (y * z - w * x))
        out[2, 0], out[2, 1], out[2, 2] = (s * (x * z - w * y), s * (y * z + w * x),
                                           1.0 - s * (x * x + y * y))
        out[0, 3], out[1, 3], out[2, 3] = q[i + 4], q[i + 5], q[i + 6]


@_jit
def _joint_velocity(row, q, v):
    """(w_FM, v_FM) expressed in F."""
    kind = int(row[J.TYPE])
    a = (row[J.AXIS_X], row[J.AXIS_Y], row[J.AXIS_Z])
    zero = (0.0, 0.0, 0.0)
    if kind == 1:
        rate = v[int(row[J.V])]
        return (a[0] * rate, a[1] * rate, a[2] * rate), zero
    if kind == 2:
        rate = v[int(row[J.V])]
        return zero, (a[0] * rate, a[1] * rate, a[2] * rate)
    if kind == 3:
        i, k = int(row[J.Q]), int(row[J.V])
        c0, s0 = math.cos(q[i]), math.sin(q[i])
        return (v[k], c0 * v[k + 1], s0 * v[k + 1]), zero
    if kind == 4:
        k = int(row[J.V])
        return (v[k], v[k + 1], v[k + 2]), (v[k + 3], v[k + 4], v[k + 5])
    return zero, zero


@_jit
def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@_jit
def _rotate(pose, u):
    return (pose[0, 0] * u[0] + pose[0, 1] * u[1] + pose[0, 2] * u[2],
            pose[1, 0] * u[0] + pose[1, 1] * u[1] + pose[1, 2] * u[2],
            pose[2, 0] * u[0] + pose[2, 1] * u[1] + pose[2, 2] * u[2])


@_jit
def tree_kinematics(tree, x, nq, poses, twists):
    """Poses (n x 3 x 4, [R | p] of each row's body in world) and twists (n x 6, [w; v] of its
    origin, in world) of the bodies of ``tree`` (rows of ``pack_joint``) at the state
    ``x`` = [q; v] (``nq`` positions), written into ``poses`` and ``twists``."""
    q, v = x[:nq], x[nq:]
    x_wf = np.empty((3, 4))
    x_fm = np.empty((3, 4))
    x_wm = np.empty((3, 4))
    pf = np.empty((3, 4))
    mc = np.empty((3, 4))
    for b in range(tree.shape[0]):
        row = tree[b]
        parent = int(row[J.PARENT])
        pf[:, :] = row[J.PF_00:J.PF_Z + 1].reshape(3, 4)
        mc[:, :] = row[J.MC_00:J.MC_Z + 1].reshape(3, 4)
        if parent < 0:
            x_wf[:, :] = pf
            w_p = (0.0, 0.0, 0.0)
            v_p = (0.0, 0.0, 0.0)
            p_p = (0.0, 0.0, 0.0)
        else:
            _compose(poses[parent], pf, x_wf)
            w_p = (twists[parent, 0], twists[parent, 1], twists[parent, 2])
            v_p = (twists[parent, 3], twists[parent, 4], twists[parent, 5])
            p_p = (poses[parent, 0, 3], poses[parent, 1, 3], poses[parent, 2, 3])
        _joint_pose(row, q, x_fm)
        _compose(x_wf, x_fm, x_wm)
        _compose(x_wm, mc, poses[b])
        # Velocities: F moves with P; M moves relative to F by the joint's velocities.
        p_f = (x_wf[0, 3], x_wf[1, 3], x_wf[2, 3])
        p_m = (x_wm[0, 3], x_wm[1, 3], x_wm[2, 3])
        p_c = (poses[b, 0, 3], poses[b, 1, 3], poses[b, 2, 3])
        w_fm, v_fm = _joint_velocity(row, q, v)
        w_fm_w, v_fm_w = _rotate(x_wf, w_fm), _rotate(x_wf, v_fm)
        r = _cross(w_p, (p_f[0] - p_p[0], p_f[1] - p_p[1], p_f[2] - p_p[2]))
        v_f = (v_p[0] + r[0], v_p[1] + r[1], v_p[2] + r[2])
        r = _cross(w_p, (p_m[0] - p_f[0], p_m[1] - p_f[1], p_m[2] - p_f[2]))
        v_m = (v_f[0] + r[0] + v_fm_w[0], v_f[1] + r[1] + v_fm_w[1], v_f[2] + r[2] + v_fm_w[2])
        w_c = (w_p[0] + w_fm_w[0], w_p[1] + w_fm_w[1], w_p[2] + w_fm_w[2])
        r = _cross(w_c, (p_c[0] - p_m[0], p_c[1] - p_m[1], p_c[2] - p_m[2]))
        twists[b, 0], twists[b, 1], twists[b, 2] = w_c
        twists[b, 3], twists[b, 4], twists[b, 5] = v_m[0] + r[0], v_m[1] + r[1], v_m[2] + r[2]
