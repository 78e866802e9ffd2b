"""mudforce.jax.domain: Table I's mud for a traced water content equals MudParameters.from_water_content."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("jax")

from mudforce.errors import InputError
from mudforce.model.foot import Foot
from mudforce.model.parameters import TABLE_I_WATER_CONTENTS, MudParameters

ROWS = np.array(TABLE_I_WATER_CONTENTS)
POINTS = np.concatenate([ROWS, 0.5 * (ROWS[1:] + ROWS[:-1]), [0.1537, 0.2291, 0.3499]])


def test_traced_water_content_gives_the_cpu_parameters() -> None:
    import jax
    import jax.numpy as jnp

    import mudforce.jax as mj
    from jax_compile import light_jit
    from mudforce.jax.domain import params_from_water_content

    was = bool(jax.config.jax_enable_x64)  # put back as found: other modules in this worker run in float64
    jax.config.update("jax_enable_x64", True)
    try:
        foot = Foot.disc(0.04)

        @light_jit
        def run(w):  # type: ignore[no-untyped-def]  # one light compile: flat, worlds x feet, a gradient
            slope = jax.grad(lambda x: jnp.log(params_from_water_content(x).sigma_y))(w[6])
            return params_from_water_content(w, foot), jax.vmap(params_from_water_content)(w[:12].reshape(3, 4)), slope

        got, batched, slope = run(jnp.asarray(POINTS))
        want = mj.make_params([MudParameters.from_water_content(float(w)) for w in POINTS], foot=foot,
                              dtype=jnp.float64)
        for name, a, b in zip(mj.Params._fields, got, want, strict=True):
            assert np.asarray(a).dtype == np.float64
            np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-12, atol=0.0, err_msg=name)
        for j, w in enumerate(ROWS):  # the rows themselves are exact, as on the CPU
            assert [float(f[j]) for f in got[:11]] == MudParameters.table_i(float(w)).as_array().tolist()
        assert batched.sigma_y.shape == (3, 4) and batched.area.shape == (3, 4)
        np.testing.assert_allclose(np.asarray(batched.sigma_y).ravel(), np.asarray(got.sigma_y)[:12], rtol=1e-12)
        log_rows = np.log([MudParameters.table_i(w).sigma_y for w in (0.20, 0.25)])  # POINTS[6] = 0.225
        assert float(slope) == pytest.approx((log_rows[1] - log_rows[0]) / 0.05, rel=1e-9)
    finally:
        jax.config.update("jax_enable_x64", was)


@pytest.mark.parametrize(("w", "arguments", "words"), [
    (np.array([0.15, 0.4]), {}, r"within Table I's range \[0.15, 0.35\].*got 0.15 to 0.4"),
    ("wet", {}, "^water content must be an array of real numbers"),
    ("0.25", {}, "^water content must be an array of real numbers"),  # was parsed
    (np.array([0.25 + 1j]), {}, "^water content must be an array of real numbers.*complex"),  # 1j was dropped
    ([0.25, True], {}, "^water content must be an array of real numbers.*booleans"),
    (0.25, {"foot": 5}, r"^foot must be a Foot or a non-empty sequence of Foot, got int"),  # was list()'s TypeError
    (np.array([0.25, 0.3]), {"foot": [Foot.paper()] * 3}, r"^got 3 feet for water contents of shape \(2,\)"),
    (0.25, {"foot": [Foot.paper()] * 2}, r"^got 2 feet for water contents of shape \(\)"),  # were broadcast errors
    (0.25, {"dtype": "int32"}, "^dtype must be float32 or float64"),  # was k_i = 162755 Pa/m for 260000
    (0.25, {"dtype": "float16"}, "^dtype must be float32 or float64"),  # was k_i = inf
    (0.25, {"dtype": "nope"}, "^dtype must be float32 or float64"),  # was numpy's TypeError
])
def test_concrete_water_content_out_of_range_is_refused(w: object, arguments: dict[str, object], words: str) -> None:
    from mudforce.jax.domain import params_from_water_content

    with pytest.raises(InputError, match=words):
        params_from_water_content(w, **arguments)  # type: ignore[arg-type]
