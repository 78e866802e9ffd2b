"""The MuJoCo adapter's work in each step, compiled: commit the feet's depths, set the band and the forces.

:class:`mudforce.engines.mujoco.MudAdapter` calls these through the raw-address
plumbing of :mod:`mudforce.engines.mujoco._fast`, before and after each
``mj_step``: :func:`apply_mud` adds the mud force to ``xfrc_applied`` for the
step; :func:`commit_and_prepare` takes it back, commits each foot's new depth
to its contact state (:func:`mudforce._kernel.step`), and prepares the next
step: the rest band of every foot (:func:`mudforce.engines.dynamics.branch_forces`),
the tendon's friction (the band's half-width), the mid-band force and
torque, and the anchor sites 1 m above the feet. The layout of the arrays
they share with the adapter is given by the ``I_*``, ``W_*`` and ``C_*``
row indices below.
"""

from __future__ import annotations

import numpy as np

from mudforce import _kernel as K
from mudforce._kernel import forget_row_cache, load_state
from mudforce.engines.dynamics.rest_band import band_middle, branch_forces

__all__ = [
    "ANCHOR_HEIGHT",
    "C_COMMIT",
    "C_DT",
    "C_FOOT",
    "C_WEIGHT",
    "I_ANCHOR",
    "I_BODY",
    "I_SITE",
    "I_TENDON",
    "W_DOWN",
    "W_DRAG",
    "W_LAST",
    "W_MID",
    "W_TX",
    "W_TY",
    "W_UP",
    "apply_mud",
    "commit_and_prepare",
]

#: Height of the tendon anchor above the foot [m].
ANCHOR_HEIGHT = 1.0

# Compiled with the stepper's options (K._compiled), keeping the GIL (releasing and taking it back
# would cost more than it frees) and without numba's reference counting: they allocate nothing,
# and counting the array views they take would cost ~25% of their time (the callers in
# _mujoco_fast, which build those views, need it).


# rows of the adapter's integer array (ints) and work array
I_SITE, I_BODY, I_TENDON, I_ANCHOR = 0, 1, 2, 3
W_UP, W_DOWN, W_DRAG, W_MID, W_TX, W_TY, W_LAST = 0, 1, 2, 3, 4, 5, 6
# conf: dt [s], band weight [-], commit flag, then per foot: surface [m], xmin, xmax, ymin, ymax [m]
C_DT, C_WEIGHT, C_COMMIT, C_FOOT = 0, 1, 2, 3


@K._compiled(nogil=False)
def commit_and_prepare(states: np.ndarray, params: np.ndarray, out: np.ndarray, ints: np.ndarray,
                       conf: np.ndarray, work: np.ndarray, site_xpos: np.ndarray, xipos: np.ndarray,
                       xfrc: np.ndarray, site_pos: np.ndarray, frictionloss: np.ndarray) -> None:
    """After a MuJoCo step: commit each foot's depth; before the next: band, forces, anchors.

    Forces [N], torques [N m], positions [m], ``conf[C_DT]`` [s]. Called
    through :func:`mudforce.engines.mujoco._fast.after_step` (one argument from Python, see there).
    """
    n = ints.shape[1]
    dt = conf[C_DT]
    commit = conf[C_COMMIT] != 0.0
    # the adapter's velocity filter has window 1: no history to keep. No rows, and N_STATE < N_RING columns, which
    # advance refuses for a window > 1; C-contiguous (a slice of rows): one compiled signature of the ring's
    # functions, the one every other caller passes
    ring = states[:0]
    for j in range(n):
        # take back the force applied for the step just taken (see apply_mud)
        body = ints[I_BODY, j]
        xfrc[body, 2] -= work[W_MID, j]
        xfrc[body, 3] -= work[W_TX, j]
        xfrc[body, 4] -= work[W_TY, j]
        work[W_LAST, j] = work[W_MID, j]
        site = ints[I_SITE, j]
        g = conf[C_FOOT + 5 * j: C_FOOT + 5 * j + 5]
        x = site_xpos[site, 0]
        y = site_xpos[site, 1]
        inside = g[1] <= x <= g[2] and g[3] <= y <= g[4]
        depth = g[0] - site_xpos[site, 2]
        if not inside:
            states[j, :] = 0.0  # off its patch: a fresh state, as new_states gives (the next step inside starts it)
            forget_row_cache(states, j)
        elif commit or load_state(states, j).started == 0.0:
            K.step(states, ring, j, params, depth, dt, out, j)
    branch_forces(states, params, dt, conf[C_WEIGHT], work[W_UP], work[W_DOWN], work[W_DRAG])
    for j in range(n):
        lo = work[W_UP, j]
        hi = work[W_DOWN, j]
        # an inverted band (large compressive strain, k_m_w > k_m_i): no sticking is possible in between; the
        # branch of the current motion (band_middle; the state read only for an inverted band)
        inverted = not hi >= lo  # (as it always read: a NaN band counts as inverted)
        mid = band_middle(lo, hi, work[W_DRAG, j], inverted, inverted and load_state(states, j).velocity >= 0.0)
        half = 0.0 if inverted else 0.5 * (hi - lo)
        frictionloss[ints[I_TENDON, j]] = half
        body = ints[I_BODY, j]
        site = ints[I_SITE, j]
        # the force for the next step, at the sole; torque about the centre of mass:
        # r x (0, 0, F) = (r_y F, -r_x F, 0)
        rx = site_xpos[site, 0] - xipos[body, 0]
        ry = site_xpos[site, 1] - xipos[body, 1]
        work[W_MID, j] = mid
        work[W_TX, j] = ry * mid
        work[W_TY, j] = -rx * mid
        a = ints[I_ANCHOR, j]
        site_pos[a, 0] = site_xpos[site, 0]
        site_pos[a, 1] = site_xpos[site, 1]
        site_pos[a, 2] = site_xpos[site, 2] + ANCHOR_HEIGHT


@K._compiled(nogil=False)
def apply_mud(xfrc: np.ndarray, ints: np.ndarray, work: np.ndarray) -> None:
    """Add the mud force [N] and torque [N m] to ``xfrc_applied`` for one step (taken back after it)."""
    for j in range(ints.shape[1]):
        body = ints[I_BODY, j]
        xfrc[body, 2] += work[W_MID, j]
        xfrc[body, 3] += work[W_TX, j]
        xfrc[body, 4] += work[W_TY, j]
