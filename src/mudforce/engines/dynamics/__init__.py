"""The mud model coupled with rigid-body dynamics: the rest band, a built-in engine, its result.

When the foot's motion is simulated rather than prescribed, the force law is
set-valued at zero velocity (``docs/model.md``, "Coupled with
dynamics"): moving down the mud resists on the intrusion branch, moving up
on the withdrawal branch, and a foot at rest can carry any load between the
two. This package implements that as a hybrid system, one module per job:

* :mod:`mudforce.engines.dynamics.rest_band`: the band of forces that hold a foot
  at rest (:func:`rest_band`), and every foot's band for the coming time step
  (:func:`branch_forces`, what the MuJoCo adapter uses); the physics is
  :func:`mudforce.model.equations.rest_band_forces`.
* :mod:`mudforce.engines.dynamics.engine`: the built-in event-driven engine
  (:func:`simulate_foot`).
* :mod:`mudforce.engines.dynamics.naive`: the naive explicit coupling, for
  comparison (:func:`naive_drop`).
* :mod:`mudforce.engines.dynamics.result`: what a simulation returns
  (:class:`FootResult`) and the phases of the foot (:class:`Phase`).
* The exact drop, an independent solution used by the tests to check the
  engines, is :func:`mudforce.references.drop.exact_drop` (also importable
  from here).

The foot at rest: the sticking band
------------------------------------
With the Maxwell strain ``e = z_i - z_m`` [m] and the foot at rest at depth
``z_i > 0``, the two one-sided limits of the force (Eqs. (1)-(5) with
``dz_i = 0``, so no drag) are

    F_down = S (k_m_i e + alpha (z_i / H)^beta)     intrusion branch, v -> 0+
    F_up   = S k_m_w e                              withdrawal branch, v -> 0-

The foot sticks while the load it must carry, ``L = m g + F_applied``
(positive down), lies in ``[F_up, F_down]``; the contact force is then
``L`` itself (a reaction, like static friction), and the Maxwell element
relaxes with the intrusion parameters, ``de/dt = -e / tau_i`` (Filippov's
solution; ``sign(0) = +1`` in the paper). The foot slides down once
``L > F_down`` and up once ``L < F_up``. After necking (``Phase.NECKED``) the upward
limit is the post-necking force ``b_m_w v_m0 g(t - t_n)`` (Eq. (7)) and the
downward limit the intrusion force with the necked mud's ``z_m``.

Two ways to solve it, and their errors
--------------------------------------
* Event-driven (:func:`simulate_foot`, the built-in engine): between events
  the motion is a smooth ODE in ``(z_i, dz_i/dt, e)``, integrated with
  classical Runge-Kutta (RK4) on a fixed sub-step ``h``; every branch change
  (velocity through zero), touchdown, necking (Eq. (9)), surface crossing
  (the drag switches off) and the end of sticking is located by bisection
  to 1e-14 s and the phase switched there. The error is RK4's ``O(h^4)``
  inside phases plus the event tolerance; at rest the foot stays exactly
  at rest (no chatter, no ratcheting: a stuck foot does not move at all).
  Near touchdown the nonlinear spring ``z^beta`` is not smooth, which costs
  a little accuracy near touchdown: about 1e-5 of the depth for ``h = 0.1 ms``.
* Time-stepping (:class:`mudforce.engines.mujoco.MudAdapter`): a simulator with a
  fixed step ``dt`` cannot locate events; it treats the band like dry
  friction in an implicit (Moreau-Jean) step: the force is the clamp of
  the force that stops the foot within the step to ``[F_up, F_down]``, with
  the band taken from the mud state at the step's start. The foot sticks
  in one step, never overshoots the band, and does not chatter; the error
  is first order in ``dt`` (the band lags one step, and a stop inside a
  step is resolved at the step's end).

A naive explicit coupling (branch from the sign of the last velocity) puts
the full intrusion force on a foot that has just stopped, throws it up onto
the withdrawal branch, then drops it back: it chatters every step, and as
the intrusion branch carries the weight only on the way down, it ratchets
the foot deeper. :func:`naive_drop` reproduces that for comparison.
"""

from __future__ import annotations

from mudforce.engines.dynamics.engine import simulate_foot
from mudforce.engines.dynamics.naive import NaiveDrop, naive_drop
from mudforce.engines.dynamics.rest_band import branch_forces, rest_band
from mudforce.engines.dynamics.result import GRAVITY, PHASE_NAMES, REST_SPEED, FootResult, Phase
from mudforce.references.drop import ExactDrop, exact_drop

__all__ = [
    "GRAVITY",
    "PHASE_NAMES",
    "REST_SPEED",
    "ExactDrop",
    "FootResult",
    "NaiveDrop",
    "Phase",
    "branch_forces",
    "exact_drop",
    "naive_drop",
    "rest_band",
    "simulate_foot",
]
