"""mudforce.engines.mjx: `mudforce drop --engine mjx` rests at the exact drop's depth without chatter; worlds in
one jit."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from jax_compile import light_env, light_jit

pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")

from mudforce.engines.dynamics import exact_drop
from mudforce.model.parameters import MudParameters


def test_drop_engine_mjx_rests_at_the_exact_depth(tmp_path: Path) -> None:
    out = tmp_path / "drop.csv"
    proc = subprocess.run([sys.executable, "-m", "mudforce", "drop", "--engine", "mjx", "--mass", "10kg",
                           "--water-content", "20%", "--duration", "3s", "--out", str(out)],
                          capture_output=True, text=True, env=light_env(), timeout=240)  # light compile
    assert proc.returncode == 0, proc.stderr
    assert "mjx: rest depth" in proc.stdout
    with out.open() as handle:
        rows = list(csv.DictReader(handle))
    t = np.array([float(r["time_s"]) for r in rows])
    z = np.array([float(r["depth_m"]) for r in rows])
    f = np.array([float(r["force_N"]) for r in rows])
    exact = exact_drop(10.0, MudParameters.from_water_content(0.20), duration=3.0)
    assert abs(z[-1] / exact.rest_depth - 1.0) <= 0.05
    last = t >= t[-1] - 1.0
    assert np.std(f[last]) <= 0.02 * 10.0 * 9.81
    assert {r["state"] for r in rows[-1000:]} == {"STUCK"}


def test_bad_engine_is_refused() -> None:
    proc = subprocess.run([sys.executable, "-m", "mudforce", "drop", "--engine", "warp", "--mass", "1kg",
                           "--water-content", "20%", "--out", "x.csv"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and "mjx" in proc.stderr


def test_worlds_with_their_own_mud_in_one_jit() -> None:
    import jax
    import jax.numpy as jnp
    from mujoco import mjx

    import mudforce.engines.mjx as mud

    model = mud.drop_model(5.0)
    m = mjx.put_model(model)
    water = (0.15, 0.20, 0.25)
    patches = [mud.add_mud(model, ["sole"], MudParameters.from_water_content(w)) for w in water]
    patch = jax.tree_util.tree_map(lambda *xs: jnp.stack(xs), *patches)
    d0 = mjx.make_data(m)
    data = jax.tree_util.tree_map(lambda x: jnp.broadcast_to(x, (len(water), *x.shape)), d0)
    step = jax.vmap(lambda d, c, p: mud.step(m, d, c, p), in_axes=(0, 0, 0))

    @light_jit  # this test is about numbers, not speed
    def run(data):  # type: ignore[no-untyped-def]
        def body(carry, _):  # type: ignore[no-untyped-def]
            d, c = carry
            d, c, f = step(d, c, patch)
            return (d, c), (c.state.depth[:, 0], f[:, 0], c.stuck[:, 0])
        return jax.lax.scan(body, (data, jax.vmap(mud.init)(patch)), None, length=600)[1]

    depth, force, stuck = (np.asarray(a) for a in run(data))
    assert np.isfinite(force).all()
    assert depth[-1, 0] < depth[-1, 1] < depth[-1, 2]  # wetter mud, deeper rest
    assert stuck[-100:].all()
    np.testing.assert_allclose(force[-100:], 5.0 * 9.81, rtol=1e-4)  # at rest the mud carries the weight
