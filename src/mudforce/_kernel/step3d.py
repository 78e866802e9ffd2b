"""Speed plumbing only: the compiled 3-D step of many feet (:class:`mudforce.contact3d.MudContacts3D`).

Nothing here is physics. One call places every foot's elements by its pose,
steps every element's paper state with the 1-D stepper
(:func:`~mudforce._kernel.loops.run_feet`, the same compiled function
:class:`mudforce.MudContacts` runs, so the state machine exists once), and
applies the lateral law through the scalar functions of
:mod:`~mudforce._kernel.element3d` (each :mod:`mudforce.law3d`'s namesake
for one element) and Eq. (4) through
:func:`mudforce.equations.nonlinear_spring_stress`. It follows
:meth:`mudforce.contact3d.MudContact3D.step` line for line, foot by foot,
and differs only in where things are kept:

* the elements of all feet, concatenated foot after foot, are the columns
  of one float64 block (``E_*`` rows: constants, the lateral state, and
  this step's scratch), so that each row is a contiguous array (the 1-D
  stepper takes the depth and stress rows as they are);
* each foot's constants and its ``started`` flag are the columns of a
  second block (``F_*`` rows), and ``starts[f]:starts[f + 1]`` are its
  elements;
* the 1-D states, params and rings are :mod:`~mudforce._kernel.layout`'s
  rows, one per element.

:func:`step_feet` checks every foot's pose, every element's depth and the
step length before anything moves (so a refused step changes nothing),
then steps. It does not use BLAS or numpy's sums, so it does not give
:class:`~mudforce.contact3d.MudContact3D`'s bits (which has its rotations
from BLAS): the two agree to rounding, about 1e-15 of the peak force
(``tests/contact3d/test_many3d.py``); the same foot gives the same bits
here whatever the other feet are.
"""

from __future__ import annotations

import math

import numpy as np

from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MIN_DT
from mudforce._kernel.element3d import (
    bearing_factor,
    horizontal_drag,
    lateral_capacity,
    lateral_return_map,
    rotation,
    shear_fraction,
    vertical_weight,
)
from mudforce._kernel.layout import _compiled
from mudforce._kernel.loops import run_feet
from mudforce.equations import nonlinear_spring_stress
from mudforce.law3d import QUATERNION_TOLERANCE

__all__ = [
    "BAD_DT",
    "N_ELEMENT_ROWS",
    "N_FOOT_ROWS",
    "OK",
    "step_feet",
]

# rows of the element block: one column per element (all feet's, foot after foot)
E_CBX, E_CBY, E_CBZ = 0, 1, 2  # centroid in the body frame [m]
E_NBX, E_NBY, E_NBZ = 3, 4, 5  # outward unit normal in the body frame [-]
E_AREA = 6  # area [m^2]
E_SLIPX, E_SLIPY = 7, 8  # horizontal elastic slip [m] (state)
E_CX, E_CY, E_CZ = 9, 10, 11  # world centroid at the last step [m] (state)
E_OX, E_OY, E_OZ = 12, 13, 14  # this step: the centroid's offset from the body origin, world frame [m]
E_NX, E_NY, E_NZ = 15, 16, 17  # this step: the world normal [-]
E_WX, E_WY, E_WZ = 18, 19, 20  # this step: the world centroid [m]
E_DEPTH = 21  # this step: depth below the surface [m]
E_STRESS = 22  # this step: the paper's stress [Pa] (the 1-D stepper's force on a unit area)
N_ELEMENT_ROWS = 23
#: the rows a snapshot keeps (the lateral state)
STATE_ROWS = (E_SLIPX, E_SLIPY, E_CX, E_CY, E_CZ)

# rows of the foot block: one column per foot
F_SURFACE = 0  # surface height [m]
F_WIDTH = 1  # H of Eq. (4) [m]
F_STIFFNESS = 2  # lateral stiffness [Pa/m]
F_SIGMA_Y = 3  # yield stress [Pa]
F_ALPHA = 4  # spring coefficient [Pa]
F_BETA = 5  # spring exponent [-]
F_LAMBDA = 6  # drag factor [-]
F_RHO = 7  # mud density [kg/m^3]
F_STARTED = 8  # 1 once the foot has taken its first step
N_FOOT_ROWS = 9

#: :func:`step_feet`'s return values other than a foot's index
OK = -1
BAD_DT = -2


@_compiled()
def _place(positions: np.ndarray, quaternions: np.ndarray, el: np.ndarray, ft: np.ndarray, starts: np.ndarray) -> int:
    """Every element's world offset, normal, centroid and depth into the scratch rows; the first bad foot or -1.

    A foot is bad if its position is not finite, its quaternion not finite
    or farther than :data:`~mudforce.law3d.QUATERNION_TOLERANCE` from unit
    norm, or one of its elements would be deeper (or higher) than
    ``MAX_DEPTH``. Writes only scratch rows.
    """
    for f in range(positions.shape[0]):
        px, py, pz = positions[f, 0], positions[f, 1], positions[f, 2]
        qw, qx, qy, qz = quaternions[f, 0], quaternions[f, 1], quaternions[f, 2], quaternions[f, 3]
        # |x| < inf is False for NaN and inf alike
        if not ((abs(px) < math.inf) & (abs(py) < math.inf) & (abs(pz) < math.inf) & (abs(qw) < math.inf)
                & (abs(qx) < math.inf) & (abs(qy) < math.inf) & (abs(qz) < math.inf)):
            return f
        norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        if not abs(norm - 1.0) <= QUATERNION_TOLERANCE:
            return f
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = rotation(qw, qx, qy, qz)
        h = ft[F_SURFACE, f]
        bad = False
        for i in range(starts[f], starts[f + 1]):
            bx, by, bz = el[E_CBX, i], el[E_CBY, i], el[E_CBZ, i]
            ox = r00 * bx + r01 * by + r02 * bz
            oy = r10 * bx + r11 * by + r12 * bz
            oz = r20 * bx + r21 * by + r22 * bz
            nx, ny, nz = el[E_NBX, i], el[E_NBY, i], el[E_NBZ, i]
            el[E_OX, i] = ox
            el[E_OY, i] = oy
            el[E_OZ, i] = oz
            el[E_NX, i] = r00 * nx + r01 * ny + r02 * nz
            el[E_NY, i] = r10 * nx + r11 * ny + r12 * nz
            el[E_NZ, i] = r20 * nx + r21 * ny + r22 * nz
            el[E_WX, i] = px + ox
            el[E_WY, i] = py + oy
            cz = pz + oz
            el[E_WZ, i] = cz
            depth = h - cz
            el[E_DEPTH, i] = depth
            bad |= not abs(depth) <= MAX_DEPTH
        if bad:
            return f
    return OK


@_compiled(inline="always")
def _lateral(el: np.ndarray, ft: np.ndarray, f: int, lo: int, hi: int, dt: float, forces: np.ndarray,
             torques: np.ndarray) -> None:
    """Foot ``f``'s elements ``lo:hi`` after the 1-D step: the lateral law, the wrench, the new lateral state.

    :meth:`mudforce.contact3d.MudContact3D.step` from the paper's stress on,
    one element at a time.
    """
    started = ft[F_STARTED, f] != 0.0
    moving = False  # MudContact3D's ``trial.any()``
    if started:
        for i in range(lo, hi):
            if el[E_DEPTH, i] > 0.0:
                tx = el[E_SLIPX, i] + (el[E_WX, i] - el[E_CX, i])
                ty = el[E_SLIPY, i] + (el[E_WY, i] - el[E_CY, i])
                moving |= (tx != 0.0) | (ty != 0.0)
    k = ft[F_STIFFNESS, f]
    sigma_y = ft[F_SIGMA_Y, f]
    alpha = ft[F_ALPHA, f]
    beta = ft[F_BETA, f]
    width = ft[F_WIDTH, f]
    lambda_ = ft[F_LAMBDA, f]
    rho = ft[F_RHO, f]
    sfx = sfy = sfz = 0.0
    stx = sty = stz = 0.0
    for i in range(lo, hi):
        area = el[E_AREA, i]
        nx, ny, nz = el[E_NX, i], el[E_NY, i], el[E_NZ, i]
        fz = el[E_STRESS, i] * area * vertical_weight(nz)
        fx = fy = 0.0
        slip_x = slip_y = 0.0
        if moving:
            depth = el[E_DEPTH, i]
            below = depth > 0.0
            mx = el[E_WX, i] - el[E_CX, i]
            my = el[E_WY, i] - el[E_CY, i]
            tx = ty = 0.0
            if below:
                tx = el[E_SLIPX, i] + mx
                ty = el[E_SLIPY, i] + my
            size = math.sqrt(tx * tx + ty * ty)
            unit = size if size > 0.0 else 1.0
            dx = tx / unit
            dy = ty / unit
            capacity = lateral_capacity(sigma_y, shear_fraction(nx, ny, nz, dx, dy),
                                        nonlinear_spring_stress(alpha, beta, depth, width),
                                        bearing_factor(nx, ny, nz, dx, dy))
            slip_x, slip_y, ax, ay = lateral_return_map(tx, ty, k, capacity)
            if below:
                gx, gy = horizontal_drag(lambda_, rho, nx, ny, mx / dt, my / dt)
                ax += gx
                ay += gy
            else:
                ax += 0.0
                ay += 0.0
            fx = ax * area
            fy = ay * area
        el[E_SLIPX, i] = slip_x
        el[E_SLIPY, i] = slip_y
        el[E_CX, i] = el[E_WX, i]
        el[E_CY, i] = el[E_WY, i]
        el[E_CZ, i] = el[E_WZ, i]
        ox, oy, oz = el[E_OX, i], el[E_OY, i], el[E_OZ, i]
        sfx += fx
        sfy += fy
        sfz += fz
        stx += oy * fz - oz * fy
        sty += oz * fx - ox * fz
        stz += ox * fy - oy * fx
    forces[f, 0] = sfx
    forces[f, 1] = sfy
    forces[f, 2] = sfz
    torques[f, 0] = stx
    torques[f, 1] = sty
    torques[f, 2] = stz
    ft[F_STARTED, f] = 1.0


@_compiled()
def step_feet(positions: np.ndarray, quaternions: np.ndarray, dt: float, el: np.ndarray, ft: np.ndarray,
              starts: np.ndarray, states: np.ndarray, ring: np.ndarray, params: np.ndarray, scratch: np.ndarray,
              index: np.ndarray, forces: np.ndarray, torques: np.ndarray) -> int:
    """One step of every foot: the wrench of foot ``f`` [N], [N m] into ``forces[f]`` and ``torques[f]``.

    ``positions`` (m, 3) [m] and ``quaternions`` (m, 4) ``(w, x, y, z)``
    are the feet's poses, ``dt`` [s] the time since the last step (ignored
    if no foot has started). ``states``, ``ring`` and ``params`` are the
    1-D stepper's rows, one per element; ``scratch`` and ``index`` the
    spring pass's (:func:`~mudforce._kernel.loops.new_spring_scratch` for
    all elements). Returns :data:`OK`; or, having changed nothing, the
    first foot whose pose or depth is refused (see :func:`_place`), or
    :data:`BAD_DT` for a ``dt`` outside [``MIN_DT``, ``MAX_DT``] once a
    foot has started.
    """
    m = positions.shape[0]
    any_started = False
    for f in range(m):
        any_started |= ft[F_STARTED, f] != 0.0
    if any_started:
        if not MIN_DT <= dt <= MAX_DT:  # False for NaN
            return BAD_DT
    else:
        dt = 1.0  # ignored by every element's first step, as MudContact3D passes it
    bad = _place(positions, quaternions, el, ft, starts)
    if bad != OK:
        return bad
    refused = run_feet(states, ring, params, el[E_DEPTH], dt, el[E_STRESS], scratch, index)
    if refused >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
        return refused
    for f in range(m):
        _lateral(el, ft, f, starts[f], starts[f + 1], dt, forces, torques)
    return OK
