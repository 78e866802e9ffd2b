"""simulate() refuses a sample out of bounds with the same message on every path.

For the caller's arrays with the exact rule, the bounds are checked by the
compiled loop as it copies the samples (``_kernel.run_batch_compact``), not
by a pass of their own; for fresh arrays and the "auto" filter, by
``simulation._check_values`` before the loop. Both must refuse the same
samples, with the same one-line message naming the first bad one.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

import mudforce as mf
from mudforce import _kernel as K
from mudforce.steppers import simulation as S

N = 12
T = np.arange(N) * 0.01
Z = np.linspace(-0.01, 0.02, N)


def _set(index: int | slice, what: str, value: float) -> tuple[np.ndarray, np.ndarray]:
    t, z = T.copy(), Z.copy()
    (t if what == "t" else z)[index] = value
    return t, z


CASES: dict[str, tuple[tuple[np.ndarray, np.ndarray], str]] = {
    "NaN depth": (_set(3, "z", np.nan), "depth is not finite at sample 3"),
    "depth beyond 100 m first": (_set(0, "z", 100.5), "depth at sample 0 (100.5 m) is beyond +-100 m"),
    "depth beyond 100 m last": (_set(N - 1, "z", -101.0), f"depth at sample {N - 1} (-101.0 m) is beyond +-100 m"),
    "infinite time": (_set(N - 1, "t", np.inf), f"time is not finite at sample {N - 1}"),
    "time beyond 1e9 s": ((T + 2e9, Z.copy()), "time at sample 0 (2000000000.0 s) is beyond +-1e+09 s"),
    "repeated time": (_set(5, "t", T[4]), "time repeats at sample 5"),
    "backward time": (_set(5, "t", T[3]), "time goes backwards at sample 5"),
    # the step as it is (repr), not rounded: a step just outside a bound must not print as the bound
    "step below 1 ns": (_set(5, "t", T[4] + 1e-10),
                        f"the time step before sample 5 (t = {float(T[4] + 1e-10)!r} s) is "
                        f"{float((T[4] + 1e-10) - T[4])!r} s"),
    "step above 1000 s": (_set(slice(5, None), "t", T[5:] + 2000.0),
                          f"the time step before sample 5 (t = {float(T[5] + 2000.0)!r} s) is "
                          f"{float((T[5] + 2000.0) - T[4])!r} s"),
}

PATHS: dict[str, tuple[str, Callable[[np.ndarray], object]]] = {
    "caller's arrays, exact (checked in the loop)": ("exact", lambda a: a),
    "caller's arrays, auto": ("auto", lambda a: a),
    "lists, exact": ("exact", lambda a: a.tolist()),
    "lists, auto": ("auto", lambda a: a.tolist()),
}


@pytest.mark.parametrize("path", PATHS)
@pytest.mark.parametrize("case", CASES)
def test_the_same_refusal_on_every_path(case: str, path: str) -> None:
    (t, z), expected = CASES[case]
    vf, convert = PATHS[path]
    t_before, z_before = t.copy(), z.copy()
    params = mf.MudParameters.from_water_content(0.25)
    with pytest.raises(mf.InputError) as err:
        mf.simulate(convert(t), convert(z), params, velocity_filter=vf)
    assert str(err.value).startswith(expected), str(err.value)
    assert "\n" not in str(err.value)
    np.testing.assert_array_equal(t, t_before)  # the caller's arrays are untouched
    np.testing.assert_array_equal(z, z_before)


@pytest.mark.parametrize("case", CASES)
def test_the_compiled_loop_refuses_what_it_copies(case: str) -> None:
    (t, z), expected = CASES[case]
    first_bad = int(expected.split("sample ")[1].split()[0])
    vf = mf.VelocityFilter.exact()
    prow = K.params_row(mf.MudParameters.from_water_content(0.25), mf.Foot.paper(), vf)[None, :]
    bad, *_ = S.run_compact(t, z, prow, vf.window, np.empty_like(t), np.empty_like(z))
    assert bad == first_bad


def test_the_bounds_themselves_are_accepted() -> None:
    """Exactly at the bounds: a depth of +-100 m, steps of 1 ns and of 1000 s, |t| = 1e9 s."""
    t = np.array([-1e9, -1e9 + 1e3, -1e9 + 2e3])
    z = np.array([100.0, -100.0, 0.01])
    res = mf.simulate(t, z, mf.MudParameters.from_water_content(0.25), velocity_filter="exact")
    assert np.isfinite(res.force).all()
    t = np.array([0.0, 1e-9, 2e-9])
    res = mf.simulate(t, np.array([0.0, 0.0, 0.0]), mf.MudParameters.from_water_content(0.25),
                      velocity_filter="exact")
    assert np.isfinite(res.force).all()
