"""Speed plumbing only: the compiled 3-D step of many feet (:class:`mudforce.steppers.contact3d.MudContacts3D`).

Nothing here is physics. One call places every foot's elements by its pose
(:func:`mudforce.model.law3d.rotation`, :func:`~mudforce.model.law3d.rotate`,
:func:`~mudforce.model.law3d.element_depth`), steps every element's paper state
with the 1-D stepper's functions (:func:`~mudforce._kernel.transitions.quiet_step`'s
equations, and the state machine itself, :func:`~mudforce._kernel.loops.advance_row`,
for the steps in which something happens, so the state machine exists once), and
applies the 3-D law through :func:`mudforce.model.law3d.element_force` and
:func:`~mudforce.model.law3d.moment`: the very functions
:class:`~mudforce.steppers.contact3d.MudContact3D`'s numpy step and :mod:`mudforce.jax.contact3d`
call on arrays, compiled in here (law3d registers them with numba). Only the
control flow and the storage are this module's.

Where things are kept (:func:`new_block`, one float64 array):

* **the lanes**: every element's constants (body-frame centroid, normal, area), its 1-D state (the ``S_*``
  columns of :mod:`~mudforce._kernel.layout`'s state row; of its step-length cache only the step length, a block
  keeping one cache for its lanes, ``B_CACHE``) and its lateral state
  (slip, last world centroid), field by field, four elements side by side (a chunk), in blocks of
  :data:`LANES` elements: each foot's elements fill ``ceil(n / LANES)`` blocks of its own, the last padded.
  Field ``W_x`` of a lane lies ``W_x FIELD`` entries after its first field, a constant the compiler sees, so
  a chunk's four lanes are computed as one (4 doubles an instruction): the element-steps in
  which nothing happens (99 % of a walk's) run without branches, every contact state's quiet step computed
  and the element's own selected (:func:`_paper_lanes`), and the 3-D law likewise, by groups of
  :data:`GROUP` lanes, a group wholly above the surface taking the vertical force alone
  (:func:`_law_lanes`). The rest go through the state machine one by one (:func:`_rare_lanes`).
* each foot's constants, this step's pose and its ``started`` flag are a row of the foot block (``F_*``
  columns), and ``starts[f]:starts[f + 1]`` are its elements;
* the element block (``E_*`` columns, one row per element) holds the constants as the Python side wrote them
  and, with the 1-D rows (``states``, ``ring``, ``params``: the layout's, one per element, arrays of their
  own), the **export** of the lanes: a step leaves the rows and the slips and centroids behind (``H_STALE``
  set), :func:`rows_from_lanes` brings them up to date before anything reads them, and
  :func:`lanes_from_rows` takes them back after anything writes them (a state restored, a reset, a step of
  the numpy reference). The state machine steps an element on its own row (written from the lanes, read
  back).

:func:`step_feet` checks every foot's pose, every element's depth and the
step length before anything moves (so a refused step changes nothing),
then steps. It sums each foot's wrench over its elements in element order,
as :class:`~mudforce.steppers.contact3d.MudContact3D`'s numpy step does (numpy's
``sum(axis=0)``), so the two give the same bits; the same foot gives the same
bits here whatever the other feet are.

:class:`~mudforce.steppers.contact3d.MudContact3D`'s step is this one, for one
foot, with an ``each`` array (:func:`step_feet`): every element's force is
written out as well; one compiled step for both classes (and one compile).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import prange, typeof

from mudforce._kernel.addresses import f64_1d, f64_2d
from mudforce._kernel.bounds import MAX_DEPTH, MAX_DT, MAX_HORIZONTAL, MIN_DT
from mudforce._kernel.layout import (
    CONTACT,
    FREE,
    N_CORE,
    NECKED,
    S_CACHE_DT,
    S_DEPTH,
    S_DIRECTION,
    S_MODE,
    S_MUD,
    S_NECK_AGE,
    S_NECK_G,
    S_NECK_GI,
    S_NECK_V,
    S_NECK_Z,
    S_STARTED,
    S_STRAIN,
    S_TIME,
    S_VELOCITY,
    Cache,
    Params,
    State,
    _compiled,
    load_params,
)
from mudforce._kernel.loops import advance_row
from mudforce._kernel.transitions import (
    exact_rule,
    neck_filter_step,
    piece_drag,
    sign,
    stress_parts,
    total_force,
)
from mudforce.model.equations import (
    intrusion_stress,
    maxwell_strain_step,
    neck_breaks,
    necked_mud_motion,
    necked_stress,
    nonlinear_spring_stress,
    submerged_drag_stress,
    withdrawal_stress,
)
from mudforce.model.law3d import (
    QUATERNION_TOLERANCE,
    bearing_stress,
    element_depth,
    element_force,
    moment,
    rotate,
    rotation,
    select,
    settle_depth,
    vertical_element_force,
)

__all__ = [
    "BAD_DT",
    "BAD_SHAPE",
    "N_ELEMENT_COLUMNS",
    "N_FOOT_COLUMNS",
    "OK",
    "block_views",
    "element_forces",
    "export_rows",
    "fixed_types",
    "lane_entries",
    "lanes_from_rows",
    "new_block",
    "row_from_lanes",
    "rows_from_lanes",
    "step_feet",
    "step_feet_threads",
    "step_one",
]

# columns of the element block: one row per element (all feet's, foot after foot)
E_CBX, E_CBY, E_CBZ = 0, 1, 2  # centroid in the body frame [m]
E_NBX, E_NBY, E_NBZ = 3, 4, 5  # outward unit normal in the body frame [-]
E_AREA = 6  # area [m^2]
E_SLIPX, E_SLIPY = 7, 8  # horizontal elastic slip [m] (state: the lanes' export, rows_from_lanes)
E_CX, E_CY, E_CZ = 9, 10, 11  # world centroid at the last step [m] (state: the lanes' export)
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
F_BEARING = 22  # the bearing scale [-] (law3d.bearing_stress)
N_FOOT_COLUMNS = 23

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


# the header of the block (:func:`new_block`): the sizes, where each array starts in it (float64 entries), and
# whether the 1-D rows are behind the lanes (set by a step, cleared by rows_from_lanes and lanes_from_rows)
H_ELEMENTS, H_FEET, H_BLOCKS = 0, 1, 2
H_EL, H_FT, H_LANES, H_FIRST, H_STARTS = 3, 4, 5, 6, 7
H_STALE = 8
N_HEADER = 16


def new_block(starts: np.ndarray) -> np.ndarray:
    """One float64 array holding the compiled step's own arrays for feet whose elements are ``starts[f]:starts[f
    + 1]``: the element block (``E_*`` columns), the foot block (``F_*``), the lanes (``W_*`` fields, each foot's
    elements in ``ceil(n / LANES)`` blocks of its own), each foot's first lane block and the starts, after a
    header of their sizes and offsets; all zero but the starts and first blocks. :func:`block_views` gives them
    as arrays.

    Speed plumbing: :func:`step_feet` takes them as one argument, not five (numba's dispatcher costs ~0.05-0.1
    us an array argument); the 1-D rows stay arrays of their own (``MudContacts``' in ``MudContact3D``).
    """
    starts = np.asarray(starts, dtype=np.int64)
    m = starts.shape[0] - 1
    n = int(starts[-1])
    first = np.zeros(m + 1, dtype=np.int64)
    np.cumsum(-(-np.diff(starts) // LANES), out=first[1:])
    nb = int(first[-1])
    sizes = (n * N_ELEMENT_COLUMNS, m * N_FOOT_COLUMNS, nb * BLOCK, m + 1, m + 1)
    offsets = np.cumsum((N_HEADER, *sizes))
    block = np.zeros(int(offsets[-1]))
    block[:8] = (n, m, nb, *offsets[:5])
    views = block_views(block)
    views[2][:] = starts
    views[4][:] = first
    return block


def lane_entries(block: np.ndarray) -> np.ndarray:
    """Each element's entry in the lanes of a :func:`new_block` (its first field's), foot after foot, int64: field
    ``W_x`` of element ``i`` is ``lanes[entries[i] + W_x * FIELD]``."""
    _, _, starts, _, first = block_views(block)
    entries = np.empty(int(starts[-1]), dtype=np.int64)
    for f in range(starts.shape[0] - 1):
        j = np.arange(int(starts[f + 1] - starts[f]))
        lane = j % LANES
        entries[starts[f]:starts[f + 1]] = (first[f] + j // LANES) * BLOCK + (lane >> 2) * CHUNK + (lane & 3)
    return entries


def block_views(block: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The arrays of a :func:`new_block` as views of it: elements (n, ``N_ELEMENT_COLUMNS``), feet (m,
    ``N_FOOT_COLUMNS``), starts (m + 1,) int64, the lanes (flat: lane block ``b`` is ``b BLOCK .. (b + 1)
    BLOCK``), each foot's first lane block (m + 1,) int64. (:func:`_unpack` in compiled code: the same header,
    the same views.)"""
    n, m, nb = (int(v) for v in block[:3])
    o_el, o_ft, o_lanes, o_first, o_starts = (int(v) for v in block[3:8])
    return (block[o_el:o_el + n * N_ELEMENT_COLUMNS].reshape(n, N_ELEMENT_COLUMNS),
            block[o_ft:o_ft + m * N_FOOT_COLUMNS].reshape(m, N_FOOT_COLUMNS),
            block[o_starts:o_starts + m + 1].view(np.int64),
            block[o_lanes:o_lanes + nb * BLOCK],
            block[o_first:o_first + m + 1].view(np.int64))


@_compiled(inline="always")
def _unpack(block: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`block_views` in compiled code."""
    n, m, nb = int(block[H_ELEMENTS]), int(block[H_FEET]), int(block[H_BLOCKS])
    o_el, o_ft, o_lanes = int(block[H_EL]), int(block[H_FT]), int(block[H_LANES])
    o_first, o_starts = int(block[H_FIRST]), int(block[H_STARTS])
    return (block[o_el:o_el + n * N_ELEMENT_COLUMNS].reshape((n, N_ELEMENT_COLUMNS)),
            block[o_ft:o_ft + m * N_FOOT_COLUMNS].reshape((m, N_FOOT_COLUMNS)),
            block[o_starts:o_starts + m + 1].view(np.int64),
            block[o_lanes:o_lanes + nb * BLOCK],
            block[o_first:o_first + m + 1].view(np.int64))


# ---------------------------------------------------------------- the elements' working layout: lanes
# Every element's paper state, its constants and its lateral state are kept field by field, four elements side by
# side: a chunk of CHUNK_LANES elements holds field F of its lane l at entry F FIELD + l (FIELD = CHUNK_LANES), and
# a block of LANES elements is LANES / CHUNK_LANES chunks one after another, then the block's step-length cache
# (B_CACHE); a foot's elements fill ceil(n / LANES) blocks of its own, the last padded. The distances between a
# chunk's fields are constants the compiler sees, so the four lanes of a chunk are computed as one (4 doubles an
# instruction), and a chunk's fields are contiguous in memory, a block's chunks too, so that a step of thousands of
# feet streams through them (field after field of 64 elements apart was 15-40 % slower there, docs/speed.md).
# The 1-D rows (layout's, one per element) are the export of the lanes: written from them on demand
# (:func:`rows_from_lanes`), read into them after they change (:func:`lanes_from_rows`).
LANES = 64
CHUNK_LANES = 4
FIELD = CHUNK_LANES
W_CBX, W_CBY, W_CBZ = 0, 1, 2  # centroid in the body frame [m]
W_NBX, W_NBY, W_NBZ = 3, 4, 5  # outward unit normal in the body frame [-]
W_AREA = 6  # area [m^2]
W_STATE = 7  # the 1-D state proper, the state row's first N_CORE columns in layout's S_* order (W_STATE + S_*)
W_CACHE_DT = W_STATE + N_CORE  # the step length of the element's step-length cache (the cache itself is its row's)
W_SLIPX, W_SLIPY = W_CACHE_DT + 1, W_CACHE_DT + 2  # horizontal elastic slip [m]
W_CX, W_CY, W_CZ = W_SLIPY + 1, W_SLIPY + 2, W_SLIPY + 3  # world centroid at the last step [m]
W_OK = W_CZ + 1  # this step: 1.0 where the quiet step held, else 0.0 (the state machine steps the element)
W_Z = W_OK + 1  # this step: the depth [m]
W_FE1, W_FS = W_Z + 1, W_Z + 2  # this step: the paper's stresses but the spring's, f_e1 and f_s [Pa]
W_HAS_SPRING = W_FS + 1  # this step: 1.0 where the paper's stress has Eq. (4)'s spring (CONTACT, intrusion)
W_FX, W_FY, W_FZ = W_HAS_SPRING + 1, W_HAS_SPRING + 2, W_HAS_SPRING + 3  # this step: the element's force [N]
W_TX, W_TY, W_TZ = W_FZ + 1, W_FZ + 2, W_FZ + 3  # this step: its moment about the body origin [N m]
W_STRESS = W_TZ + 1  # this step: the element's paper stress [Pa] (the 1-D stepper's force on a unit area)
N_FIELDS = W_STRESS + 1
CHUNK = N_FIELDS * FIELD  # entries of a chunk of CHUNK_LANES elements
#: where a block keeps its step-length cache (layout's ``Cache``, 7 entries, after its chunks): the decays and
#: Eq. (7)'s transition matrix of every element of a foot are the same numbers for the same step length (they are
#: computed from it and the mud's constants), so one copy serves the lanes whose own cache is for that step length
#: (``W_CACHE_DT``); the others take the state machine, on their rows, which keep every element's own cache
B_CACHE = (LANES // CHUNK_LANES) * CHUNK
BLOCK = B_CACHE + 8  # entries of a block of LANES elements
#: lanes are stepped by the 3-D law in groups of this many: a group wholly above the surface takes the vertical
#: force alone (the paper's stress on the downward projection), without the horizontal law's arithmetic
GROUP = 8


@_compiled(inline="always")
def _lane(block: int, j: int) -> int:
    """Entry of lane ``j``'s first field in the block at ``block``."""
    return block + (j >> 2) * CHUNK + (j & 3)


@_compiled(inline="always")
def _at(q: np.uint64, field: int) -> np.uint64:
    """Entry of ``field`` of the lane at entry ``q`` (its first field's): unsigned, so that numba adds no
    wraparound of negative indices (which keeps a loop from vectorising)."""
    return q + np.uint64(field * FIELD)  # type: ignore[no-any-return]


@_compiled(inline="always")
def _quiet_lanes_step(s: State, c: Cache, p: Params, depth: float, dt: float
                      ) -> tuple[float, float, float, float, float, float, float, bool]:
    """:func:`~mudforce._kernel.transitions.quiet_step` without branches, for a loop over lanes: every contact
    state's quiet step computed and the element's own selected, the same calls, the same bits.

    Returns the state's changed columns ``(mud, neck_age, direction, velocity, neck_g, neck_gi, strain)`` and
    whether nothing happened in the step (else they are meaningless and the state machine steps the element).
    The necking test of a withdrawal step is :func:`~mudforce.model.equations.necking_time`'s "does not break"
    (:func:`~mudforce.model.equations.neck_breaks` at the step's start and end: the suction is monotone within
    it), without its instant, which only a step that necks needs. ``s.mode`` is a float here.
    """
    z0 = s.depth
    v = (depth - z0) / dt
    d = sign(v)
    ok = (abs(dt - c.dt) <= 0.5e-9 * c.dt) & (abs(depth) < math.inf) & (s.started != 0.0)
    free = s.mode == float(FREE)
    necked = s.mode == float(NECKED)
    down = d >= 0.0
    age = s.neck_age + dt  # NECKED (up or at rest): Eq. (7)'s filter one step on
    gi, g = neck_filter_step(c, p, age, s.neck_gi, s.neck_g)
    _, mud_necked = necked_mud_motion(s.neck_v, s.neck_z, g, gi)
    strain_i = maxwell_strain_step(s.strain, v, p.tau_i, c.decay_i)  # CONTACT, intrusion
    fs = piece_drag(p, z0, v, dt)  # CONTACT, withdrawal in one piece in which the neck holds
    strain_w = maxwell_strain_step(s.strain, v, p.tau_w, c.decay_w)
    holds = (not neck_breaks(p.k_w, s.strain, fs, p.sigma_y)) & (not neck_breaks(p.k_w, strain_w, fs, p.sigma_y))
    ok_contact = select(down, depth > 0.0, ((z0 > 0.0) == (depth > 0.0)) & holds)
    ok = ok & select(free, depth <= 0.0, select(necked, d <= 0.0, ok_contact))
    strain = select(free | necked, s.strain, select(down, strain_i, strain_w))
    mud = select(free, depth, select(necked, mud_necked, depth - strain))
    return (mud, select(necked, age, s.neck_age), d, v, select(necked, g, s.neck_g), select(necked, gi, s.neck_gi),
            strain, ok)


@_compiled(inline="always")
def _stress_lanes(p: Params, mode: float, depth: float, direction: float, velocity: float, strain: float,
                  neck_v: float, neck_z: float, g: float, gi: float) -> tuple[float, float, bool]:
    """:func:`~mudforce._kernel.transitions.stress_parts` without branches (the state after a quiet step, its mode a
    float): ``(f_e1, f_s [Pa], spring)``, the same calls, the same bits."""
    free = mode == float(FREE)
    contact = mode == float(CONTACT)
    fs = submerged_drag_stress(p.lam, p.rho_m, velocity, depth)
    fe1_i, _ = intrusion_stress(p.k_i, p.tau_i, strain)
    fe1_w, _ = withdrawal_stress(p.k_w, p.tau_w, strain)
    fe1_n, _ = necked_stress(p.b_w, necked_mud_motion(neck_v, neck_z, g, gi)[0])
    fe1 = select(contact, select(direction >= 0.0, fe1_i, fe1_w), fe1_n)
    return select(free, 0.0, fe1), select(free, 0.0, fs), contact & (direction >= 0.0)


@_compiled()
def _paper_lanes(a: np.ndarray, block: int, width: int, p: Params, r: tuple[float, float, float, float, float,
                 float, float, float, float], h: float, pz: float, dt: float) -> bool:
    """The paper's quiet step of a block's first ``width`` lanes (a multiple of :data:`GROUP`), in one loop
    without branches (vectorised): each element's depth settled (:func:`~mudforce.model.law3d.settle_depth`), its
    quiet step, its stresses but the spring's. A lane whose quiet step does not hold keeps its state
    (``W_OK`` 0.0: :func:`_rare_lanes` steps it). Returns whether every lane's quiet step held."""
    b = np.uint64(max(block, 0))
    k = max(block + B_CACHE, 0)
    c = Cache(a[k], a[k + 1], a[k + 2], a[k + 3], a[k + 4], a[k + 5], a[k + 6])  # the block's (see B_CACHE)
    held = True
    for chunk in range(width >> 2):
        for sub in range(CHUNK_LANES):
            q = b + np.uint64(chunk * CHUNK + sub)
            _, _, oz = rotate(r, a[_at(q, W_CBX)], a[_at(q, W_CBY)], a[_at(q, W_CBZ)])
            started = a[_at(q, W_STATE + S_STARTED)]
            depth0 = a[_at(q, W_STATE + S_DEPTH)]
            z = element_depth(h, pz, oz)  # (checked by _place)
            z = select(started != 0.0, settle_depth(z, depth0), z)  # a change of depth by rounding is none
            mode = a[_at(q, W_STATE + S_MODE)]
            time = a[_at(q, W_STATE + S_TIME)]
            mud0 = a[_at(q, W_STATE + S_MUD)]
            age0 = a[_at(q, W_STATE + S_NECK_AGE)]
            neck_v = a[_at(q, W_STATE + S_NECK_V)]
            neck_z = a[_at(q, W_STATE + S_NECK_Z)]
            direction0 = a[_at(q, W_STATE + S_DIRECTION)]
            velocity0 = a[_at(q, W_STATE + S_VELOCITY)]
            g0 = a[_at(q, W_STATE + S_NECK_G)]
            gi0 = a[_at(q, W_STATE + S_NECK_GI)]
            strain0 = a[_at(q, W_STATE + S_STRAIN)]
            s = State(started, mode, time, depth0, mud0, age0, neck_v, neck_z, direction0, velocity0, g0, gi0, strain0)
            mud, age, d, v, g, gi, strain, ok = _quiet_lanes_step(s, c, p, z, dt)
            ok = ok & (a[_at(q, W_CACHE_DT)] == c.dt)  # the element's own cache is the block's
            fe1, fs, spring = _stress_lanes(p, mode, z, d, v, strain, neck_v, neck_z, g, gi)
            a[_at(q, W_OK)] = select(ok, 1.0, 0.0)
            held &= ok
            a[_at(q, W_Z)] = z
            a[_at(q, W_FE1)] = fe1
            a[_at(q, W_FS)] = fs
            a[_at(q, W_HAS_SPRING)] = select(spring, 1.0, 0.0)
            a[_at(q, W_STATE + S_STARTED)] = select(ok, 1.0, started)
            a[_at(q, W_STATE + S_TIME)] = select(ok, time + dt, time)
            a[_at(q, W_STATE + S_DEPTH)] = select(ok, z, depth0)
            a[_at(q, W_STATE + S_MUD)] = select(ok, mud, mud0)
            a[_at(q, W_STATE + S_NECK_AGE)] = select(ok, age, age0)
            a[_at(q, W_STATE + S_DIRECTION)] = select(ok, d, direction0)
            a[_at(q, W_STATE + S_VELOCITY)] = select(ok, v, velocity0)
            a[_at(q, W_STATE + S_NECK_G)] = select(ok, g, g0)
            a[_at(q, W_STATE + S_NECK_GI)] = select(ok, gi, gi0)
            a[_at(q, W_STATE + S_STRAIN)] = select(ok, strain, strain0)
    return held


@_compiled(inline="always")
def _store_law(a: np.ndarray, q: np.uint64, sx: float, sy: float, wx: float, wy: float, wz: float, fx: float,
               fy: float, fz: float, tx: float, ty: float, tz: float, sigma: float) -> None:
    """A lane's results of the 3-D law (at entry ``q``): its slip [m] and world centroid [m], kept; its force [N],
    moment [N m] and paper stress [Pa] of this step."""
    a[_at(q, W_SLIPX)] = sx
    a[_at(q, W_SLIPY)] = sy
    a[_at(q, W_CX)] = wx
    a[_at(q, W_CY)] = wy
    a[_at(q, W_CZ)] = wz
    a[_at(q, W_FX)] = fx
    a[_at(q, W_FY)] = fy
    a[_at(q, W_FZ)] = fz
    a[_at(q, W_TX)] = tx
    a[_at(q, W_TY)] = ty
    a[_at(q, W_TZ)] = tz
    a[_at(q, W_STRESS)] = sigma


@_compiled()
def _law_lanes(a: np.ndarray, block: int, width: int, p: Params, r: tuple[float, float, float, float, float, float,
               float, float, float], px: float, py: float, pz: float, dt: float, started: bool, k: float,
               sigma_y: float, lambda_: float, rho: float, bearing: float) -> None:
    """The 3-D law on a block's first ``width`` lanes (a multiple of :data:`GROUP`), in groups of :data:`GROUP`
    without branches (vectorised): Eq. (4) at the depth, the paper's stress (``total_force``), then
    :func:`~mudforce.model.law3d.element_force` and :func:`~mudforce.model.law3d.moment`. A group wholly at or
    above the surface carries :func:`~mudforce.model.law3d.vertical_element_force` alone, which is what
    ``element_force`` gives it (no spring there: Eq. (4) is 0), without the horizontal law's arithmetic. Every
    lane's paper step is done (:func:`_paper_lanes`, :func:`_rare_lanes`)."""
    b = np.uint64(max(block, 0))
    alpha, beta, h_width, area_1d = p.alpha, p.beta, p.width, p.area
    per_dt = 1.0 / dt
    for group in range(width // GROUP):
        g0 = b + np.uint64(group * 2 * CHUNK)
        submerged = False
        for c2 in range(2):
            for sub in range(CHUNK_LANES):
                submerged |= a[_at(g0 + np.uint64(c2 * CHUNK + sub), W_Z)] > 0.0
        if submerged:
            for c2 in range(2):  # the group's two chunks
                for sub in range(CHUNK_LANES):
                    q = g0 + np.uint64(c2 * CHUNK + sub)
                    z = a[_at(q, W_Z)]
                    ox, oy, oz = rotate(r, a[_at(q, W_CBX)], a[_at(q, W_CBY)], a[_at(q, W_CBZ)])
                    nx, ny, nz = rotate(r, a[_at(q, W_NBX)], a[_at(q, W_NBY)], a[_at(q, W_NBZ)])
                    # Eq. (4), inlined (law3d.spring_stress's compiled form is a call, which does not vectorise)
                    spring = nonlinear_spring_stress(alpha, beta, z, h_width)
                    sigma = total_force(a[_at(q, W_FE1)], select(a[_at(q, W_HAS_SPRING)] != 0.0, spring, 0.0),
                                        a[_at(q, W_FS)], area_1d)
                    wx, wy, wz = px + ox, py + oy, pz + oz
                    sx0, sy0 = a[_at(q, W_SLIPX)], a[_at(q, W_SLIPY)]
                    sx, sy, fx, fy, fz = element_force(sigma, bearing_stress(spring, bearing), a[_at(q, W_AREA)], nx,
                                                       ny, nz, z, sx0, sy0,
                                                       wx - a[_at(q, W_CX)], wy - a[_at(q, W_CY)], per_dt, started, k,
                                                       sigma_y, lambda_, rho)
                    tx, ty, tz = moment(ox, oy, oz, fx, fy, fz)
                    _store_law(a, q, sx, sy, wx, wy, wz, fx, fy, fz, tx, ty, tz, sigma)
        else:
            for c2 in range(2):  # the group's two chunks
                for sub in range(CHUNK_LANES):
                    q = g0 + np.uint64(c2 * CHUNK + sub)
                    ox, oy, oz = rotate(r, a[_at(q, W_CBX)], a[_at(q, W_CBY)], a[_at(q, W_CBZ)])
                    nx, ny, nz = rotate(r, a[_at(q, W_NBX)], a[_at(q, W_NBY)], a[_at(q, W_NBZ)])
                    sigma = total_force(a[_at(q, W_FE1)], 0.0, a[_at(q, W_FS)], area_1d)
                    fx, fy, fz = vertical_element_force(sigma, a[_at(q, W_AREA)], nx, ny, nz)
                    # element_force adds its horizontal 0 to these: 0.0 + fx (the same bits, but -0.0's sign)
                    fx, fy = 0.0 + fx, 0.0 + fy
                    tx, ty, tz = moment(ox, oy, oz, fx, fy, fz)
                    _store_law(a, q, 0.0, 0.0, px + ox, py + oy, pz + oz, fx, fy, fz, tx, ty, tz, sigma)


@_compiled()
def _rare_lanes(a: np.ndarray, block: int, count: int, first: int, states: np.ndarray, ring: np.ndarray,
                params: np.ndarray, dt: float) -> int:
    """The lanes of a block (its first ``count``, elements ``first``, ``first + 1``, ...) whose quiet step did not
    hold (:func:`_paper_lanes`): each through the state machine (:func:`~mudforce._kernel.loops.advance_row` on its
    1-D row, written from the lanes and read back), then its stresses but the spring's
    (:func:`~mudforce._kernel.transitions.stress_parts`) into the block's working values, as :func:`_paper_lanes`
    puts the others'; :func:`_law_lanes` then takes them all. ~1 % of a walk's element-steps. Returns the element
    refused, or -1."""
    p = load_params(params, first)
    for lane in range(count):
        q = _lane(block, lane)
        if a[q + W_OK * FIELD] != 0.0:
            continue
        i = first + lane
        row = states[i]  # (its cache columns are the element's own: the lanes keep only their step length)
        for j in range(N_CORE):
            row[j] = a[q + (W_STATE + j) * FIELD]
        st = advance_row(states, ring, i, params, a[q + W_Z * FIELD], dt)
        if not st.ok:  # pragma: no cover - every input the 1-D stepper refuses was refused before
            return i
        for j in range(N_CORE):
            a[q + (W_STATE + j) * FIELD] = row[j]
        a[q + W_CACHE_DT * FIELD] = row[S_CACHE_DT]
        if row[S_CACHE_DT] != a[block + B_CACHE]:  # a new step length: the block's cache is this element's
            for j in range(7):
                a[block + B_CACHE + j] = row[S_CACHE_DT + j]
        fe1, fs, _, has_spring = stress_parts(p, st.state, st.velocity)
        a[q + W_FE1 * FIELD] = fe1
        a[q + W_FS * FIELD] = fs
        a[q + W_HAS_SPRING * FIELD] = 1.0 if has_spring else 0.0
    return -1


@_compiled()
def _step_foot(ft: np.ndarray, starts: np.ndarray, lanes: np.ndarray, blocks: np.ndarray, states: np.ndarray,
               ring: np.ndarray, params: np.ndarray, f: int, dt: float, forces: np.ndarray, torques: np.ndarray,
               each: np.ndarray) -> int:
    """Foot ``f``'s step once placed (:func:`_place`): its elements' paper step, then the 3-D law; the element
    refused, or -1.

    :meth:`mudforce.steppers.contact3d.MudContact3D.step` for one foot, block by block of its elements' lanes:

    1. :func:`_paper_lanes`: every element's depth and quiet paper step (the 1-D stepper's ``quiet_step``, as
       :func:`mudforce._kernel.loops.run_feet` takes it, in a form without branches), its stresses but the spring's;
    2. :func:`_rare_lanes`: the elements in which something happens (a touchdown, a necking, a change of branch
       or of step length, a first step) through the state machine, one by one;
    3. :func:`_law_lanes`: Eq. (4), the paper's stress and the 3-D law (:func:`~mudforce.model.law3d.element_force`,
       :func:`~mudforce.model.law3d.moment`), every element;

    then the wrench, summed over the foot's elements in element order, as
    :class:`~mudforce.steppers.contact3d.MudContact3D`'s numpy step sums it (numpy's ``sum(axis=0)``), and, with
    ``each`` one row per element (:func:`step_feet`), every element's force [N] into its row. Every element of a
    foot has the same mud and width (:class:`~mudforce.steppers.contact3d.MudContacts3D` builds them so): the
    foot's params row is its first element's; ``ft``'s width, alpha and beta are that row's (the same numbers).
    """
    # (never negative; said to the compiler, which then drops some of numba's wraparound of negative indices)
    lo, hi = max(starts[f], 0), max(starts[f + 1], 0)
    if hi <= lo:
        for j in range(3):
            forces[f, j] = 0.0
            torques[f, j] = 0.0
        ft[f, F_STARTED] = 1.0
        return -1
    p = load_params(params, lo)
    r = (ft[f, F_R], ft[f, F_R + 1], ft[f, F_R + 2], ft[f, F_R + 3], ft[f, F_R + 4], ft[f, F_R + 5],
         ft[f, F_R + 6], ft[f, F_R + 7], ft[f, F_R + 8])
    px, py, pz = ft[f, F_PX], ft[f, F_PX + 1], ft[f, F_PX + 2]
    h = ft[f, F_SURFACE]
    started = ft[f, F_STARTED] != 0.0
    k, sigma_y, lambda_, rho = ft[f, F_STIFFNESS], ft[f, F_SIGMA_Y], ft[f, F_LAMBDA], ft[f, F_RHO]
    bearing = ft[f, F_BEARING]
    quiet = exact_rule(p)
    for b in range(blocks[f], blocks[f + 1]):
        first = lo + (b - blocks[f]) * LANES
        count = min(hi - first, LANES)
        width = -(-count // GROUP) * GROUP
        block = b * BLOCK
        held = _paper_lanes(lanes, block, width, p, r, h, pz, dt)
        if not quiet:  # pragma: no cover - the 3-D feet take the exact rule (MudContacts3D builds them so)
            held = False
            for lane in range(count):
                lanes[_lane(block, lane) + W_OK * FIELD] = 0.0
        if not held:  # (padding lanes past count are never stepped, whatever they hold)
            refused = _rare_lanes(lanes, block, count, first, states, ring, params, dt)
            if refused >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused before
                return refused
        _law_lanes(lanes, block, width, p, r, px, py, pz, dt, started, k, sigma_y, lambda_, rho, bearing)
    # the wrench in element order, from the first element (numpy's sum(axis=0)), and each element's force
    b0 = blocks[f]
    q0 = np.uint64(max(b0 * BLOCK, 0))
    sfx, sfy, sfz = lanes[_at(q0, W_FX)], lanes[_at(q0, W_FY)], lanes[_at(q0, W_FZ)]
    stx, sty, stz = lanes[_at(q0, W_TX)], lanes[_at(q0, W_TY)], lanes[_at(q0, W_TZ)]
    for b in range(b0, blocks[f + 1]):
        base = np.uint64(max(b * BLOCK, 0))
        count = min(hi - (lo + (b - b0) * LANES), LANES)
        for lane in range(1 if b == b0 else 0, count):
            q = base + np.uint64(_lane(0, lane))
            sfx += lanes[_at(q, W_FX)]
            sfy += lanes[_at(q, W_FY)]
            sfz += lanes[_at(q, W_FZ)]
            stx += lanes[_at(q, W_TX)]
            sty += lanes[_at(q, W_TY)]
            stz += lanes[_at(q, W_TZ)]
    if each.shape[0] != 0:
        for b in range(b0, blocks[f + 1]):
            base = np.uint64(max(b * BLOCK, 0))
            first = lo + (b - b0) * LANES
            for lane in range(min(hi - first, LANES)):
                q = base + np.uint64(_lane(0, lane))
                each[first + lane, 0] = lanes[_at(q, W_FX)]
                each[first + lane, 1] = lanes[_at(q, W_FY)]
                each[first + lane, 2] = lanes[_at(q, W_FZ)]
    forces[f, 0] = sfx
    forces[f, 1] = sfy
    forces[f, 2] = sfz
    torques[f, 0] = stx
    torques[f, 1] = sty
    torques[f, 2] = stz
    ft[f, F_STARTED] = 1.0
    return -1


@_compiled(inline="always")
def row_from_lanes(lanes: np.ndarray, entry: int, states: np.ndarray, i: int) -> None:
    """Element ``i``'s state proper (the first ``N_CORE`` columns of its 1-D row) from the lanes, where it is at
    ``entry`` (:func:`lane_entries`): an engine that reads a few rows after a step exports only those (the
    cache columns are the row's own)."""
    for j in range(N_CORE):
        states[i, j] = lanes[entry + (W_STATE + j) * FIELD]


def export_rows(block: np.ndarray, states: np.ndarray) -> None:
    """:func:`rows_from_lanes`, if a step has left the rows behind (``H_STALE``): what a contact calls before
    anything reads its rows, slips or centroids."""
    if block[H_STALE] != 0.0:
        rows_from_lanes(block, states)


@_compiled()
def rows_from_lanes(block: np.ndarray, states: np.ndarray) -> None:
    """The lanes' states into the 1-D rows (``states``, one per element) and the element block's slips and
    centroids (``E_SLIPX``, ``E_CX``, ...): the rows as the lanes have them (after a step: the export)."""
    el, _, starts, lanes, blocks = _unpack(block)
    for f in range(starts.shape[0] - 1):
        for i in range(starts[f], starts[f + 1]):
            k = i - starts[f]  # the element's place in its foot
            q = _lane((blocks[f] + k // LANES) * BLOCK, k % LANES)
            for j in range(N_CORE):  # (the cache columns are the rows' own: see B_CACHE)
                states[i, j] = lanes[q + (W_STATE + j) * FIELD]
            el[i, E_SLIPX] = lanes[q + W_SLIPX * FIELD]
            el[i, E_SLIPY] = lanes[q + W_SLIPY * FIELD]
            el[i, E_CX] = lanes[q + W_CX * FIELD]
            el[i, E_CY] = lanes[q + W_CY * FIELD]
            el[i, E_CZ] = lanes[q + W_CZ * FIELD]
    block[H_STALE] = 0.0


@_compiled()
def lanes_from_rows(block: np.ndarray, states: np.ndarray) -> None:
    """The 1-D rows (``states``) and the element block (constants, slips, centroids) into the lanes: after
    either changed (a state restored, a reset, a step of the numpy reference)."""
    el, _, starts, lanes, blocks = _unpack(block)
    for f in range(starts.shape[0] - 1):
        for i in range(starts[f], starts[f + 1]):
            k = i - starts[f]  # the element's place in its foot
            b = (blocks[f] + k // LANES) * BLOCK  # its lane block
            q = _lane(b, k % LANES)
            for j in range(N_CORE):
                lanes[q + (W_STATE + j) * FIELD] = states[i, j]
            lanes[q + W_CACHE_DT * FIELD] = states[i, S_CACHE_DT]
            if k % LANES == 0:  # a block's cache: its first element's
                for j in range(7):
                    lanes[b + B_CACHE + j] = states[i, S_CACHE_DT + j]
            for j in range(W_AREA + 1):  # the constants: E_CBX .. E_AREA are W_CBX .. W_AREA
                lanes[q + j * FIELD] = el[i, j]
            lanes[q + W_SLIPX * FIELD] = el[i, E_SLIPX]
            lanes[q + W_SLIPY * FIELD] = el[i, E_SLIPY]
            lanes[q + W_CX * FIELD] = el[i, E_CX]
            lanes[q + W_CY * FIELD] = el[i, E_CY]
            lanes[q + W_CZ * FIELD] = el[i, E_CZ]
    block[H_STALE] = 0.0


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
    if no foot has started). ``block`` holds the step's own arrays (:func:`new_block`: the elements, the feet,
    the lanes, the starts); ``states``, ``ring`` and ``params`` are the 1-D stepper's rows, one per element
    (``states`` the lanes' export, :func:`rows_from_lanes`; the state machine's scratch for the elements it steps).
    Returns :data:`OK`; or, having changed nothing, the first foot whose pose or depth is refused (see
    :func:`_place`), :data:`BAD_DT` for a ``dt`` outside [``MIN_DT``, ``MAX_DT``] once a
    foot has started, or :data:`BAD_SHAPE` if the poses or the outputs are
    not one row per foot (``ft``'s rows): (m, 3), (m, 4), (m, 3), (m, 3),
    or ``each`` neither (0, 3) nor one row per element.

    ``each`` (0, 3): :class:`~mudforce.steppers.contact3d.MudContacts3D`'s step. One row per element
    (:class:`~mudforce.steppers.contact3d.MudContact3D`, one foot): each element's force [N] into its row as
    well. Either way each foot's wrench is summed over its elements in element order, as ``MudContact3D``'s numpy
    step sums it, its bits.
    """
    el, ft, starts, lanes, blocks = _unpack(block)
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
    block[H_STALE] = 1.0
    for f in range(m):
        refused = _step_foot(ft, starts, lanes, blocks, states, ring, params, f, dt, forces, torques, each)
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
    each slice's feet take their step. The feet are independent (each has lanes of its own), so the results
    are :func:`step_feet`'s bit for bit.
    """
    el, ft, starts, lanes, blocks = _unpack(block)
    m = positions.shape[0]
    dt = _checked_dt(ft, m, dt)
    if dt != dt:
        return BAD_DT
    bad = _place(positions, quaternions, el, ft, starts)
    if bad != OK:
        return bad
    block[H_STALE] = 1.0
    n = chunks.shape[0]
    for c in prange(n):
        lo = m * c // n
        hi = m * (c + 1) // n
        chunks[c] = -1
        for f in range(lo, hi):
            refused = _step_foot(ft, starts, lanes, blocks, states, ring, params, f, dt, forces, torques, each)
            if refused >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
                chunks[c] = refused
    for c in range(n):
        if chunks[c] >= 0:  # pragma: no cover - every input the 1-D stepper refuses was refused above
            return int(chunks[c])
    return OK


# slots of :func:`step_one`'s address table (:func:`mudforce._kernel.addresses.address_table`)
T_BLOCK, T_STATES, T_RING, T_PARAMS, T_POSITION, T_QUATERNION, T_FORCES, T_TORQUES, T_EACH = range(9)
N_TABLE = 9


@_compiled(nogil=False, _nrt=True)
def step_one(position: np.ndarray, quaternion: np.ndarray, dt: float, table: np.ndarray) -> int:
    """:func:`step_feet` for one foot (:class:`~mudforce.steppers.contact3d.MudContact3D`), its arrays in one
    address table (slots ``T_*``: the block, the 1-D rows, the pose's (1, 3) and (1, 4) buffers, the outputs):
    the pose (``position`` (3,) [m], ``quaternion`` (4,), any strides) copied into the buffers, then the step.
    :data:`BAD_SHAPE` if the pose is not (3,) and (4,).

    Speed plumbing: called through its entry point (:func:`mudforce._kernel.addresses.entry_point`) with four
    arguments, where :func:`step_feet` takes ten through numba's dispatcher (~0.5 us less a call); the step
    itself is :func:`step_feet`, the same compiled code (its buffers have its types).
    """
    if position.shape[0] != 3 or quaternion.shape[0] != 4:
        return BAD_SHAPE
    positions = f64_2d(table, T_POSITION)
    quaternions = f64_2d(table, T_QUATERNION)
    for j in range(3):
        positions[0, j] = position[j]
    for j in range(4):
        quaternions[0, j] = quaternion[j]
    return step_feet(positions, quaternions, dt, f64_1d(table, T_BLOCK), f64_2d(table, T_STATES),
                     f64_2d(table, T_RING), f64_2d(table, T_PARAMS), f64_2d(table, T_FORCES),
                     f64_2d(table, T_TORQUES), f64_2d(table, T_EACH))


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
