"""Speed plumbing only: the compiled 3-D step of many feet (:class:`mudforce.steppers.contact3d.MudContacts3D`).

Nothing here is physics. One call places every foot's elements by its pose
(:func:`mudforce.model.law3d.rotation`, :func:`~mudforce.model.law3d.rotate`,
:func:`~mudforce.model.law3d.element_depth`), steps every element's paper state
with the 1-D stepper (:func:`~mudforce._kernel.loops.run_feet`, the same
compiled function :class:`mudforce.MudContacts` runs, so the state machine
exists once), and applies the 3-D law through
:func:`mudforce.model.law3d.element_force` and
:func:`~mudforce.model.law3d.moment`: the very functions
:class:`~mudforce.steppers.contact3d.MudContact3D` and :mod:`mudforce.jax.contact3d`
call on arrays, compiled in here (law3d registers them with numba). Only the
control flow is this module's: an element that carries no horizontal force
(above the surface, or at a foot's first step) takes
:func:`~mudforce.model.law3d.vertical_force` alone, which is what
``element_force`` gives it, without the horizontal law's arithmetic. It
follows :meth:`mudforce.steppers.contact3d.MudContact3D.step` foot by foot, and
differs only in where things are kept:

* the elements of all feet, concatenated foot after foot, are the rows
  of one float64 block (``E_*`` columns: constants and the lateral state),
  an element's values side by side; the world geometry of a step is
  recomputed where it is used from the foot's pose (``F_*`` scratch
  columns), not stored per element (a step of thousands of feet is bound
  by memory traffic, not arithmetic), the depths included (a foot's
  elements are checked against ``MAX_DEPTH`` at once by its reach,
  ``F_REACH``, not one by one). (Not one contiguous row per quantity: rows
  of a few thousand doubles lie a multiple of 4 KiB apart, and the
  processor then stalls loads behind stores to other rows with the same
  low address bits ("4K aliasing"): placing the elements took 80 ns
  each, not 5.)
* each foot's constants and its ``started`` flag are a row of a second
  block (``F_*`` columns), and ``starts[f]:starts[f + 1]`` are its
  elements;
* the 1-D states, params and rings are :mod:`~mudforce._kernel.layout`'s
  rows, one per element.

:func:`step_feet` checks every foot's pose, every element's depth and the
step length before anything moves (so a refused step changes nothing),
then steps. It sums each foot's wrench in another order than
:class:`~mudforce.steppers.contact3d.MudContact3D` (numpy's ``sum(axis=0)``), so the
two agree to rounding, about 1e-15 of the peak force
(``tests/steppers/test_many3d.py``); the same foot gives the same bits
here whatever the other feet are.

:class:`~mudforce.steppers.contact3d.MudContact3D`'s step is this one, for one
foot, with an ``each`` array (:func:`step_feet`): every element's force is
written out and the wrench summed in element order, as its numpy step sums
it, so that the two give the same bits; one compiled step for both classes
(and one compile).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import prange, typeof

from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MAX_HORIZONTAL, MIN_DT
from mudforce._kernel.layout import (
    FREE,
    S_DEPTH,
    S_DIRECTION,
    S_MODE,
    S_MUD,
    S_STARTED,
    S_TIME,
    S_VELOCITY,
    _compiled,
    load_cache,
    load_params,
    load_state,
    store_state,
)
from mudforce._kernel.loops import advance_row
from mudforce._kernel.transitions import exact_rule, quiet_step, stress_parts, total_force
from mudforce.model.equations import nonlinear_spring_stress
from mudforce.model.law3d import (
    QUATERNION_TOLERANCE,
    element_depth,
    element_force,
    moment,
    rotate,
    rotation,
    settle_depth,
    vertical_force,
)

__all__ = [
    "BAD_DT",
    "BAD_SHAPE",
    "N_ELEMENT_COLUMNS",
    "N_FOOT_COLUMNS",
    "OK",
    "block_views",
    "element_forces",
    "fixed_types",
    "lateral_scratch",
    "new_block",
    "step_feet",
    "step_feet_threads",
]

# columns of the element block: one row per element (all feet's, foot after foot)
E_CBX, E_CBY, E_CBZ = 0, 1, 2  # centroid in the body frame [m]
E_NBX, E_NBY, E_NBZ = 3, 4, 5  # outward unit normal in the body frame [-]
E_AREA = 6  # area [m^2]
E_SLIPX, E_SLIPY = 7, 8  # horizontal elastic slip [m] (state)
E_CX, E_CY, E_CZ = 9, 10, 11  # world centroid at the last step [m] (state)
N_ELEMENT_COLUMNS = 12

# columns of the foot block: one row per foot
F_SURFACE = 0  # surface height [m]
F_WIDTH = 1  # H of Eq. (4) [m]
F_STIFFNESS = 2  # lateral stiffness [Pa/m]
F_SIGMA_Y = 3  # yield stress [Pa]
F_ALPHA = 4  # spring coefficient [Pa]
F_BETA = 5  # spring exponent [-]
F_LAMBDA = 6  # drag factor [-]
F_RHO = 7  # mud density [kg/m^3]
F_STARTED = 8  # 1 once the foot has taken its first step
F_PX = 9  # this step: the body origin [m], 3 columns
F_R = 12  # this step: the rotation matrix [-], 9 columns, row by row
F_REACH = 21  # the farthest element centroid from the body origin [m] (a bound for the depth check)
N_FOOT_COLUMNS = 22

#: :func:`step_feet`'s return values other than a foot's index
OK = -1
BAD_DT = -2
BAD_SHAPE = -3


@_compiled(inline="always")
def _pose_ok(px: float, py: float, pz: float, qw: float, qx: float, qy: float, qz: float) -> bool:
    """Whether a pose can be stepped: the position [m] and the quaternion finite, the position's x and y within
    :data:`~mudforce._kernel.bounds.MAX_HORIZONTAL`, and the quaternion within
    :data:`~mudforce.model.law3d.QUATERNION_TOLERANCE` of unit norm (of :func:`_place`)."""
    # |x| <= bound and |x| < inf are False for NaN and inf alike
    if not ((abs(px) <= MAX_HORIZONTAL) & (abs(py) <= MAX_HORIZONTAL) & (abs(pz) < math.inf) & (abs(qw) < math.inf)
            & (abs(qx) < math.inf) & (abs(qy) < math.inf) & (abs(qz) < math.inf)):
        return False
    return abs(math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz) - 1.0) <= QUATERNION_TOLERANCE


@_compiled()
def _place(positions: np.ndarray, quaternions: np.ndarray, el: np.ndarray, ft: np.ndarray, starts: np.ndarray
           ) -> int:
    """Every foot's pose into scratch, every element's depth [m] checked; the first bad foot or -1.

    A foot is bad if its position is not finite, its quaternion not finite
    or farther than :data:`~mudforce.model.law3d.QUATERNION_TOLERANCE` from unit
    norm, or one of its elements would be deeper (or higher) than
    ``MAX_DEPTH``. Writes only scratch (``ft``'s this-step columns).

    Speed plumbing: a foot whose elements are all certainly within bounds (``|h| + |p_z|`` plus its reach
    ``F_REACH`` with a margin of 0.1 %, far above any rounding, within ``MAX_DEPTH``: a rotation keeps
    lengths) is not checked element by element; :func:`_step_foot` computes the depths where it uses them.
    """
    for f in range(positions.shape[0]):
        px, py, pz = positions[f, 0], positions[f, 1], positions[f, 2]
        qw, qx, qy, qz = quaternions[f, 0], quaternions[f, 1], quaternions[f, 2], quaternions[f, 3]
        if not _pose_ok(px, py, pz, qw, qx, qy, qz):
            return f
        r = rotation(qw, qx, qy, qz)
        for j in range(9):
            ft[f, F_R + j] = r[j]
        ft[f, F_PX] = px
        ft[f, F_PX + 1] = py
        ft[f, F_PX + 2] = pz
        h = ft[f, F_SURFACE]
        if abs(h) + abs(pz) + 1.001 * ft[f, F_REACH] < 0.999 * MAX_DEPTH:
            continue
        bad = False
        for i in range(starts[f], starts[f + 1]):
            _, _, oz = rotate(r, el[i, E_CBX], el[i, E_CBY], el[i, E_CBZ])
            bad |= not abs(element_depth(h, pz, oz)) <= MAX_DEPTH
        if bad:
            return f
    return OK


@_compiled(inline="always")
def _foot_rotation(ft: np.ndarray, f: int) -> tuple[float, float, float, float, float, float, float, float, float]:
    """Foot ``f``'s rotation of this step (:func:`_place` put it in ``ft``), row by row: loaded once per foot."""
    return (ft[f, F_R], ft[f, F_R + 1], ft[f, F_R + 2], ft[f, F_R + 3], ft[f, F_R + 4], ft[f, F_R + 5],
            ft[f, F_R + 6], ft[f, F_R + 7], ft[f, F_R + 8])


@_compiled(inline="always")
def _vertical_into(each: np.ndarray, i: int, fz: float) -> None:
    """Element ``i``'s force [N] when it carries its vertical force ``fz`` alone, into ``each[i]`` (MudContact3D's
    element forces)."""
    each[i, 0] = 0.0
    each[i, 1] = 0.0
    each[i, 2] = fz


@_compiled()
def _in_element_order(el: np.ndarray, each: np.ndarray, r: tuple[float, float, float, float, float, float, float,
                                                                  float, float], lo: int, hi: int
                      ) -> tuple[float, float, float, float, float, float]:
    """A foot's wrench, force [N] and torque [N m], summed over its elements ``lo:hi`` as
    :class:`~mudforce.steppers.contact3d.MudContact3D` sums it (numpy's ``sum(axis=0)``: from the first element,
    element after element), from their forces ``each`` and their moments
    (:func:`~mudforce.model.law3d.moment` about the body origin, recomputed from the foot's rotation ``r``: the
    same arguments, the same bits)."""
    if hi <= lo:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    fx, fy, fz = each[lo, 0], each[lo, 1], each[lo, 2]
    ox, oy, oz = rotate(r, el[lo, E_CBX], el[lo, E_CBY], el[lo, E_CBZ])
    tx, ty, tz = moment(ox, oy, oz, fx, fy, fz)
    for i in range(lo + 1, hi):
        ex, ey, ez = each[i, 0], each[i, 1], each[i, 2]
        ox, oy, oz = rotate(r, el[i, E_CBX], el[i, E_CBY], el[i, E_CBZ])
        mx, my, mz = moment(ox, oy, oz, ex, ey, ez)
        fx += ex
        fy += ey
        fz += ez
        tx += mx
        ty += my
        tz += mz
    return fx, fy, fz, tx, ty, tz


# rows of the lateral scratch block (one per slice of feet, :func:`lateral_scratch`): a foot's submerged elements
# side by side, so that the spring and the 3-D law run over them in loops without branches, which the compiler
# vectorises
L_INDEX = 0  # the element's row in the element block (an integer, exact in a double)
L_NX, L_NY, L_NZ = 1, 2, 3  # world normal [-]
L_OX, L_OY, L_OZ = 4, 5, 6  # world offset from the body origin [m]
L_AREA = 7  # [m^2]
L_DEPTH = 8  # [m]
L_STRESS = 9  # the paper's stress [Pa]
L_SPRING = 10  # Eq. (4) at the depth [Pa]
L_SX, L_SY = 11, 12  # the last slip [m]; then the slip kept
L_MX, L_MY = 13, 14  # the horizontal displacement since the last step [m]
L_FX, L_FY, L_FZ = 15, 16, 17  # the element's force [N]
L_FE1, L_FS = 18, 19  # the paper's stresses but the spring's, f_e1 and f_s [Pa] (stress_parts)
L_HAS_SPRING = 20  # 1.0 where the paper's stress has the spring of Eq. (4) (CONTACT, intrusion), else 0.0
N_LATERAL = 21


def lateral_scratch(widest: int, slices: int) -> np.ndarray:
    """The lateral scratch of :func:`step_feet` (``slices`` = 1) or :func:`step_feet_threads`: (slices, N_LATERAL, w).

    ``widest`` the most elements of one foot; the rows are padded so that
    they do not lie a multiple of 4 KiB apart (see the module).
    """
    width = -(-max(widest, 1) // 8) * 8
    if width % 512 == 0:
        width += 8
    return np.zeros((slices, N_LATERAL, width))


# the header of the block (:func:`new_block`): the sizes and where each array starts in it (float64 entries)
H_ELEMENTS, H_FEET, H_SLICES, H_WIDTH = 0, 1, 2, 3
H_EL, H_FT, H_STRESS, H_LAT, H_STARTS = 4, 5, 6, 7, 8
N_HEADER = 16


def new_block(starts: np.ndarray, slices: int) -> np.ndarray:
    """One float64 array holding the compiled step's own arrays for feet whose elements are ``starts[f]:starts[f
    + 1]``: the element block (``E_*`` columns), the foot block (``F_*``), the elements' stresses [Pa], the
    lateral scratch (:func:`lateral_scratch`, ``slices`` slices) and the starts, after a header of their sizes and
    offsets; all zero but the starts. :func:`block_views` gives them as arrays.

    Speed plumbing: :func:`step_feet` takes them as one argument, not five (numba's dispatcher costs ~0.05-0.1
    us an array argument); the 1-D rows stay arrays of their own (``MudContacts``' in ``MudContact3D``).
    """
    starts = np.asarray(starts, dtype=np.int64)
    m = starts.shape[0] - 1
    n = int(starts[-1])
    widest = int(np.diff(starts).max(initial=0))
    width = lateral_scratch(widest, 1).shape[2]
    sizes = (n * N_ELEMENT_COLUMNS, m * N_FOOT_COLUMNS, n, slices * N_LATERAL * width, m + 1)
    offsets = np.cumsum((N_HEADER, *sizes))
    block = np.zeros(int(offsets[-1]))
    block[:9] = (n, m, slices, width, *offsets[:5])
    block_views(block)[2][:] = starts
    return block


def block_views(block: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The arrays of a :func:`new_block` as views of it: elements (n, ``N_ELEMENT_COLUMNS``), feet (m,
    ``N_FOOT_COLUMNS``), starts (m + 1,) int64, stresses (n,) [Pa], lateral scratch (slices, ``N_LATERAL``,
    width). (:func:`_unpack` in compiled code: the same header, the same views.)"""
    n, m, slices, width = (int(v) for v in block[:4])
    o_el, o_ft, o_stress, o_lat, o_starts = (int(v) for v in block[4:9])
    return (block[o_el:o_el + n * N_ELEMENT_COLUMNS].reshape(n, N_ELEMENT_COLUMNS),
            block[o_ft:o_ft + m * N_FOOT_COLUMNS].reshape(m, N_FOOT_COLUMNS),
            block[o_starts:o_starts + m + 1].view(np.int64),
            block[o_stress:o_stress + n],
            block[o_lat:o_lat + slices * N_LATERAL * width].reshape(slices, N_LATERAL, width))


@_compiled(inline="always")
def _unpack(block: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`block_views` in compiled code."""
    n, m, slices, width = int(block[H_ELEMENTS]), int(block[H_FEET]), int(block[H_SLICES]), int(block[H_WIDTH])
    o_el, o_ft, o_stress = int(block[H_EL]), int(block[H_FT]), int(block[H_STRESS])
    o_lat, o_starts = int(block[H_LAT]), int(block[H_STARTS])
    return (block[o_el:o_el + n * N_ELEMENT_COLUMNS].reshape((n, N_ELEMENT_COLUMNS)),
            block[o_ft:o_ft + m * N_FOOT_COLUMNS].reshape((m, N_FOOT_COLUMNS)),
            block[o_starts:o_starts + m + 1].view(np.int64),
            block[o_stress:o_stress + n],
            block[o_lat:o_lat + slices * N_LATERAL * width].reshape((slices, N_LATERAL, width)))


@_compiled()
def _step_foot(el: np.ndarray, ft: np.ndarray, starts: np.ndarray, stress: np.ndarray,
               lat: np.ndarray, states: np.ndarray, ring: np.ndarray, params: np.ndarray, f: int, dt: float,
               forces: np.ndarray, torques: np.ndarray, each: np.ndarray) -> int:
    """Foot ``f``'s step once placed: its elements' paper step, then the 3-D law; the element refused, or -1.

    :meth:`mudforce.steppers.contact3d.MudContact3D.step` for one foot, in passes over its elements:

    1. each element's paper step: its depth settled
       (:func:`mudforce.model.law3d.settle_depth`), then the 1-D stepper's
       calls (:func:`mudforce._kernel.loops.run_feet`'s: :func:`~mudforce._kernel.transitions.quiet_step`,
       else ``advance`` through :func:`~mudforce._kernel.loops.advance_row`, called out of line;
       ``stress_parts``), with the
       foot's params row loaded once (every element of a foot has the same
       mud and width: :class:`~mudforce.steppers.contact3d.MudContacts3D` builds them
       so). A FREE element that stays FREE (most elements above the
       surface) stores only the state columns its quiet step changes. An
       element at or above the surface has its stress at once (no spring
       there: Eq. (4) is 0), and, once the foot has started, carries
       :func:`~mudforce.model.law3d.vertical_force` alone, which is what
       ``element_force`` gives it, without the horizontal law's arithmetic;
       a submerged one is gathered into ``lat`` with its world geometry;
    2. over the gathered elements, in loops without branches (vectorised):
       Eq. (4) once per element (:func:`~mudforce.model.equations.nonlinear_spring_stress`,
       the 1-D stepper's spring, which :func:`~mudforce.model.law3d.spring_stress` is
       in compiled code: called here itself, inlined, so that the loop
       vectorises, where ``spring_stress``'s compiled form is a call per
       element; ``loops.spring_pass`` would compute the same number again),
       the paper's stress (``total_force``, the spring where the branch has
       it), then :func:`~mudforce.model.law3d.element_force`;
    3. their slips scattered and the wrench summed: the elements at or above
       the surface in element order (during pass 1), then the gathered ones
       in element order, as :class:`~mudforce.steppers.contact3d.MudContact3D`'s
       loop does. At a foot's first step no element is loaded sideways: one
       more pass sums them all in element order.

    The foot's rotation is read once (:func:`_foot_rotation`) and each
    element's world geometry is recomputed from it where it is used (memory,
    not arithmetic, bounds a step of thousands of feet). ``ft``'s width,
    alpha and beta are the params row's (the same numbers).

    With ``each`` one row per element (:func:`step_feet`), every element's force [N] goes into its row, the
    elements that carry their vertical force alone included (zero or not), and the wrench is summed over them
    in element order at the end (:func:`_in_element_order`) instead.
    """
    # (never negative; said to the compiler, which then drops some of numba's wraparound of negative indices:
    # ~1 % fewer instructions an element-step, docs/speed.md)
    lo, hi = max(starts[f], 0), max(starts[f + 1], 0)
    p = load_params(params, lo)
    quiet = exact_rule(p)
    r = _foot_rotation(ft, f)
    px, py, pz = ft[f, F_PX], ft[f, F_PX + 1], ft[f, F_PX + 2]
    h = ft[f, F_SURFACE]
    started = ft[f, F_STARTED] != 0.0
    each_ = each.shape[0] != 0  # every element's force wanted (MudContact3D), the wrench summed in element order
    sfx = sfy = sfz = 0.0
    stx = sty = stz = 0.0
    m = 0
    for i in range(lo, hi):
        row = states[i]
        _, _, oz = rotate(r, el[i, E_CBX], el[i, E_CBY], el[i, E_CBZ])
        z = element_depth(h, pz, oz)  # (checked by _place)
        if row[S_STARTED] != 0.0:  # law3d.settle_depth: a change of depth by rounding is none
            z = settle_depth(z, row[S_DEPTH])
        # ---- the paper's step of the element (what _kernel.loops.run_feet does for a foot)
        if quiet and row[S_MODE] == FREE:
            q = quiet_step(load_state(states, i), load_cache(states, i), p, z, dt)
            ok = q.ok
            if ok:  # FREE stays FREE: only these columns change (the others are the state's own)
                s1 = q.state
                row[S_STARTED] = s1.started
                row[S_TIME] = s1.time
                row[S_DEPTH] = s1.depth
                row[S_MUD] = s1.mud
                row[S_DIRECTION] = s1.direction
                row[S_VELOCITY] = s1.velocity
        else:
            ok = False
            if quiet:
                q = quiet_step(load_state(states, i), load_cache(states, i), p, z, dt)
                ok = q.ok
                if ok:
                    store_state(states, i, q.state)
        if not ok:
            q = advance_row(states, ring, i, params, z, dt)
            if not q.ok:  # pragma: no cover - every input the 1-D stepper refuses was refused before
                return i
        fe1, fs, _, spring = stress_parts(p, q.state, q.velocity)
        # ---- the element's world geometry and the 3-D law's first pass
        ox, oy, oz = rotate(r, el[i, E_CBX], el[i, E_CBY], el[i, E_CBZ])
        wx, wy, wz = px + ox, py + oy, pz + oz
        if z > 0.0:  # submerged: gathered for the spring and the lateral law
            lat[L_INDEX, m] = i
            lat[L_DEPTH, m] = z
            lat[L_FE1, m] = fe1
            lat[L_FS, m] = fs
            lat[L_HAS_SPRING, m] = 1.0 if spring else 0.0
            if started:
                nx, ny, nz = rotate(r, el[i, E_NBX], el[i, E_NBY], el[i, E_NBZ])
                lat[L_NX, m] = nx
                lat[L_NY, m] = ny
                lat[L_NZ, m] = nz
                lat[L_OX, m] = ox
                lat[L_OY, m] = oy
                lat[L_OZ, m] = oz
                lat[L_AREA, m] = el[i, E_AREA]
                lat[L_SX, m] = el[i, E_SLIPX]
                lat[L_SY, m] = el[i, E_SLIPY]
                lat[L_MX, m] = wx - el[i, E_CX]
                lat[L_MY, m] = wy - el[i, E_CY]
            m += 1
        else:  # no spring at or above the surface (Eq. (4) is 0 there): the stress at once
            sigma = total_force(fe1, 0.0, fs, p.area)
            stress[i] = sigma
            if started:  # what element_force gives an element that carries no horizontal force
                el[i, E_SLIPX] = 0.0
                el[i, E_SLIPY] = 0.0
                if sigma != 0.0 or each_:  # (most elements above the surface carry none: no force, no moment)
                    _, _, nz = rotate(r, el[i, E_NBX], el[i, E_NBY], el[i, E_NBZ])
                    fz = vertical_force(sigma, el[i, E_AREA], nz)
                    if each_:
                        _vertical_into(each, i, fz)
                    mx, my, mz = moment(ox, oy, oz, 0.0, 0.0, fz)
                    sfz += fz
                    stx += mx
                    sty += my
                    stz += mz
        if started:
            el[i, E_CX] = wx
            el[i, E_CY] = wy
            el[i, E_CZ] = wz
    # ---- the gathered elements: Eq. (4) once each, their paper stress (rows as arrays: the loops vectorise)
    depth, spring_, area = lat[L_DEPTH], lat[L_SPRING], lat[L_AREA]
    fe1s, fss, has, stresses = lat[L_FE1], lat[L_FS], lat[L_HAS_SPRING], lat[L_STRESS]
    alpha, beta, width, area_1d = p.alpha, p.beta, p.width, p.area
    for j in range(m):  # Eq. (4), inlined (law3d.spring_stress's compiled form is a call, which does not vectorise)
        spring_[j] = nonlinear_spring_stress(alpha, beta, depth[j], width)
    for j in range(m):
        stresses[j] = total_force(fe1s[j], spring_[j] if has[j] != 0.0 else 0.0, fss[j], area_1d)
    for j in range(m):
        stress[int(lat[L_INDEX, j])] = stresses[j]
    if not started:  # a first step: no element is loaded sideways; each carries its vertical force, in order
        for i in range(lo, hi):
            ox, oy, oz = rotate(r, el[i, E_CBX], el[i, E_CBY], el[i, E_CBZ])
            el[i, E_SLIPX] = 0.0
            el[i, E_SLIPY] = 0.0
            if stress[i] != 0.0 or each_:
                _, _, nz = rotate(r, el[i, E_NBX], el[i, E_NBY], el[i, E_NBZ])
                fz = vertical_force(stress[i], el[i, E_AREA], nz)
                if each_:
                    _vertical_into(each, i, fz)
                mx, my, mz = moment(ox, oy, oz, 0.0, 0.0, fz)
                sfz += fz
                stx += mx
                sty += my
                stz += mz
            el[i, E_CX] = px + ox
            el[i, E_CY] = py + oy
            el[i, E_CZ] = pz + oz
    elif m > 0:  # the 3-D law on the submerged elements
        k = ft[f, F_STIFFNESS]
        sigma_y = ft[f, F_SIGMA_Y]
        lambda_ = ft[f, F_LAMBDA]
        rho = ft[f, F_RHO]
        per_dt = 1.0 / dt
        nxs, nys, nzs = lat[L_NX], lat[L_NY], lat[L_NZ]
        sxs, sys_, mxs, mys = lat[L_SX], lat[L_SY], lat[L_MX], lat[L_MY]
        fxs, fys, fzs = lat[L_FX], lat[L_FY], lat[L_FZ]
        for j in range(m):  # the 3-D law
            slip_x, slip_y, fx, fy, fz = element_force(
                stresses[j], spring_[j], area[j], nxs[j], nys[j], nzs[j], depth[j], sxs[j], sys_[j], mxs[j], mys[j],
                per_dt, True, k, sigma_y, lambda_, rho)
            sxs[j] = slip_x
            sys_[j] = slip_y
            fxs[j] = fx
            fys[j] = fy
            fzs[j] = fz
        for j in range(m):
            i = int(lat[L_INDEX, j])
            el[i, E_SLIPX] = sxs[j]
            el[i, E_SLIPY] = sys_[j]
            fx, fy, fz = fxs[j], fys[j], fzs[j]
            if each_:
                each[i, 0] = fx
                each[i, 1] = fy
                each[i, 2] = fz
            mx, my, mz = moment(lat[L_OX, j], lat[L_OY, j], lat[L_OZ, j], fx, fy, fz)
            sfx += fx
            sfy += fy
            sfz += fz
            stx += mx
            sty += my
            stz += mz
    if each_:  # MudContact3D's order: every element's force and moment, from the first element, in element order
        sfx, sfy, sfz, stx, sty, stz = _in_element_order(el, each, r, lo, hi)
    forces[f, 0] = sfx
    forces[f, 1] = sfy
    forces[f, 2] = sfz
    torques[f, 0] = stx
    torques[f, 1] = sty
    torques[f, 2] = stz
    ft[f, F_STARTED] = 1.0
    return -1


@_compiled()
def element_forces(stress: np.ndarray, spring: np.ndarray, areas: np.ndarray, nx: np.ndarray, ny: np.ndarray,
                   nz: np.ndarray, ox: np.ndarray, oy: np.ndarray, oz: np.ndarray, depth: np.ndarray,
                   slip: np.ndarray, mx: np.ndarray, my: np.ndarray, per_dt: float, stiffness: float,
                   sigma_y: float, lambda_: float, rho_m: float, out: np.ndarray) -> None:
    """:func:`mudforce.model.law3d.element_force` and :func:`~mudforce.model.law3d.moment` on every element of a
    started foot (:class:`~mudforce.steppers.contact3d.MudContact3D`'s step): ``out[i]`` = slip x, slip y [m],
    force x, y, z [N], moment x, y, z [N m].

    The arrays are the elements' columns (SI, world frame; ``slip`` (n, 2) the last slips); one compiled
    loop rather than numpy's dozens of passes, the same source, the same bits.
    """
    for i in range(stress.shape[0]):
        sx, sy, fx, fy, fz = element_force(stress[i], spring[i], areas[i], nx[i], ny[i], nz[i], depth[i], slip[i, 0],
                                           slip[i, 1], mx[i], my[i], per_dt, True, stiffness, sigma_y, lambda_,
                                           rho_m)
        tx, ty, tz = moment(ox[i], oy[i], oz[i], fx, fy, fz)
        out[i, 0] = sx
        out[i, 1] = sy
        out[i, 2] = fx
        out[i, 3] = fy
        out[i, 4] = fz
        out[i, 5] = tx
        out[i, 6] = ty
        out[i, 7] = tz


@_compiled()
def step_feet(positions: np.ndarray, quaternions: np.ndarray, dt: float, block: np.ndarray, states: np.ndarray,
              ring: np.ndarray, params: np.ndarray, forces: np.ndarray, torques: np.ndarray, each: np.ndarray) -> int:
    """One step of every foot: the wrench of foot ``f`` [N], [N m] into ``forces[f]`` and ``torques[f]``.

    ``positions`` (m, 3) [m] and ``quaternions`` (m, 4) ``(w, x, y, z)``
    are the feet's poses, ``dt`` [s] the time since the last step (ignored
    if no foot has started). ``block`` holds the step's own arrays (:func:`new_block`, one slice: the elements,
    the feet, the starts, the 1-D stepper's forces (on a unit area: the elements' paper stresses [Pa]) and the
    lateral scratch); ``states``, ``ring`` and ``params`` are the 1-D stepper's rows, one per element. Returns
    :data:`OK`; or, having changed nothing, the first foot whose pose or depth is refused (see :func:`_place`),
    :data:`BAD_DT` for a ``dt`` outside [``MIN_DT``, ``MAX_DT``] once a
    foot has started, or :data:`BAD_SHAPE` if the poses or the outputs are
    not one row per foot (``ft``'s rows): (m, 3), (m, 4), (m, 3), (m, 3),
    or ``each`` neither (0, 3) nor one row per element.

    ``each`` (0, 3): :class:`~mudforce.steppers.contact3d.MudContacts3D`'s step, each foot's wrench summed
    as it goes (see :func:`_step_foot`). One row per element (:class:`~mudforce.steppers.contact3d.MudContact3D`,
    one foot): each element's force [N] into its row as well, and each foot's wrench summed over its elements
    in element order, as ``MudContact3D``'s numpy step sums it (:func:`_in_element_order`), its bits.
    """
    el, ft, starts, stress, lat = _unpack(block)
    m = ft.shape[0]
    if not (positions.shape[0] == m and positions.shape[1] == 3 and quaternions.shape[0] == m
            and quaternions.shape[1] == 4 and forces.shape[0] == m and forces.shape[1] == 3
            and torques.shape[0] == m and torques.shape[1] == 3
            and (each.shape[0] == 0 or each.shape[0] == el.shape[0]) and each.shape[1] == 3):
        return BAD_SHAPE
    dt = _checked_dt(ft, m, dt)  # 1.0 (ignored by every element's first step) while no foot has started
    if dt != dt:
        return BAD_DT
    bad = _place(positions, quaternions, el, ft, starts)
    if bad != OK:
        return bad
    for f in range(m):
        refused = _step_foot(el, ft, starts, stress, lat[0], states, ring, params, f, dt, forces, torques,
                             each)
        if refused >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
            return refused
    return OK


@_compiled(inline="always")
def _checked_dt(ft: np.ndarray, m: int, dt: float) -> float:
    """``dt`` if a foot has started and it is within bounds, 1.0 if none has started, NaN if refused."""
    any_started = False
    for f in range(m):
        any_started |= ft[f, F_STARTED] != 0.0
    if not any_started:
        return 1.0
    return dt if MIN_DT <= dt <= MAX_DT else math.nan


@_compiled(parallel=True)
def step_feet_threads(positions: np.ndarray, quaternions: np.ndarray, dt: float, block: np.ndarray,
                      states: np.ndarray, ring: np.ndarray, params: np.ndarray, forces: np.ndarray,
                      torques: np.ndarray, each: np.ndarray, chunks: np.ndarray) -> int:
    """:func:`step_feet` with the feet in ``chunks.shape[0]`` contiguous slices on numba's threads.

    The checks run first, on the calling thread, over every foot; then
    each slice's elements take their 1-D step and its feet their lateral
    law. The feet are independent, so the results are :func:`step_feet`'s
    bit for bit. ``block``'s lateral scratch holds one lateral block per slice.
    """
    el, ft, starts, stress, lat = _unpack(block)
    m = positions.shape[0]
    dt = _checked_dt(ft, m, dt)
    if dt != dt:
        return BAD_DT
    bad = _place(positions, quaternions, el, ft, starts)
    if bad != OK:
        return bad
    n = chunks.shape[0]
    for c in prange(n):
        lo = m * c // n
        hi = m * (c + 1) // n
        chunks[c] = -1
        for f in range(lo, hi):
            refused = _step_foot(el, ft, starts, stress, lat[c], states, ring, params, f, dt, forces,
                                 torques, each)
            if refused >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
                chunks[c] = refused
    for c in range(n):
        if chunks[c] >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
            return int(chunks[c])
    return OK


def fixed_types(dispatcher: Any, *examples: Any) -> Any:
    """A dispatcher of ``dispatcher``'s compiled code that compiles nothing new: other argument types raise TypeError.

    Speed plumbing for :meth:`mudforce.steppers.contact3d.MudContacts3D.step`'s hot path. numba's dispatcher
    types every argument in C (its dtype, number of dimensions, layout, alignment and writeability: ~30 ns an
    array) before it picks the compiled code; with compiling disabled, an argument of any other type (a list, a
    float32, a strided or read-only array, ...) raises ``TypeError`` before anything runs, instead of compiling a
    new specialisation. So the caller checks nothing but what the types do not say (the shapes: :data:`BAD_SHAPE`
    from :func:`step_feet`) and sends anything refused to its checks that convert or word the error. The
    compiled code is ``dispatcher``'s own (the same bits): call ``dispatcher`` once first, so that it has some, or
    give ``examples``, arguments of the one set of types to compile it for (or load from numba's cache).
    """
    if examples:
        dispatcher.compile(tuple(typeof(a) for a in examples))
    fixed = type(dispatcher)(dispatcher.py_func, targetoptions=dispatcher.targetoptions)
    for compiled in dispatcher.overloads.values():
        fixed.add_overload(compiled)
    fixed.disable_compile()
    return fixed
