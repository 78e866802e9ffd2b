"""Domain randomisation under ``jit``: Table I's mud for a traced water content, as a :class:`mudforce.jax.Params`.

Usage (a Playground-style ``reset``, one world; ``jax.vmap`` it over worlds)::

    import jax
    import mudforce.engines.mjx as mud
    from mudforce.jax.domain import params_from_water_content

    patch = mud.add_mud(model, feet, MudParameters.from_water_content(0.25))   # once, on the host

    def reset(rng):
        w = jax.random.uniform(rng, minval=0.15, maxval=0.35)                   # this world's water content [-]
        mud_w = params_from_water_content(jnp.full(patch.sites.shape, w))       # every foot in the same mud
        world_patch = patch._replace(params=mud_w._replace(area=patch.params.area, width=patch.params.width))
        return mjx.make_data(m), mud.init(world_patch), world_patch

:func:`params_from_water_content` is :meth:`mudforce.MudParameters.from_water_content`
as a pure JAX function: the same five rows of Table I (read from
:meth:`mudforce.MudParameters.table_i`, not written again), the same
log-linear interpolation between neighbouring rows, the rows themselves
exact; float64 values equal the CPU's to 1e-12 (with ``jax_enable_x64``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

import mudforce.jax as mj
from mudforce.errors import InputError, real_array
from mudforce.model.foot import Foot
from mudforce.model.parameters import TABLE_I_WATER_CONTENTS, WATER_CONTENT_RANGE, MudParameters

__all__ = ["params_from_water_content"]

Array = Any
_ROW = 1e-9  # [-]: a water content this close to a row of Table I is that row, as in MudParameters.from_water_content


def _table() -> np.ndarray:
    """Table I's five rows [SI], in :class:`mudforce.jax.Params`' first eleven fields' order (rows, 11)."""
    return np.array([MudParameters.table_i(w).as_array() for w in TABLE_I_WATER_CONTENTS], dtype=np.float64)


def params_from_water_content(w: Array, foot: Foot | Sequence[Foot] | None = None, dtype: Any = None) -> mj.Params:
    """The mud of Table I at water content ``w``, a traced array of any shape, as a :class:`mudforce.jax.Params`.

    Parameters
    ----------
    w : array
        Water content [-] (a volume fraction: 0.25 for 25 %), any shape,
        traced or not. Every field of the result has ``w``'s shape. A
        concrete value outside Table I's range [0.15, 0.35] (or not finite)
        is refused with an :class:`mudforce.errors.InputError`; a traced
        one cannot be checked under ``jit`` and is clipped to the range.
    foot : Foot or sequence of Foot, optional
        Sole geometry for the ``area`` [m^2] and ``width`` [m] fields (a
        sequence: one per foot, along ``w``'s last axis); the paper's
        51 x 38 mm cuboid by default.
    dtype : dtype, optional
        Float dtype, float32 or float64; JAX's default float by default (float64 needs ``jax_enable_x64``).

    Returns
    -------
    mudforce.jax.Params
        ``k_i`` [Pa/m], ``b_i`` [Pa s/m], ``k_w`` [Pa/m], ``b_w`` [Pa s/m],
        ``alpha`` [Pa], ``beta`` [-], ``sigma_y`` [Pa], ``zeta`` [-],
        ``omega_0`` [rad/s] interpolated log-linearly between Table I's rows
        (as :meth:`mudforce.MudParameters.from_water_content`), ``rho_m``
        [kg/m^3] and ``lam`` [-] the paper's constants, ``area``, ``width``
        the foot's: what :func:`mudforce.jax.step` and the ``params`` of a
        :class:`mudforce.engines.mjx.MudPatch` take.
    """
    dt_ = mj._float_dtype(dtype)  # an int32 dtype gave a wrong mud (k_i 162755 Pa/m for 260000), float16 inf
    lo, hi = WATER_CONTENT_RANGE
    if not isinstance(w, jax.core.Tracer):
        concrete = real_array(w, "water content", "-")  # not "0.25" parsed, True as 1 or a complex number's real part
        if not np.isfinite(concrete).all() or (concrete < lo - 1e-12).any() or (concrete > hi + 1e-12).any():
            raise InputError(f"water content must be within Table I's range [{lo:g}, {hi:g}] (a fraction: "
                             f"0.25 means 25%), got {concrete.min():g} to {concrete.max():g}")
    feet = mj._feet(foot)
    table = _table()
    rows = jnp.asarray(TABLE_I_WATER_CONTENTS, dtype=dt_)
    w = jnp.clip(jnp.asarray(w, dtype=dt_), lo, hi)
    if len(feet) > 1 and w.shape[-1:] != (len(feet),):
        raise InputError(f"got {len(feet)} feet for water contents of shape {w.shape}; give one foot or one per "
                         "water content along its last axis")
    nearest = jnp.argmin(jnp.abs(w[..., None] - rows), axis=-1)  # the row closest to each w
    on_row = jnp.abs(w - rows[nearest]) < _ROW
    fields = []
    for j in range(9):  # the nine calibrated values; rho_m and lambda are the paper's constants
        column = jnp.asarray(table[:, j], dtype=dt_)
        between = jnp.exp(jnp.interp(w, rows, jnp.asarray(np.log(table[:, j]), dtype=dt_)))
        fields.append(jnp.where(on_row, column[nearest], between))
    fields += [jnp.full(w.shape, table[0, j], dtype=dt_) for j in (9, 10)]
    geometry = np.array([[f.area, f.width] for f in feet], dtype=np.float64)
    area, width = (jnp.broadcast_to(jnp.asarray(g if len(feet) > 1 else g[0], dtype=dt_), w.shape)
                   for g in geometry.T)
    return mj.Params._make([*fields, area, width])
