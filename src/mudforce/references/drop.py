"""An independent, high-accuracy solution of a foot dropped into mud, for the tests (:func:`exact_drop`).

Like :mod:`mudforce.references.trajectory` (the model on a prescribed trajectory), this
re-implements the model from ``docs/model.md`` without the compiled stepper
(:mod:`mudforce._kernel`) or the built-in engine (:mod:`mudforce.engines.dynamics`),
so that the tests can catch bugs in either: each phase of the hybrid system
(free fall, intrusion, withdrawal, after necking) is an ODE integrated with
SciPy's DOP853 to tight tolerances, its end located as an integrator event,
and sticking is solved in closed form. It shares with the stepper only the
post-necking filter's impulse response
(:func:`mudforce.model.equations.neck_filter_response`, Eq. (7)), itself tested
against a numerical integration. It is pure Python and slow (tens of
milliseconds per phase).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number, number_within, real_array, shown
from mudforce.model.bounds import bounded_depth, check_gravity, max_samples
from mudforce.model.equations import neck_filter_response
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.model.shapes import Shape

__all__ = ["GRAVITY", "ExactDrop", "exact_drop", "exact_drop_3d"]

#: Standard gravity [m/s^2] (the same value as :data:`mudforce.engines.dynamics.GRAVITY`).
GRAVITY = 9.81


@dataclass(frozen=True)
class ExactDrop:
    """The exact (event-driven, high-accuracy) solution of a drop under constant load.

    Attributes
    ----------
    events : list of (float, str, float, float, float)
        ``(time [s], new phase, depth [m], velocity [m/s], strain [m])`` at each phase change.
    time, depth, velocity, force : ndarray
        Dense output on the requested grid [s, m, m/s, N].
    end_depth : float
        Depth at the end of the requested duration [m], whether or not the foot rests there.
    final_depth : float
        Depth where the foot comes to rest for good [m] (if it does within the duration; NaN otherwise).
    at_rest : bool
        Whether the foot is stuck (at rest in the mud, phase STUCK or STUCK_NECKED) at the end of the duration.
    """

    events: list[tuple[float, str, float, float, float]]
    time: np.ndarray
    depth: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    end_depth: float
    final_depth: float
    at_rest: bool

    @property
    def rest_depth(self) -> float:
        """Depth where the foot rests at the end of the duration [m]; NaN if it is moving there (:attr:`at_rest`).

        The same rule as the engines' :attr:`mudforce.engines.dynamics.FootResult.rest_depth`; use
        :attr:`end_depth` for the depth at the end in any case.
        """
        return self.end_depth if self.at_rest else math.nan


def exact_drop(
    mass: float,
    params: MudParameters,
    foot: Foot | None = None,
    *,
    duration: float = 8.0,
    height: float = 0.0,
    dt: float = 1e-3,
    gravity: float = GRAVITY,
    rtol: float = 1e-11,
) -> ExactDrop:
    """The drop's exact solution, phase by phase, with SciPy's DOP853 and event location.

    The foot falls freely from ``height``, sinks on the
    intrusion branch until it stops (event ``dz_i/dt = 0``); there it
    sticks if the withdrawal-branch force ``S k_m_w e`` is at most ``m g``,
    and otherwise rebounds on the withdrawal branch. While stuck the Maxwell
    strain relaxes in closed form, ``e(t) = e_s exp(-(t - t_s) / tau_i)``,
    and the foot sinks again when the intrusion force falls to ``m g``, at
    ``e* = (m g / S - alpha (z / H)^beta) / k_m_i``, i.e. after
    ``tau_i ln(e_s / e*)``; if ``e* <= 0`` it stays for good. This is an
    implementation independent of :func:`mudforce.engines.dynamics.simulate_foot` (different
    integrator, closed-form sticking), used to check it.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0.
    params : MudParameters
        Mud parameters.
    foot : Foot, optional
        Foot geometry; the paper's cuboid by default.
    duration : float
        Time span [s], at least ``dt``.
    height : float
        Release height of the foot's bottom above the surface [m], in [0, 100].
    dt : float
        Grid of the dense output [s], > 0 (at most 1e8 points).
    gravity : float
        [m/s^2], > 0 (the foot must fall).
    rtol : float
        Relative tolerance of DOP853, within [1e-13, 0.1].

    Notes
    -----
    A rebound that breaks the neck (Eq. (9)) continues with the closed-form
    post-necking force (Eq. (7)) until the foot stops again; there it sinks
    again on the intrusion branch with the necked mud's ``z_m`` (docs/model.md),
    or sticks, the band's ends then found by a 1 ms scan and Brent's method.
    """
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if foot is None:
        foot = Foot.paper()
    elif not isinstance(foot, Foot):
        raise InputError(f"foot must be a Foot (or None for the paper's cuboid), got {type(foot).__name__}")
    mass, duration, height, dt, gravity, rtol = _checked_numbers(mass, duration, height, dt, gravity, rtol)
    return _solve_drop(mass, params, np.zeros(1), np.array([foot.area]), foot.width, duration=duration,
                       height=height, dt=dt, gravity=gravity, rtol=rtol)


def _checked_numbers(mass: Any, duration: Any, height: Any, dt: Any, gravity: Any, rtol: Any
                     ) -> tuple[float, float, float, float, float, float]:
    """A drop's numbers as floats, each refused in one line if it is not finite or out of its range."""
    mass = finite_number(mass, "mass", "kg", positive=True)
    duration = finite_number(duration, "duration", "s", positive=True)
    height = bounded_depth(height, "height", of=" of the mud surface")  # simulate_foot's bound: 1e12 m was taken
    height = finite_number(height, "height", "m", nonnegative=True)
    dt = finite_number(dt, "dt", "s", positive=True)
    gravity = check_gravity(gravity, positive=True)  # the engines' bound: 1e200 raised IndexError, 1e6 sank 1.9 km
    # scipy raises a tolerance under 100 ulp to it with a UserWarning only; one of 1 or more controls nothing
    rtol = number_within(rtol, "rtol", 1e-13, 0.1, "-")
    max_samples(duration, dt)  # the engines' bounds: at least one step dt, at most 1e8 samples
    return mass, duration, height, dt, gravity, rtol


def exact_drop_3d(
    mass: float,
    params: MudParameters,
    shape: Shape,
    *,
    orientation: Any = (1.0, 0.0, 0.0, 0.0),
    bottom: float | None = None,
    duration: float = 8.0,
    height: float = 0.0,
    dt: float = 1e-3,
    gravity: float = GRAVITY,
    rtol: float = 1e-11,
) -> ExactDrop:
    """The exact drop of a rigid foot of any shape, upright, straight down: the 3-D law on its elements.

    The foot keeps its orientation (the shape's body frame, no tilt) and has no sideways speed, so by
    symmetry it moves vertically: one degree of freedom, the depth ``z`` of its reference point. Every
    surface element ``i`` carries the paper's whole state from the instant it submerges (its own Maxwell
    strain, suction, necking, the post-necking decay, sticking), on its own depth ``z + o_i``, and its stress
    acts on its downward projection ``A_i max(-n_z, 0)`` (docs/model.md, "Mud in 3-D"; placed by
    :func:`mudforce.references.contact3d.place` and :func:`~mudforce.references.contact3d.vertical_weights`);
    a symmetric foot has no sideways force and no torque (a shape and orientation whose elements at some depth
    are not balanced about the vertical through the body origin are refused). Elements at one depth share one
    state. The
    phases and their events are those of :func:`exact_drop` (one solver for both: the 1-D drop is this
    with one element of area ``S``), with every element's touchdown, surface crossing and necking an event
    of its own, and the foot stuck while the load lies between the sums of the elements' bands.

    Parameters
    ----------
    mass : float
        Foot mass [kg], > 0.
    params : MudParameters
        Mud parameters.
    shape : Shape
        The foot's surface (:mod:`mudforce.model.shapes`), body frame; its ``width`` is ``H`` of Eq. (4).
    orientation : array_like, shape (4,)
        The foot's fixed orientation, a unit quaternion ``(w, x, y, z)`` [-] (MuJoCo's order; a capsule lying
        along x: ``(cos 45deg, 0, sin 45deg, 0)``); upright by default.
    bottom : float, optional
        Height of the reference point above the body origin in the world frame [m] (negative: below it): its
        depth is the result's ``depth``, and it is released ``height`` above the surface; by default the lowest
        element centroid (a sphere of radius ``r``: pass ``-r`` for its lowest point, as the engines report);
        within +-100 m. Every loaded element must start at or above the surface (the release is a fall).
    duration, height, dt, gravity, rtol
        As for :func:`exact_drop` ([s], [m], [s], [m/s^2], [-]).

    Returns
    -------
    ExactDrop
        ``depth``: the reference point's [m]; ``events``: ``(time, phase, depth, velocity, strain)`` with the
        deepest element's strain [m].
    """
    from mudforce.references.contact3d import place, vertical_weights

    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if not isinstance(shape, Shape):
        raise InputError(f"shape must be a mudforce.model.shapes.Shape, got {type(shape).__name__}")
    if shape.width is None:
        raise InputError("this shape has no width H for Eq. (4); build it with a mudforce.model.shapes constructor")
    mass, duration, height, dt, gravity, rtol = _checked_numbers(mass, duration, height, dt, gravity, rtol)
    quat = real_array(orientation, "orientation", "-")
    if quat.shape != (4,) or not np.all(np.isfinite(quat)) or abs(float(np.sqrt(np.sum(quat * quat))) - 1.0) > 1e-6:
        raise InputError(f"orientation must be a unit quaternion (w, x, y, z), got {shown(orientation)}")
    offsets, _, normals, depth = place(shape, np.zeros((1, 3)), quat[None, :], 0.0)  # each centroid's depth: -c_z
    weights = vertical_weights(np.asarray(shape.areas, dtype=np.float64), normals[0])
    loaded = weights > 0.0
    if not np.any(loaded):
        raise InputError("the shape has no downward-facing element: nothing carries it")
    _check_symmetric(depth[0, loaded], offsets[0, loaded, :2], weights[loaded])
    ref = float(-depth[0].max()) if bottom is None else bounded_depth(bottom, "bottom", of=" of the body origin")
    # element depth = reference point's depth + offset, offset = ref - c_z <= 0 for elements above it
    offset = np.round(depth[0, loaded] + ref, 12)  # one level for elements within 1e-12 m (a rotation's rounding)
    if float(offset.max()) > height:  # the solver takes every level FREE at release: one below fell through the mud
        raise InputError(f"with bottom={shown(bottom)} m and height={shown(height)} m a loaded element starts "
                         f"{float(offset.max()) - height:.6g} m below the surface; expected the foot released above "
                         "the mud (bottom at or below its lowest element centroid, or a larger height)")
    levels, which = np.unique(offset, return_inverse=True)
    summed = np.bincount(which, weights=weights[loaded], minlength=levels.size)
    order = np.argsort(-levels, kind="stable")  # the deepest level first
    return _solve_drop(mass, params, levels[order], summed[order], float(shape.width), duration=duration,
                       height=height, dt=dt, gravity=gravity, rtol=rtol)


def _check_symmetric(depth: np.ndarray, horizontal: np.ndarray, weights: np.ndarray) -> None:
    """Refuse, in one line, loaded elements (their depths below the body origin [m], horizontal offsets (n, 2) [m]
    and vertical weights [m^2]) whose mud force would have a torque about the vertical through the body origin.

    The elements at one depth share one state, so one stress: the torque vanishes at every instant only if each
    depth's weighted horizontal offset ``sum w_i (x_i, y_i)`` does (a foot symmetric about that vertical); the law's
    horizontal force is zero on a straight vertical motion anyway (no horizontal slip or drag). Depths within 1e-9 m
    count as one (mirror twins of a rotation differ by its rounding), and a sum within 1e-9 of ``sum w_i`` times the
    foot's horizontal reach as zero (rounding: 1.4e-15 for a lying capsule). Without it an asymmetric or tilted foot
    was dropped straight as if it were symmetric, its torque left out.
    """
    order = np.argsort(depth, kind="stable")
    group = np.concatenate([[0], np.cumsum(np.diff(depth[order]) > 1e-9)])
    reach = float(np.max(np.hypot(horizontal[:, 0], horizontal[:, 1])))
    moment = np.zeros((int(group[-1]) + 1, 2))
    np.add.at(moment, group, weights[order, None] * horizontal[order])
    total = np.bincount(group, weights=weights[order])
    off = np.hypot(moment[:, 0], moment[:, 1]) / total  # each depth's centre of load off the vertical [m]
    bad = np.flatnonzero(off > 1e-9 * reach)
    if bad.size:
        g = int(bad[np.argmax(off[bad])])
        level, far = -float(depth[order][np.argmax(group == g)]), float(off[g])
        raise InputError(f"exact_drop_3d drops a foot with no torque from the mud: at this orientation the loaded "
                         f"elements at z = {level:.6g} m (from the body origin, world axes) bear {far:.3g} m "
                         "off the vertical through it; expected a shape symmetric about that vertical (upright, or "
                         "turned about an axis of its symmetry)")


_FREE, _CONTACT, _NECKED = 0, 1, 2  # each element level's contact state (docs/model.md's state machine)


def _solve_drop(mass: float, params: MudParameters, offsets: np.ndarray, weights: np.ndarray, width: float, *,
                duration: float, height: float, dt: float, gravity: float, rtol: float) -> ExactDrop:
    """The drop of a rigid body whose loaded elements lie at depths ``z + offsets`` [m], phase by phase.

    ``offsets`` (G,) [m], the deepest first (0 for the reference point's own level), ``weights`` (G,) each
    level's vertical weight ``sum A_i max(-n_z, 0)`` [m^2], ``width`` ``H`` of Eq. (4) [m]; inputs checked by
    the callers (:func:`exact_drop`: one level of area ``S``; :func:`exact_drop_3d`). The body's phases:
    FREE (falling, no level in contact) and INTRUSION while it moves down, WITHDRAWAL (NECKED when every
    level in contact has necked) while it moves up, STUCK (STUCK_NECKED with a necked level) at rest.
    """
    from scipy.integrate import solve_ivp

    q = params
    off = np.asarray(offsets, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    levels = off.size
    load = mass * gravity
    tau_i = q.b_m_i / q.k_m_i
    tau_w = q.b_m_w / q.k_m_w
    lr = q.lambda_ * q.rho_m
    # DOP853's absolute tolerance [m, m/s]: 1e-14, or a millionth of the strain m g / (S k_m_i) when that is smaller
    # (5 kg under 1e-8 m/s^2 sinks 1e-21 m; at 1e-14 every phase ended where it began)
    atol = min(1e-14, 1e-6 * load / (float(np.sum(w)) * q.k_m_i))
    mode = np.full(levels, _FREE, dtype=np.int8)
    wet = np.zeros(levels, dtype=bool)  # below the surface: the drag acts (Eq. (5))
    nk = np.zeros((levels, 3))  # each necked level's (t_n, v_m0, z_m at necking)

    def spring(d: np.ndarray) -> np.ndarray:
        """Eq. (4) [Pa] on each level's depth."""
        out: np.ndarray = q.alpha * (np.maximum(d, 0.0) / width) ** q.beta
        return out

    def neck(tt: float, g: int, nk_: np.ndarray) -> tuple[float, float]:
        """A necked level's post-necking stress [Pa] and z_m [m], Eq. (7)."""
        g_, g_int = neck_filter_response(tt - nk_[g, 0], q.zeta, q.omega_0)
        return q.b_m_w * nk_[g, 1] * g_, nk_[g, 2] + nk_[g, 1] * g_int

    def stress(down: bool, tt: float, z: float, v: float, e: np.ndarray, mode_: np.ndarray, wet_: np.ndarray,
               nk_: np.ndarray) -> np.ndarray:
        """Each level's stress [Pa], Eq. (8), on the intrusion (``down``) or withdrawal branch."""
        drag = np.where(wet_, lr * v * abs(v), 0.0)
        contact = mode_ == _CONTACT
        if down:
            return np.where(contact, q.k_m_i * e + spring(z + off) + drag, 0.0)
        out = np.where(contact, q.k_m_w * e + drag, 0.0)
        for g in np.flatnonzero(mode_ == _NECKED).tolist():
            out[g] = neck(tt, g, nk_)[0] + drag[g]
        return out

    def force(down: bool, tt: float, y: np.ndarray, mode_: np.ndarray, wet_: np.ndarray, nk_: np.ndarray) -> float:
        return float(np.sum(w * stress(down, tt, y[0], y[1], y[2:], mode_, wet_, nk_)))

    def make_rhs(down: bool) -> Any:
        tau = tau_i if down else tau_w
        contact = mode == _CONTACT

        def rhs(tt: float, y: np.ndarray) -> np.ndarray:
            out = np.empty_like(y)
            out[0] = y[1]
            out[1] = (load - force(down, tt, y, mode, wet, nk)) / mass
            out[2:] = np.where(contact, y[1] - y[2:] / tau, 0.0)
            return out

        return rhs

    def event(fn: Any, direction: float) -> Any:
        fn.terminal = True
        fn.direction = direction
        return fn

    def moving_events(down: bool) -> list[tuple[str, Any]]:
        """The events of a moving phase, named: the stop; the next level to touch down (down), or the first
        level to neck and the next to leave the surface (up)."""
        if down:
            out = [("stop", event(lambda _t, y: y[1], -1.0))]
            free = np.flatnonzero(mode == _FREE)
            if free.size:
                g = int(free[np.argmax(off[free])])
                out.append(("touchdown", event(lambda _t, y, g=g: y[0] + off[g], 1.0)))
            return out
        out = [("stop", event(lambda _t, y: y[1], 1.0))]
        contact = np.flatnonzero(mode == _CONTACT)
        if contact.size:
            def margin(_t: float, y: np.ndarray, c: np.ndarray = contact) -> float:
                drag = np.where(wet[c], lr * y[1] * abs(y[1]), 0.0)
                return float(np.min(q.k_m_w * y[2 + c] + drag)) + q.sigma_y

            out.append(("necking", event(margin, -1.0)))
        under = np.flatnonzero(wet)
        if under.size:
            g = int(under[np.argmin(off[under])])
            out.append(("surface", event(lambda _t, y, g=g: y[0] + off[g], -1.0)))
        return out

    def band(tt: float, z: float, e: np.ndarray) -> tuple[float, float]:
        """The forces that hold the body at rest, ``(F_up, F_down)`` [N]: the levels' bands summed."""
        up = np.where(mode == _CONTACT, q.k_m_w * e, 0.0)
        strain = e.copy()
        for g in np.flatnonzero(mode == _NECKED).tolist():
            up[g], zm = neck(tt, g, nk)
            strain[g] = z + off[g] - zm
        down = np.where((mode != _FREE) & wet, q.k_m_i * strain + spring(z + off), 0.0)
        return float(np.sum(w * up)), float(np.sum(w * down))

    def moving_label(down: bool) -> str:
        if down:
            return "INTRUSION" if np.any(mode == _CONTACT) else "FREE"
        return "WITHDRAWAL" if np.any(mode == _CONTACT) else "NECKED"

    def at_rest(tt: float, y: np.ndarray, *, leaving: bool = False) -> str:
        """The body stopped at ``tt``: stuck, or moving on (the levels' transitions applied to ``y``);
        ``leaving``: the end of a stuck spell, so it moves on (down if the load exceeds ``F_down``, else up)."""
        z, e = float(y[0]), y[2:]
        f_up, f_down = band(tt, z, e)
        if load > f_down * (1.0 + (0.0 if leaving else 1e-12)):  # down (a necked level in the mud keeps z_m)
            for g in range(levels):
                if mode[g] == _NECKED and wet[g]:
                    mode[g], e[g] = _CONTACT, z + off[g] - neck(tt, g, nk)[1]
                elif mode[g] != _FREE and not wet[g]:
                    mode[g], e[g] = _FREE, 0.0
            return moving_label(True)
        if leaving or load < f_up:
            return moving_label(False)
        dry = (mode == _CONTACT) & ~wet  # at rest on the intrusion branch above the surface: FREE
        mode[dry], e[dry] = _FREE, 0.0
        return "STUCK_NECKED" if np.any(mode == _NECKED) else "STUCK"

    def resting(z: float) -> Any:
        def piece(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            return np.full_like(tt, z), np.zeros_like(tt), np.full_like(tt, load)

        return piece

    def moving(dense: Any, down: bool) -> Any:
        mode_, wet_, nk_ = mode.copy(), wet.copy(), nk.copy()  # the levels' states over this phase

        def piece(tt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            yy = dense(tt)
            ff = np.array([force(down, a, yy[:, k], mode_, wet_, nk_) for k, a in enumerate(tt)])
            return yy[0], yy[1], ff

        return piece

    pieces: list[tuple[float, float, Any]] = []  # (t0, t1, callable t -> (z, v, F))
    events: list[tuple[float, str, float, float, float]] = []
    t = 0.0
    y = np.zeros(2 + levels)
    y[0] = -float(height)
    phase = "FREE"
    events.append((t, phase, float(y[0]), 0.0, 0.0))
    final = math.nan
    horizon = duration
    guard = 0
    stalled = 0  # moving phases in a row that ended where they began
    while t < horizon and guard < 10000:
        guard += 1
        if phase in ("FREE", "INTRUSION", "WITHDRAWAL", "NECKED"):
            down = phase in ("FREE", "INTRUSION")
            named = moving_events(down)
            sol = solve_ivp(make_rhs(down), (t, horizon), y, method="DOP853", rtol=rtol, atol=atol,
                            events=[fn for _, fn in named], dense_output=True)
            t1 = float(sol.t[-1])
            stalled = stalled + 1 if t1 <= t else 0
            if stalled > 50:  # DOP853 finds the stop at the phase's start again and again: a Zeno loop
                raise InputError(f"exact_drop: the solver cannot follow this drop (its phase ended where it began "
                                 f"{stalled} times at t = {t:g} s); the load m g = {load:.3g} N is likely too small "
                                 f"for its tolerances: use a larger mass or gravity")

            pieces.append((t, t1, moving(sol.sol, down)))
            y = sol.y[:, -1].copy()
            t = t1
            if sol.status != 1:
                break
            kind = named[next(i for i, te in enumerate(sol.t_events) if te.size)][0]
            if kind == "touchdown":
                free = np.flatnonzero(mode == _FREE)
                g = int(free[np.argmax(off[free])])
                y[0] = max(y[0], -off[g])
                mode[g], wet[g], y[2 + g] = _CONTACT, True, 0.0  # z_m = 0 at the crossing
                phase = "INTRUSION"
            elif kind == "surface":  # the drag switches off at the surface
                under = np.flatnonzero(wet)
                wet[int(under[np.argmin(off[under])])] = False
            elif kind == "necking":
                contact = np.flatnonzero(mode == _CONTACT)
                drag = np.where(wet[contact], lr * y[1] * abs(y[1]), 0.0)
                g = int(contact[np.argmin(q.k_m_w * y[2 + contact] + drag)])
                nk[g] = (t, float(y[2 + g]) / tau_w, float(y[0] + off[g] - y[2 + g]))
                mode[g] = _NECKED
                phase = moving_label(False)
            else:  # a stop
                y[1] = 0.0
                phase = at_rest(t, y)
            events.append((t, phase, float(y[0]), float(y[1]), float(y[2])))
        elif phase == "STUCK":  # closed form: the strains relax with tau_i, F_down = a exp(-s / tau_i) + b
            z, e_s = float(y[0]), y[2:].copy()
            contact = mode == _CONTACT
            a = float(np.sum(np.where(contact, w * q.k_m_i * e_s, 0.0)))
            b = float(np.sum(np.where(contact, w * spring(z + off), 0.0)))
            rest = load - b
            if rest <= 0.0:
                t_end = math.inf
            else:
                t_end = t + tau_i * math.log(a / rest) if a > rest else t
            t_s = t
            stop = min(t_end, horizon)
            pieces.append((t_s, stop, resting(z)))
            if t_end == math.inf:
                final = z
                t = horizon
                break
            t = stop
            if stop < t_end:
                y[2:] = e_s * math.exp(-(stop - t_s) / tau_i)
                break
            y[2:] = e_s * (rest / a if a > rest else 1.0)  # F_down = m g there
            phase = "INTRUSION"
            events.append((t, phase, z, 0.0, float(y[2])))
        else:  # STUCK_NECKED: the band moves with the necked mud; find its end by scanning + brentq
            from scipy.optimize import brentq

            z, e_s, t_s = float(y[0]), y[2:].copy(), t

            def relaxed(tt: float, e_s: np.ndarray = e_s, t_s: float = t_s) -> np.ndarray:
                out: np.ndarray = e_s * math.exp(-(tt - t_s) / tau_i)
                return out

            def slack(tt: float, z: float = z) -> float:
                f_up, f_down = band(tt, z, relaxed(tt))
                return min(f_down - load, load - f_up)

            t_end = math.inf
            step = 1e-3
            ta = t
            while ta < horizon:
                tb = min(ta + step, horizon)
                if slack(tb) < 0.0:
                    t_end = brentq(slack, ta, tb, xtol=1e-15)
                    break
                ta = tb
            stop = min(t_end, horizon)
            pieces.append((t_s, stop, resting(z)))
            t = stop
            if t_end == math.inf:
                break
            t = t_end + 1e-13
            y = np.concatenate([[z, 0.0], relaxed(t)])
            y[2:][mode == _NECKED] = 0.0
            phase = at_rest(t, y, leaving=True)
            events.append((t, phase, z, 0.0, float(y[2])))
    if guard >= 10000:
        raise RuntimeError(f"exact_drop: more than 10000 phases before t = {t:g} s")
    n = math.floor(duration / dt + 1e-9) + 1
    grid = np.arange(n) * dt
    depth = np.empty(n)
    vel = np.empty(n)
    frc = np.empty(n)
    for k, (t0, t1, fn) in enumerate(pieces):
        last = k == len(pieces) - 1  # it also takes grid points past the horizon by a rounding (n dt > duration)
        sel = (grid >= t0) & ((grid <= t1) | last)
        if sel.any():
            zz, vv, ff = fn(np.minimum(grid[sel], t1))
            depth[sel], vel[sel], frc[sel] = zz, vv, ff
    zend, _, _ = pieces[-1][2](np.array([min(duration, pieces[-1][1])]))
    return ExactDrop(events, grid, depth, vel, frc, float(zend[0]), float(final),
                     phase in ("STUCK", "STUCK_NECKED"))
