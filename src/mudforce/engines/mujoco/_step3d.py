"""Speed plumbing of :class:`mudforce.engines.mujoco.adapter3d.MudAdapter3D`: its per-step element work, compiled.

Nothing here is new physics. :func:`prepare` is the adapter's preparation of
the next MuJoCo step (band, holds, drag, contact point, anchors, explicit
wrench; what it does and why is :mod:`mudforce.engines.mujoco.adapter3d`'s
docstring) as one loop over the feet's elements, calling the law's functions
of :mod:`mudforce.model.law3d` (one element's components; compiled through their numba
registration) and Eq. (4) through
:func:`mudforce.model.equations.nonlinear_spring_stress`, the functions the
compiled 3-D step (:mod:`mudforce._kernel.step3d`) calls. The 1-D states'
bands come from :func:`mudforce.engines.dynamics.rest_band.branch_forces_row`
(:func:`foot_band`: only where they count, summed per foot). :func:`add_wrench` adds (or,
with ``sign=-1``, takes back) the explicit wrench to ``xfrc_applied``.
"""

from __future__ import annotations

import ctypes
import glob
import math
import os
from typing import Any

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from mudforce._kernel.layout import _compiled
from mudforce._kernel.step3d import row_from_lanes
from mudforce.engines.dynamics.rest_band import band_middle, branch_forces_row
from mudforce.model.equations import nonlinear_spring_stress
from mudforce.model.law3d import (
    bearing_factor,
    horizontal_drag,
    lateral_capacity,
    shear_fraction,
    vertical_lean,
    vertical_weight,
)

__all__ = ["C_ALPHA", "C_BETA", "C_LAM_RHO", "C_SIGMA_Y", "C_SURFACE", "C_WIDTH", "N_FOOT_CONSTANTS", "N_SCRATCH",
           "add_wrench", "feet_bands", "foot_band", "gather_poses", "mat2quat_address", "place_anchors", "prepare",
           "scratch"]

# columns of the per-foot constants (those of the foot's patch; row ignored off every patch)
C_SURFACE, C_SIGMA_Y, C_ALPHA, C_BETA, C_LAM_RHO, C_WIDTH = 0, 1, 2, 3, 4, 5
N_FOOT_CONSTANTS = 6
#: rows of :func:`prepare`'s scratch
N_SCRATCH = 14


def scratch(widest: int) -> np.ndarray:
    """:func:`prepare`'s scratch for feet of at most ``widest`` elements: (``N_SCRATCH``, w).

    The rows are padded so that they do not lie a multiple of 4 KiB apart (a load would wait on an unrelated store
    to another row with the same low address bits: "4K aliasing").
    """
    width = -(-max(widest, 1) // 8) * 8
    if width % 512 == 0:
        width += 8
    return np.zeros((N_SCRATCH, width))


@_compiled(nogil=False)
def add_wrench(xfrc: np.ndarray, bodies: np.ndarray, applied: np.ndarray, sign: float) -> None:
    """``xfrc[bodies[f]] += sign * applied[f]`` for every foot (force [N], torque [N m])."""
    for f in range(bodies.shape[0]):
        for j in range(6):
            xfrc[bodies[f], j] += sign * applied[f, j]


@_compiled(nogil=False)
def place_anchors(site_xpos: np.ndarray, sites: np.ndarray, anchors: np.ndarray, dirs: np.ndarray,
                  site_pos: np.ndarray, height: float) -> None:
    """Each foot's three anchor sites ``height`` [m] from its contact site along its tendons' directions.

    ``site_xpos`` the contact sites' world positions [m] at the state the next step starts from;
    ``dirs`` (n, 3, 3) the unit directions (z, u, v) :func:`prepare` chose; written: the anchors' rows of
    ``site_pos`` (world-body sites: world positions [m]).
    """
    for f in range(sites.shape[0]):
        for axis in range(3):
            a = anchors[f, axis]
            for c in range(3):
                site_pos[a, c] = site_xpos[sites[f], c] + height * dirs[f, axis, c]


def mat2quat_address(mj: Any) -> int:
    """The address of MuJoCo's C function ``mju_mat2Quat`` in its shared library, or 0 where it is not found.

    ``mj`` the ``mujoco`` module. The library is the one its bindings load
    (``libmujoco.so*``, ``libmujoco*.dylib`` or ``mujoco.dll`` beside them):
    loading it again gives the same one. :func:`gather_poses` calls the
    function there, once per foot, for ~10 ns instead of the binding's ~1 us:
    the same code, the same bits.
    """
    folder = os.path.dirname(mj.__file__)
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        for path in sorted(glob.glob(os.path.join(folder, pattern))):
            try:
                fn = ctypes.CDLL(path).mju_mat2Quat
            except (OSError, AttributeError):
                continue
            return int(ctypes.cast(fn, ctypes.c_void_p).value or 0)
    return 0


def _call_pp_typing(typingctx: Any, address: Any, a: Any, b: Any) -> Any:
    """Typing and code of :data:`_call_pp`."""
    if not all(isinstance(x, types.Integer) for x in (address, a, b)):
        return None

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        byte_ptr = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.VoidType(), [byte_ptr, byte_ptr])
        fn = builder.inttoptr(args[0], fnty.as_pointer())
        builder.call(fn, [builder.inttoptr(args[1], byte_ptr), builder.inttoptr(args[2], byte_ptr)])
        return context.get_dummy_value()

    return types.void(address, a, b), codegen


#: In compiled code, ``f(a, b)`` for the C function ``void f(void *, void *)`` at integer address ``f``, on the
#: integer addresses ``a`` and ``b`` (numba has no public call through an integer address).
_call_pp: Any = intrinsic(_call_pp_typing)


@_compiled(nogil=False)
def gather_poses(geom_xpos: np.ndarray, geom_xmat: np.ndarray, gids: np.ndarray, pos: np.ndarray,
                 mats: np.ndarray, quats: np.ndarray, mat2quat: int) -> None:
    """The foot geoms' positions [m], rotation matrices (row by row) and quaternions into ``pos`` (n, 3), ``mats``
    (n, 9) and ``quats`` (n, 4).

    ``geom_xpos`` and ``geom_xmat`` are MuJoCo's ``data`` arrays, ``gids`` the feet's geom ids: the values
    ``data.geom_xpos[gids]`` and ``data.geom_xmat[gids]`` give, without allocating. The quaternions are
    MuJoCo's ``mju_mat2Quat`` of the matrices, called at address ``mat2quat``
    (:func:`mat2quat_address`); with 0, ``quats`` is left alone (the caller calls the binding).
    ``pos``, ``mats``, ``quats`` must be C-contiguous.
    """
    for f in range(gids.shape[0]):
        g = gids[f]
        for j in range(3):
            pos[f, j] = geom_xpos[g, j]
        for j in range(9):
            mats[f, j] = geom_xmat[g, j]
    if mat2quat != 0:
        q0 = quats.ctypes.data
        m0 = mats.ctypes.data
        for f in range(gids.shape[0]):
            _call_pp(mat2quat, q0 + 32 * f, m0 + 72 * f)  # rows of 4 and 9 doubles


@_compiled(nogil=False)
def foot_band(states: np.ndarray, params: np.ndarray, dt: float, lo: int, hi: int, r: np.ndarray, nb: np.ndarray,
              area: np.ndarray, lanes: np.ndarray, entries: np.ndarray, side: np.ndarray) -> tuple[float, float, float]:
    """A foot's vertical band and drag for the coming step [N]: ``(F_up, F_down, F_drag)``; their sideways parts
    into ``side`` (6,) [N]: ``(x, y)`` of the up end, of the down end and of the drag.

    The sums over elements ``lo:hi`` of each element's band and drag
    (:func:`mudforce.engines.dynamics.rest_band.branch_forces_row` on its 1-D state
    row of ``states``/``params``, weight 1: a stress [Pa]) times its
    downward-facing area ``A_i max(-n_z, 0)`` (``r`` the foot's rotation, row
    by row; ``nb``, ``area`` the elements' body-frame normals and areas).
    An element that faces no way down adds ``0`` times its band, which
    changes no sum, so its band is not computed; nor is the band at the
    step's start, which weight 1 multiplies by 0 (see ``branch_forces_row``).
    The sums are those of ``branch_forces`` over every element, bit for bit.
    The sideways parts: each element's share times ``vertical_lean(n_z) (n_x, n_y)``
    (:func:`mudforce.model.law3d.vertical_element_force`: the vertical stress in 3D-RFT's direction).

    The 3-D step keeps the elements' states in its lanes and leaves the rows behind
    (:mod:`mudforce._kernel.step3d`): each row read here is written from ``lanes`` first (element ``i`` at
    ``entries[i]``, :func:`mudforce._kernel.step3d.row_from_lanes`), and only those.
    """
    f_up = f_down = f_drag = 0.0
    for j in range(6):
        side[j] = 0.0
    for i in range(lo, hi):
        nz = r[6] * nb[i, 0] + r[7] * nb[i, 1] + r[8] * nb[i, 2]
        w = area[i] * vertical_weight(nz)
        if w != 0.0:
            row_from_lanes(lanes, entries[i], states, i)
            up, down, drag = branch_forces_row(states, params, i, dt, 1.0, False)
            f_up += w * up
            f_down += w * down
            f_drag += w * drag
            lean = w * vertical_lean(nz)
            lx = lean * (r[0] * nb[i, 0] + r[1] * nb[i, 1] + r[2] * nb[i, 2])
            ly = lean * (r[3] * nb[i, 0] + r[4] * nb[i, 1] + r[5] * nb[i, 2])
            side[0] += lx * up
            side[1] += ly * up
            side[2] += lx * down
            side[3] += ly * down
            side[4] += lx * drag
            side[5] += ly * drag
    return f_up, f_down, f_drag


@_compiled(nogil=False)
def feet_bands(states: np.ndarray, params: np.ndarray, dt: float, patch: np.ndarray, k: int, starts: np.ndarray,
               mats: np.ndarray, nb: np.ndarray, area: np.ndarray, bands: np.ndarray, lanes: np.ndarray,
               entries: np.ndarray) -> None:
    """:func:`foot_band` of every foot in patch ``k`` (``patch[f] == k``) into ``bands[f]`` (n, 9) [N]: the band
    and drag, then their sideways parts.

    ``states``, ``params``: patch ``k``'s 1-D rows (one per element of every
    foot); ``mats`` (n, 9) the feet's rotations; ``starts`` each foot's
    element rows; ``dt`` [s]; ``lanes``, ``entries`` where the 3-D step keeps their states (see :func:`foot_band`).
    """
    for f in range(patch.shape[0]):
        if patch[f] == k:
            bands[f, 0], bands[f, 1], bands[f, 2] = foot_band(states, params, dt, starts[f], starts[f + 1], mats[f],
                                                                nb, area, lanes, entries, bands[f, 3:])


@_compiled(nogil=False)
def prepare(pos: np.ndarray, mats: np.ndarray, last_pos: np.ndarray, dt: float, starts: np.ndarray,
            cb: np.ndarray, nb: np.ndarray, area: np.ndarray, patch: np.ndarray, const: np.ndarray,
            states: np.ndarray, params: np.ndarray, k_band: int, bands: np.ndarray, velocity_z: np.ndarray,
            u: np.ndarray, xipos: np.ndarray, xpos: np.ndarray, xmat: np.ndarray, bodies: np.ndarray, sites: np.ndarray,
            tendons: np.ndarray, site_pos: np.ndarray, frictionloss: np.ndarray, rest_speed: float, band: np.ndarray,
            holds: np.ndarray, applied: np.ndarray, dirs: np.ndarray, scratch: np.ndarray, lanes: np.ndarray,
            entries: np.ndarray) -> None:
    """The next step's bands, holds, contact points, tendon directions and explicit wrench, foot by foot.

    ``pos`` (n, 3) [m] and ``mats`` (n, 9) the foot geoms' poses; ``last_pos``
    the previous ones (updated here); ``dt`` [s]; ``starts`` each foot's
    element rows; ``cb``, ``nb`` (E, 3), ``area`` (E,) the elements in the
    geom's frame [m], [-], [m^2]; ``patch`` (n,) each foot's patch or -1;
    ``const`` (n, ``N_FOOT_CONSTANTS``) its patch's constants (``C_*``);
    ``states``, ``params`` patch ``k_band``'s 1-D rows: the band of a foot in
    that patch is :func:`foot_band` on them, here; that of a foot in another
    patch was put in ``bands`` (n, 9) [N] by :func:`feet_bands` (the band's sideways parts, :func:`foot_band`:
    every foot's row is written);
    ``velocity_z`` (n,) written [m/s];
    ``u`` (n, 2) each foot's last horizontal direction (updated). MuJoCo's
    arrays: ``xipos``, ``xpos``, ``xmat`` (data), ``site_pos``,
    ``frictionloss`` (model, written). Written: ``band`` (2, n) [N],
    ``holds`` (n, 2) [N], ``applied`` (n, 6) [N], [N m], ``dirs`` (n, 3, 3)
    (the anchors are placed along them by :func:`place_anchors`, from where
    MuJoCo puts the contact site);
    ``scratch`` (:data:`N_SCRATCH`, at least the most elements of a foot):
    a foot's submerged elements side by side, for loops without branches; ``lanes``, ``entries`` where the 3-D
    step keeps patch ``k_band``'s states (see :func:`foot_band`).
    """
    n = pos.shape[0]
    # the scratch's rows as arrays of their own (so that the compiler sees them apart and vectorises)
    s_nx, s_ny, s_nz, s_cx, s_cy, s_cz = scratch[0], scratch[1], scratch[2], scratch[3], scratch[4], scratch[5]
    s_depth, s_area, s_spring, s_hu, s_hv = scratch[6], scratch[7], scratch[8], scratch[9], scratch[10]
    s_gx, s_gy, s_wet = scratch[11], scratch[12], scratch[13]
    for f in range(n):
        px, py, pz = pos[f, 0], pos[f, 1], pos[f, 2]
        vx = (px - last_pos[f, 0]) / dt
        vy = (py - last_pos[f, 1]) / dt
        vz = (pz - last_pos[f, 2]) / dt
        last_pos[f, 0], last_pos[f, 1], last_pos[f, 2] = px, py, pz
        velocity_z[f] = vz
        speed = math.sqrt(vx * vx + vy * vy)
        if speed > rest_speed:
            u[f, 0] = vx / speed
            u[f, 1] = vy / speed
        ux, uy = u[f, 0], u[f, 1]
        k = patch[f]
        r = mats[f]
        lo, hi = starts[f], starts[f + 1]
        f_up = f_down = f_drag = 0.0
        if k >= 0:
            if k == k_band:
                f_up, f_down, f_drag = foot_band(states, params, dt, lo, hi, r, nb, area, lanes, entries,
                                                 bands[f, 3:])
            else:
                f_up, f_down, f_drag = bands[f, 0], bands[f, 1], bands[f, 2]
        total = qx = qy = qz = 0.0
        hold_u = hold_v = 0.0
        fx = fy = 0.0
        lowest = math.inf
        lx = ly = lz = 0.0
        surface = const[f, C_SURFACE]
        sigma_y, alpha, beta = const[f, C_SIGMA_Y], const[f, C_ALPHA], const[f, C_BETA]
        lam_rho, width = const[f, C_LAM_RHO], const[f, C_WIDTH]
        m = 0  # the foot's submerged elements, gathered into the scratch rows
        for i in range(lo, hi):
            cx = px + r[0] * cb[i, 0] + r[1] * cb[i, 1] + r[2] * cb[i, 2]
            cy = py + r[3] * cb[i, 0] + r[4] * cb[i, 1] + r[5] * cb[i, 2]
            cz = pz + r[6] * cb[i, 0] + r[7] * cb[i, 1] + r[8] * cb[i, 2]
            if cz < lowest:
                lowest = cz
                lx, ly, lz = cx, cy, cz
            if k < 0:
                continue
            depth = surface - cz
            if depth > 0.0:  # only submerged elements are loaded (Eq. (4) is 0 at and above the surface)
                nx = r[0] * nb[i, 0] + r[1] * nb[i, 1] + r[2] * nb[i, 2]
                ny = r[3] * nb[i, 0] + r[4] * nb[i, 1] + r[5] * nb[i, 2]
                nz = r[6] * nb[i, 0] + r[7] * nb[i, 1] + r[8] * nb[i, 2]
                s_nx[m], s_ny[m], s_nz[m] = nx, ny, nz
                s_cx[m], s_cy[m], s_cz[m] = cx, cy, cz
                s_depth[m] = depth
                s_area[m] = area[i]
                m += 1
        # over the gathered elements, in loops without branches (vectorised): Eq. (4), the holds, the drag
        for j in range(m):
            s_spring[j] = nonlinear_spring_stress(alpha, beta, s_depth[j], width)
        for j in range(m):
            nx, ny, nz, spring, a_j = s_nx[j], s_ny[j], s_nz[j], s_spring[j], s_area[j]
            s_hu[j] = a_j * lateral_capacity(sigma_y, shear_fraction(nx, ny, nz, ux, uy), spring,
                                             bearing_factor(nx, ny, nz, ux, uy))
            s_hv[j] = a_j * lateral_capacity(sigma_y, shear_fraction(nx, ny, nz, -uy, ux), spring,
                                             bearing_factor(nx, ny, nz, -uy, ux))
            gx, gy = horizontal_drag(lam_rho, 1.0, nx, ny, vx, vy)
            s_gx[j] = gx * a_j
            s_gy[j] = gy * a_j
            s_wet[j] = (a_j * vertical_weight(nz)) * spring
        # summed in element order (an element above the surface would add zeros, which change no sum)
        for j in range(m):
            wet = s_wet[j]
            total += wet
            qx += wet * s_cx[j]
            qy += wet * s_cy[j]
            qz += wet * s_cz[j]
            hold_u += s_hu[j]
            hold_v += s_hv[j]
            fx += s_gx[j]
            fy += s_gy[j]
        if total > 0.0:
            qx, qy, qz = qx / total, qy / total, qz / total
        else:
            qx, qy, qz = lx, ly, lz
        # an inverted band (k_m_w e > k_m_i e + spring): no sticking, the branch of the motion (band_middle)
        inverted = f_down < f_up
        falling = vz <= 0.0
        mid = band_middle(f_up, f_down, f_drag, inverted, falling)
        half = 0.0 if inverted else 0.5 * (f_down - f_up)
        # the mid-band force's sideways part (law3d.vertical_element_force): the same rule on its ends' sums
        fx += band_middle(bands[f, 3], bands[f, 5], bands[f, 7], inverted, falling)
        fy += band_middle(bands[f, 4], bands[f, 6], bands[f, 8], inverted, falling)
        if k < 0:
            mid = half = hold_u = hold_v = fx = fy = 0.0
        band[0, f] = f_up
        band[1, f] = f_down
        holds[f, 0] = hold_u
        holds[f, 1] = hold_v
        # the explicit force acts below the geom's centre at the contact point's height; torque about the COM
        b = bodies[f]
        ax, ay, az = px - xipos[b, 0], py - xipos[b, 1], qz - xipos[b, 2]
        applied[f, 0], applied[f, 1], applied[f, 2] = fx, fy, mid
        applied[f, 3] = ay * mid - az * fy
        applied[f, 4] = az * fx - ax * mid
        applied[f, 5] = ax * fy - ay * fx
        frictionloss[tendons[f, 0]] = half
        frictionloss[tendons[f, 1]] = hold_u
        frictionloss[tendons[f, 2]] = hold_v
        dirs[f, 0, 0], dirs[f, 0, 1], dirs[f, 0, 2] = 0.0, 0.0, 1.0
        dirs[f, 1, 0], dirs[f, 1, 1], dirs[f, 1, 2] = ux, uy, 0.0
        dirs[f, 2, 0], dirs[f, 2, 1], dirs[f, 2, 2] = -uy, ux, 0.0
        # the contact site in the body's frame: R^T (point - xpos)
        dx, dy, dz = qx - xpos[b, 0], qy - xpos[b, 1], qz - xpos[b, 2]
        s = sites[f]
        site_pos[s, 0] = xmat[b, 0] * dx + xmat[b, 3] * dy + xmat[b, 6] * dz
        site_pos[s, 1] = xmat[b, 1] * dx + xmat[b, 4] * dy + xmat[b, 7] * dz
        site_pos[s, 2] = xmat[b, 2] * dx + xmat[b, 5] * dy + xmat[b, 7 + 1] * dz
