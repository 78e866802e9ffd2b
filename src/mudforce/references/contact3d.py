"""An independent, slow, high-accuracy solution of the 3-D law (:mod:`mudforce.model.law3d`), for the tests.

This module re-implements the law of :mod:`mudforce.model.law3d` from its
definition (that module's docstring and docs/model.md), without calling
:class:`mudforce.steppers.contact3d.MudContact3D`, the compiled stepper or the small
functions of :mod:`mudforce.model.law3d`, so that the tests can catch a bug in
either. It uses scipy's rotations, the published 3D-RFT fits
(:func:`mudforce.model.granular.rft3d_alpha`, tested against the published values
in tests/granular) and the 1-D oracle :func:`mudforce.references.trajectory.reference_simulate`.

The motion
----------
Poses sampled at ``time`` (position [m] and unit quaternion ``(w, x, y, z)``).
Each element's centroid is taken **linear in time between samples**
(first-order hold of the centroids, the reading of :class:`MudContact3D`,
which sees an element's displacement over a step and nothing in between);
its normal is interpolated linearly and normalised. A continuous motion is
given by sampling it finely.

The law, element by element
---------------------------
* **Vertical.** The paper's 1-D ODEs on the element's own depth history,
  integrated with :func:`scipy.integrate.solve_ivp` with events (touchdown,
  branch switch at the sign change of the element's vertical velocity,
  necking ``k_m_w e + f_s = -sigma_y``, the drag's surface crossing):
  :func:`mudforce.references.trajectory.reference_simulate` with a unit area, whose
  force is then the stress ``sigma_i`` [Pa]. Vertical force
  ``sigma_i A_i max(-n_z, 0)``, with the sideways force that 3D-RFT gives a plate of the element's tilt moved
  straight down, per unit of its vertical one (``alpha_h / alpha_z`` of :func:`rft3d_alpha` at ``v = -z``):
  the 20-term fits themselves, not law3d's cubic in ``cos(beta)``.
* **Horizontal: the rate form of the elastic-perfectly-plastic slip.** An
  element below the surface (depth ``> 0``) carries a slip ``s`` [m], traction
  ``-k s``. While ``k |s| < C(s/|s|, t)``: ``ds/dt = u`` (the centroid's
  horizontal velocity). On the capacity and loading (the elastic rate would
  take ``k|s| - C`` above zero): ``|s| = C(e, t) / k`` and the direction
  ``e`` turns with the tangential part of ``u``, ``de/dt = (u - (u.e) e) / |s|``
  (the rate limit of a radial return); the rest of ``u`` flows. Yield and
  unloading are integrator events; so are the surface crossings (an
  element entering starts with ``s = 0``, one leaving forgets its slip).
  Capacity ``C = sigma_y |e - (e.n) n| + alpha (d/H)^beta b(n, e)`` with
  ``b = max(0, -alpha_rft(n, e).e) / alpha_rft_flat`` on leading faces
  (``n.e > 0``), 0 elsewhere.
* **Horizontal drag**, ``-lambda rho (n_h.u)_+ u`` per unit area while below
  the surface.

Sample values against :class:`MudContact3D`
-------------------------------------------
The CPU law updates each slip once per step with a return map on the step's
displacement ``D``: trial ``s + D``, scaled back to ``C_k / k`` in the trial's
direction, with ``C_k`` at the end of the step. That is exact (equal to the
rate form at the sample) for a **straight step whose slip is parallel to
its displacement and whose capacity is concave in time over the step**: a
translation (the normal fixed; the spring ``(d/H)^beta`` with ``beta < 1`` is
concave in a depth linear in time) of an element that stays below the
surface. It is not exact, each time by at most ``k |D|`` on the element's
traction, where

* the element **touches down inside the step**: the CPU counts the whole
  step's displacement, the rate form only the part below the surface;
* the slip **turns** (a displacement not parallel to the slip): the radial
  return and the rate form differ by ``O(|D|^2 / |s|)`` in slip;
* the body **rotates**: the capacity is not concave in time within the step
  and the element can flow and unload inside it.

A difference so made is kept by elastic memory until the element flows in
the same direction again (then both sit on the capacity) or leaves the mud.
The tests (tests/references/test_reference3d.py) state the tolerance of each
case from these.

It is pure Python and slow (about a millisecond per element and step in
contact): short motions, coarse shapes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from mudforce.errors import InputError, real_array
from mudforce.model.bounds import MAX_DEPTH, MAX_HORIZONTAL, bounded_depth, check_depths, check_times
from mudforce.model.foot import Foot
from mudforce.model.granular import RFT3D_C1, RFT3D_C2, RFT3D_C3, rft3d_alpha, rft3d_alpha_unchecked
from mudforce.model.law3d import QUATERNION_TOLERANCE, check_bearing_scale, check_lateral_stiffness, rotation_matrix
from mudforce.model.parameters import MudParameters
from mudforce.model.shapes import Shape
from mudforce.references.trajectory import reference_simulate

__all__ = ["Reference3DResult", "place", "reference_simulate_3d", "vertical_leans", "vertical_weights"]

Float = NDArray[np.float64]

_RTOL = 1e-11  # relative tolerance of the lateral integration [-]
_ATOL = 1e-16  # absolute tolerance of the lateral integration [m], [rad], [J]
_FD = 1e-7  # forward-difference step of the loading test, per step length [-]
_NUDGE = 1e-6  # how long, per step length, an element chattering between yield and unloading flows unwatched [-]
_ON = 1e-12  # relative band of k|s| about the capacity C read as "on it" (rounding, not a state) [-]
_MAX_EVENTS = 100_000  # a guard against an event loop (never reached by a sound law)

_ELASTIC = 1
_PLASTIC = 2


@dataclass(frozen=True, eq=False)
class Reference3DResult:
    """The reference solution of the 3-D law at the input samples (world frame, z up).

    Attributes
    ----------
    time : ndarray, shape (m,)
        Sample times [s].
    force : ndarray, shape (m, 3)
        Force on the foot [N].
    torque : ndarray, shape (m, 3)
        Torque about the body origin [N m].
    element_forces : ndarray, shape (m, n, 3)
        Each element's force [N].
    stress : ndarray, shape (m, n)
        Each element's paper stress ``sigma_i`` [Pa], Eq. (8), positive up.
    slip : ndarray, shape (m, n, 2)
        Each element's horizontal elastic slip [m] (0 above the surface).
    plastic : ndarray of bool, shape (m, n)
        Whether the element is flowing at the sample (on its capacity and loading).
    events : tuple of (float, int, str)
        ``(time [s], element, kind)`` of every lateral event, kind ``"enter"``,
        ``"leave"``, ``"yield"`` or ``"unload"``, in time order.
    lateral_work : ndarray, shape (m,)
        Work done on the foot by the elastic-plastic tractions since the first sample [J].
    drag_work : ndarray, shape (m,)
        Work done on the foot by the horizontal drag since the first sample [J] (never positive).
    elastic_energy : ndarray, shape (m,)
        Energy stored in the horizontal slips, ``sum A_i k |s_i|^2 / 2`` [J].
    """

    time: Float
    force: Float
    torque: Float
    element_forces: Float
    stress: Float
    slip: Float
    plastic: NDArray[np.bool_]
    events: tuple[tuple[float, int, str], ...]
    lateral_work: Float
    drag_work: Float
    elastic_energy: Float


class _Event:
    """A terminal, upward ``solve_ivp`` event."""

    def __init__(self, fun: Callable[[float, Float], float]) -> None:
        self.fun = fun
        self.terminal = True
        self.direction = 1.0

    def __call__(self, t: float, y: Float) -> float:
        return self.fun(t, y)


class _Law:
    """The horizontal law's pieces, from their definitions (numpy on index arrays)."""

    def __init__(self, params: MudParameters, width: float, stiffness: float, bearing_scale: float = 1.0) -> None:
        self.p = params
        self.width = width
        self.k = stiffness
        self.bearing_scale = bearing_scale
        down = np.array([[0.0, 0.0, -1.0]])
        self.flat = float(rft3d_alpha(down, down)[0, 2])
        self.coefficients = (np.asarray(RFT3D_C1, dtype=np.float64), np.asarray(RFT3D_C2, dtype=np.float64),
                             np.asarray(RFT3D_C3, dtype=np.float64))  # 3D-RFT's flat plate pushed down [-]
        self.floor = 1e-9 * params.sigma_y / stiffness  # the smallest slip radius the direction ODE divides by [m]

    def capacity(self, direction: Float, normals: Float, depth: Float) -> Float:
        """``sigma_y |e - (e.n)n| + c alpha (d/H)^beta b(n, e)`` [Pa] for unit horizontal directions (rows, 2), ``c``
        the bearing scale."""
        e = np.zeros((direction.shape[0], 3))
        e[:, :2] = direction
        en = np.sum(e * normals, axis=1)
        along = e - en[:, None] * normals
        shear = np.sqrt(np.sum(along * along, axis=1))
        p = self.p
        spring = np.where(depth > 0.0, p.alpha * (np.maximum(depth, 0.0) / self.width) ** p.beta, 0.0)
        rft = rft3d_alpha_unchecked(normals, e, *self.coefficients)  # no input checks on every call
        bearing = np.where(en > 0.0, np.maximum(-np.sum(rft * e, axis=1), 0.0) / self.flat, 0.0)
        out: Float = p.sigma_y * shear + self.bearing_scale * spring * bearing
        return out

    def drag(self, normals: Float, velocity: Float) -> Float:
        """Eq. (5) on the leading projection, ``-lambda rho (n_h.u)_+ u`` [Pa], rows (2,)."""
        facing = np.maximum(np.sum(normals[:, :2] * velocity, axis=1), 0.0)
        out: Float = -(self.p.lambda_ * self.p.rho_m) * facing[:, None] * velocity
        return out


def _unit(v: Float) -> Float:
    """Rows of ``v`` normalised; a zero row becomes ``(1, 0)`` (any direction: its slip is zero)."""
    size = np.sqrt(np.sum(v * v, axis=1))
    out = np.zeros_like(v)
    out[:, 0] = 1.0
    good = size > 0.0
    out[good] = v[good] / size[good, None]
    return out


class _Step:
    """One sample interval: the elements' depths, normals and velocities as functions of the local time."""

    def __init__(self, law: _Law, dt: float, c0: Float, c1: Float, n0: Float, n1: Float, h: float) -> None:
        self.law = law
        self.dt = dt
        self.d0 = h - c0[:, 2]
        self.d1 = h - c1[:, 2]
        self.n0 = n0
        self.n1 = n1
        self.u = (c1[:, :2] - c0[:, :2]) / dt  # first-order hold of the centroids [m/s]

    def depth(self, tau: float, idx: NDArray[np.intp]) -> Float:
        out: Float = self.d0[idx] + (self.d1[idx] - self.d0[idx]) * (tau / self.dt)
        return out

    def normals(self, tau: float, idx: NDArray[np.intp]) -> Float:
        if tau >= self.dt:
            return self.n1[idx]
        n = self.n0[idx] + (self.n1[idx] - self.n0[idx]) * (tau / self.dt)
        out: Float = n / np.sqrt(np.sum(n * n, axis=1))[:, None]
        return out

    def capacity(self, tau: float, idx: NDArray[np.intp], direction: Float) -> Float:
        return self.law.capacity(direction, self.normals(tau, idx), self.depth(tau, idx))

    def loading(self, tau: float, idx: NDArray[np.intp], slip: Float) -> Float:
        """Forward rate of ``k|s| - C`` under the elastic rate ``ds/dt = u`` [Pa/s] (> 0: the element would yield)."""
        k = self.law.k
        h = _FD * self.dt
        now = k * np.sqrt(np.sum(slip * slip, axis=1)) - self.capacity(tau, idx, _unit(slip))
        ahead = slip + self.u[idx] * h
        later = k * np.sqrt(np.sum(ahead * ahead, axis=1)) - self.capacity(tau + h, idx, _unit(ahead))
        out: Float = (later - now) / h
        return out


def _slip_of(step: _Step, tau: float, idx: NDArray[np.intp], y: Float, mode: NDArray[np.int8]) -> Float:
    """The slips [m] of elements ``idx`` from the state: ``(s_x, s_y)`` if elastic, ``C(phi)/k e(phi)`` if plastic."""
    n = mode.size
    s = np.stack([y[idx], y[n + idx]], axis=1)
    flowing = mode[idx] == _PLASTIC
    if np.any(flowing):
        sub = idx[flowing]
        phi = y[sub]
        e = np.stack([np.cos(phi), np.sin(phi)], axis=1)
        r = step.capacity(tau, sub, e) / step.law.k
        s[flowing] = r[:, None] * e
    return s


def _to_plastic(step: _Step, tau: float, j: int, y: Float, n: int) -> None:
    phi = float(np.arctan2(y[n + j], y[j]))
    y[j], y[n + j] = phi, 0.0


def _to_elastic(step: _Step, tau: float, j: int, y: Float, mode: NDArray[np.int8], n: int) -> None:
    s = _slip_of(step, tau, np.array([j]), y, mode)[0]
    y[j], y[n + j] = s[0], s[1]


def _classify(step: _Step, tau: float, y: Float, mode: NDArray[np.int8], inside: NDArray[np.bool_],
              events: list[tuple[float, int, str]], t0: float) -> None:
    """At the start of a segment: an element on its capacity flows if loading, else it is elastic."""
    n = mode.size
    idx = np.flatnonzero(inside)
    if idx.size == 0:
        return
    k = step.law.k
    s = _slip_of(step, tau, idx, y, mode)
    size = np.sqrt(np.sum(s * s, axis=1))
    cap = step.capacity(tau, idx, _unit(s))
    on = k * size >= cap * (1.0 - _ON)
    load = step.loading(tau, idx, s)
    for j, is_on, rate, c in zip(idx.tolist(), on.tolist(), load.tolist(), cap.tolist(), strict=True):
        if mode[j] == _PLASTIC and not (rate > 0.0):
            _to_elastic(step, tau, j, y, mode, n)
            mode[j] = _ELASTIC
            events.append((t0 + tau, j, "unload"))
        elif mode[j] == _ELASTIC and is_on and rate > 0.0 and c > 0.0:
            _to_plastic(step, tau, j, y, n)
            mode[j] = _PLASTIC
            events.append((t0 + tau, j, "yield"))


def _segment(step: _Step, a: float, b: float, y: Float, mode: NDArray[np.int8], inside: NDArray[np.bool_],
             areas: Float, events: list[tuple[float, int, str]], t0: float) -> Float:
    """Integrate the lateral law of the elements ``inside`` (no surface crossing) from ``a`` to ``b`` [s]."""
    n = mode.size
    law = step.law
    k = law.k
    idx_all = np.flatnonzero(inside)
    count = 0
    chatter = 0
    _classify(step, a, y, mode, inside, events, t0)
    while True:
        if b <= a or idx_all.size == 0:
            return y
        el = idx_all[mode[idx_all] == _ELASTIC]
        pl = idx_all[mode[idx_all] == _PLASTIC]
        u_el, u_pl, u_all = step.u[el], step.u[pl], step.u[idx_all]
        lam = law.p.lambda_ * law.p.rho_m
        speed2 = np.sum(u_all * u_all, axis=1)

        def rhs(tau: float, z: Float, el: Any = el, pl: Any = pl, u_el: Float = u_el, u_pl: Float = u_pl,
                u_all: Float = u_all, lam: float = lam, speed2: Float = speed2) -> Float:
            dz = np.zeros_like(z)
            dz[el] = u_el[:, 0]
            dz[n + el] = u_el[:, 1]
            s = np.zeros((n, 2))
            s[el, 0], s[el, 1] = z[el], z[n + el]
            if pl.size:
                phi = z[pl]
                e = np.stack([np.cos(phi), np.sin(phi)], axis=1)
                r = step.capacity(tau, pl, e) / k
                dz[pl] = (-u_pl[:, 0] * e[:, 1] + u_pl[:, 1] * e[:, 0]) / np.maximum(r, law.floor)
                s[pl] = r[:, None] * e
            s = s[idx_all]
            dz[2 * n] = -k * float(np.sum(areas[idx_all] * np.sum(s * u_all, axis=1)))
            facing = np.maximum(np.sum(step.normals(tau, idx_all)[:, :2] * u_all, axis=1), 0.0)
            dz[2 * n + 1] = -lam * float(np.sum(areas[idx_all] * facing * speed2))
            return dz

        def margin(tau: float, z: Float, el: Any = el) -> float:
            if el.size == 0:
                return -1.0
            s = np.stack([z[el], z[n + el]], axis=1)
            size = np.sqrt(np.sum(s * s, axis=1))
            # yield once past the capacity by _ON of it: an element left exactly on its capacity and not
            # loading (its capacity and slip both still) reads k|s| - C as rounding noise around zero, and a
            # crossing of that noise is no yield (it looped, yield then unload, in 2e-8 s steps)
            return float(np.max(k * size - step.capacity(tau, el, _unit(s)) * (1.0 + _ON)))

        def unloading(tau: float, z: Float, pl: Any = pl) -> float:
            if pl.size == 0:
                return -1.0
            return float(np.max(-step.loading(tau, pl, _slip_of(step, tau, pl, z, mode))))

        if chatter >= 3:  # an element switching back and forth at one instant: let it flow a moment, no events
            end = min(b, a + _NUDGE * step.dt)
            sol = solve_ivp(rhs, (a, end), y, method="DOP853", rtol=_RTOL, atol=_ATOL)
            y = sol.y[:, -1].copy()
            a = end
            chatter = 0
            _classify(step, a, y, mode, inside, events, t0)
            continue
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=_RTOL, atol=_ATOL,
                        events=[_Event(margin), _Event(unloading)])
        if sol.status < 0:  # pragma: no cover - smooth ODEs
            raise RuntimeError(f"reference integration failed: {sol.message}")
        if sol.status == 0:
            out: Float = sol.y[:, -1].copy()
            return out
        count += 1
        if count > _MAX_EVENTS:  # pragma: no cover - a guard
            raise RuntimeError("reference3d: too many lateral events in one step")
        hits = [(float(te[0]), i) for i, te in enumerate(sol.t_events) if te.size]
        tau, which = min(hits)
        y = np.asarray(sol.y_events[which][0], dtype=np.float64).copy()
        if which == 0:  # yield: every elastic element on its capacity (mirror twins at once) and loading
            s = np.stack([y[el], y[n + el]], axis=1)
            cap = step.capacity(tau, el, _unit(s))
            gap = k * np.sqrt(np.sum(s * s, axis=1)) - cap
            rate = step.loading(tau, el, s)
            hit = (gap >= gap.max() - 1e-9 * float(np.max(cap))) & (rate > 0.0)
            hit[int(np.argmax(gap))] = True
            for j in el[hit].tolist():
                _to_plastic(step, tau, j, y, n)
                mode[j] = _PLASTIC
                events.append((t0 + tau, j, "yield"))
        else:  # unloading: every flowing element whose loading rate reached zero
            rate = step.loading(tau, pl, _slip_of(step, tau, pl, y, mode))
            scale = k * float(np.max(np.sqrt(np.sum(step.u[pl] ** 2, axis=1)))) + 1.0
            hit = rate <= rate.min() + 1e-7 * scale
            for j in pl[hit].tolist():
                _to_elastic(step, tau, j, y, mode, n)
                mode[j] = _ELASTIC
                events.append((t0 + tau, j, "unload"))
        chatter = chatter + 1 if tau - a <= 1e-9 * step.dt else 0
        a = tau


def place(shape: Shape, positions: Float, quaternions: Float, surface_height: float) -> tuple[
        Float, Float, Float, Float]:
    """The shape's elements at each pose: ``(offsets, centroids, normals, depth)`` [m, m, -, m].

    ``positions`` (m, 3) [m] and unit ``quaternions`` (m, 4) ``(w, x, y, z)``; ``offsets`` (m, n, 3) are the
    centroids relative to the body origin in the world frame, ``depth`` (m, n) each centroid's depth below
    ``surface_height`` [m] (positive down).
    """
    q = quaternions
    rot = Rotation.from_quat(np.stack([q[:, 1], q[:, 2], q[:, 3], q[:, 0]], axis=1)).as_matrix()  # (m, 3, 3)
    offsets = np.einsum("kab,ib->kia", rot, shape.centroids)  # (m, n, 3)
    centroids = positions[:, None, :] + offsets
    normals = np.einsum("kab,ib->kia", rot, shape.normals)
    return offsets, centroids, normals, surface_height - centroids[:, :, 2]


def vertical_weights(areas: Float, normals: Float) -> Float:
    """What carries each element's paper stress vertically: ``A_i max(-n_z, 0)`` [m^2] (its downward projection)."""
    out: Float = areas * np.maximum(-normals[..., 2], 0.0)
    return out


def vertical_leans(normals: Float) -> Float:
    """Each element's sideways force per unit of its vertical force [-], shape (..., 2): 3D-RFT's ``alpha_x / alpha_z``
    and ``alpha_y / alpha_z`` for the element moved straight down (:func:`mudforce.model.granular.rft3d_alpha`, its
    20-term fits; an element facing up or sideways carries no vertical force, and what it gets here is not used)."""
    flat = normals.reshape(-1, 3)
    alpha = rft3d_alpha(flat, np.tile([0.0, 0.0, -1.0], (flat.shape[0], 1)))
    out: Float = (alpha[:, :2] / alpha[:, 2:3]).reshape(*normals.shape[:-1], 2)
    return out


def reference_simulate_3d(time: Any, positions: Any, quaternions: Any, params: MudParameters, shape: Shape, *,
                          surface_height: float = 0.0, width: float | None = None,
                          lateral_stiffness: float | None = None,
                          bearing_scale: float | None = None) -> Reference3DResult:
    """Reference solution of the 3-D law for a sampled motion (module docstring: what is solved, and how).

    Parameters
    ----------
    time : array_like, shape (m,)
        Sample times [s], strictly increasing.
    positions : array_like, shape (m, 3)
        The body origin at each sample [m], world frame, z up.
    quaternions : array_like, shape (m, 4)
        The orientation at each sample, ``(w, x, y, z)`` [-], unit.
    params : MudParameters
        The mud.
    shape : Shape
        The foot's surface, body frame.
    surface_height : float
        Height of the undisturbed mud surface [m].
    width : float, optional
        The intruder width ``H`` of Eq. (4) [m]; by default ``shape.width``.
    lateral_stiffness : float, optional
        Stiffness of the horizontal slip [Pa/m]; by default ``k_m_w``.
    bearing_scale : float, optional
        The sideways bearing's scale [-]; by default 1 (as :class:`~mudforce.steppers.contact3d.MudContact3D`).

    Returns
    -------
    Reference3DResult
    """
    if not isinstance(params, MudParameters):
        raise InputError(f"params must be a MudParameters, got {type(params).__name__}")
    if not isinstance(shape, Shape):
        raise InputError(f"shape must be a mudforce.model.shapes.Shape, got {type(shape).__name__}")
    t = real_array(time, "time", "s")
    x = real_array(positions, "positions", "m")
    q = real_array(quaternions, "quaternions", "-")
    m = t.shape[0] if t.ndim == 1 else -1
    if m == 0 and x.shape == (0, 3) and q.shape == (0, 4):  # they agree: "must agree" said otherwise
        raise InputError("the motion is empty; expected at least one sample (time (m,), positions (m, 3) and "
                         "quaternions (m, 4), m >= 1)")
    if m < 1 or x.shape != (m, 3) or q.shape != (m, 4):
        raise InputError(f"time (m,), positions (m, 3) and quaternions (m, 4) must agree, got {t.shape}, "
                         f"{x.shape} and {q.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x)) and np.all(np.isfinite(q))):
        raise InputError("time, positions and quaternions must be finite")
    check_times(t)  # simulate_3d's bounds and words (a step of 1e-12 s and a time of 2e9 s were solved)
    far = np.flatnonzero(~np.all(np.abs(x[:, :2]) <= MAX_HORIZONTAL, axis=1))
    if far.size:  # MudContact3D's bound, in its words (2e4 m was solved)
        raise InputError(f"sample {far[0]} (t = {float(t[far[0]])!r} s): position x and y must be within "
                         f"+-{MAX_HORIZONTAL:g} m of the world origin, got {x[far[0]].tolist()!r}")
    with np.errstate(over="ignore"):  # a component beyond 1e154: norm inf, refused below without numpy's warning
        off = np.flatnonzero(~(np.abs(np.sqrt(np.sum(q * q, axis=1)) - 1.0) <= QUATERNION_TOLERANCE))
    for k in off.tolist():  # simulate_3d's check and words, with the sample (it named none: "quaternions must ...")
        try:
            rotation_matrix(q[k])
        except InputError as error:
            raise InputError(f"sample {k} (t = {float(t[k])!r} s): {error}") from None
    h = bounded_depth(surface_height, "surface_height")  # MudContact3D's checks, in its words
    given = shape.width if width is None else width
    if given is None:
        raise InputError("this shape has no width H for Eq. (4); give width= [m]")
    element = Foot(area=1.0, width=given, shape="element")  # checks H
    h_width = element.width
    k = check_lateral_stiffness(params.k_m_w if lateral_stiffness is None else lateral_stiffness)
    law = _Law(params, h_width, k, check_bearing_scale(1.0 if bearing_scale is None else bearing_scale))
    n = shape.n
    areas = np.asarray(shape.areas, dtype=np.float64)

    offsets, centroids, normals, depth = place(shape, x, q, h)
    deep = np.flatnonzero(~np.all(np.abs(depth) <= MAX_DEPTH, axis=0))
    if deep.size:  # simulate_3d's bound on every element's depth (an element 100.48 m deep was solved)
        try:
            check_depths(depth[:, deep[0]])
        except InputError as error:
            raise InputError(f"element {deep[0]}: {error}") from None

    # --- vertical: the 1-D oracle on each element's depth history (identical histories solved once)
    stress = np.zeros((m, n))
    solved: dict[bytes, Float] = {}
    for i in range(n):
        if not np.any(depth[:, i] > 0.0):
            continue
        key = depth[:, i].tobytes()
        if key not in solved:
            solved[key] = reference_simulate(t, depth[:, i], params, element).force
        stress[:, i] = solved[key]
    forces = np.zeros((m, n, 3))
    forces[:, :, 2] = stress * vertical_weights(areas, normals)
    sideways = forces[:, :, 2:3] * vertical_leans(normals)  # 3D-RFT's direction of a vertical resistance

    # --- horizontal: the rate form, step by step, with events
    slip = np.zeros((m, n, 2))
    plastic = np.zeros((m, n), dtype=bool)
    lateral_work = np.zeros(m)
    drag_work = np.zeros(m)
    events: list[tuple[float, int, str]] = []
    y = np.zeros(2 * n + 2)
    mode = np.full(n, _ELASTIC, dtype=np.int8)
    inside = depth[0] > 0.0
    for kk in range(1, m):
        dt = float(t[kk] - t[kk - 1])
        step = _Step(law, dt, centroids[kk - 1], centroids[kk], normals[kk - 1], normals[kk], h)
        y[2 * n:] = 0.0
        # the instants inside the step at which elements cross the surface (depth linear in time)
        crossing = (step.d0 > 0.0) != (step.d1 > 0.0)
        cuts: dict[float, list[int]] = {}
        for i in np.flatnonzero(crossing).tolist():
            tau = dt * float(step.d0[i] / (step.d0[i] - step.d1[i])) if step.d0[i] != step.d1[i] else 0.0
            cuts.setdefault(min(max(tau, 0.0), dt), []).append(i)
        a = 0.0
        for tau in [*sorted(cuts), dt]:
            y = _segment(step, a, tau, y, mode, inside, areas, events, float(t[kk - 1]))
            for i in cuts.get(tau, []):
                y[i] = y[n + i] = 0.0
                mode[i] = _ELASTIC
                entering = not inside[i]
                inside[i] = entering
                events.append((float(t[kk - 1]) + tau, i, "enter" if entering else "leave"))
            a = tau
        idx = np.flatnonzero(inside)
        _classify(step, dt, y, mode, inside, [], float(t[kk - 1]))  # the state at the sample (not an event)
        s = _slip_of(step, dt, idx, y, mode)
        slip[kk, idx] = s
        plastic[kk, idx] = mode[idx] == _PLASTIC
        drag = law.drag(normals[kk, idx], step.u[idx])
        forces[kk, idx, :2] = (-k * s + drag) * areas[idx, None]
        lateral_work[kk] = lateral_work[kk - 1] + y[2 * n]
        drag_work[kk] = drag_work[kk - 1] + y[2 * n + 1]
    forces[:, :, :2] += sideways
    elastic_energy = 0.5 * k * np.sum(areas[None, :] * np.sum(slip * slip, axis=2), axis=1)
    torque = np.cross(offsets, forces).sum(axis=1)
    return Reference3DResult(t.copy(), forces.sum(axis=1), torque, forces, stress, slip, plastic,
                             tuple(sorted(events)), lateral_work, drag_work, elastic_energy)
