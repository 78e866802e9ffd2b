"""jax.grad through a scanned trajectory: finite, and equal to central differences away from events."""

from __future__ import annotations

import numpy as np
import pytest

jax = pytest.importorskip("jax")
jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402

import mudforce.jax as mj  # noqa: E402
from jax_compile import light_jit  # noqa: E402
from mudforce.model.parameters import MudParameters  # noqa: E402

DT = 2e-3
STEPS = 600


def trajectory(n: int) -> np.ndarray:
    """Smooth gaits [m] through touchdown, intrusion, withdrawal, necking and the post-necking decay."""
    t = np.arange(STEPS)[:, None] * DT
    c = np.linspace(2e-3, 12e-3, n)
    a = np.linspace(15e-3, 8e-3, n)
    return c + a * np.sin(2.0 * np.pi * np.linspace(0.9, 1.6, n) * t + np.linspace(0.3, 2.0, n))


@pytest.fixture(scope="module")
def setup():  # type: ignore[no-untyped-def]
    muds = [MudParameters.table_i(w) for w in (0.15, 0.25, 0.30, 0.35)]
    params = mj.make_params(muds)
    z = jnp.asarray(trajectory(len(muds)))

    def loss_and_modes(params: mj.Params, z: jax.Array) -> tuple[jax.Array, jax.Array]:
        def body(s: mj.State, zk: jax.Array) -> tuple[mj.State, tuple[jax.Array, jax.Array]]:
            s, f = mj.step(s, params, zk, DT)
            return s, (f, s.mode)
        _, (forces, modes) = jax.lax.scan(body, mj.init(z.shape[1]), z)
        return jnp.sum(forces**2) * DT, modes

    # one compile (XLA's light one: compiling is most of this module's cost) for the loss, the modes the
    # trajectory passes and the gradient; the central differences evaluate the loss with the same function
    value_and_grad = light_jit(jax.value_and_grad(loss_and_modes, argnums=(0, 1), has_aux=True))

    def grad(params: mj.Params, z: jax.Array) -> tuple[tuple[jax.Array, jax.Array], jax.Array]:
        (_, modes), g = value_and_grad(params, z)
        return g, modes

    def loss(params: mj.Params, z: jax.Array) -> jax.Array:
        return value_and_grad(params, z)[0][0]

    return params, z, loss, grad


def test_trajectory_passes_events(setup) -> None:  # type: ignore[no-untyped-def]
    params, z, _, grad = setup
    _, modes = grad(params, z)
    seen = set(np.unique(np.asarray(modes)).tolist())
    assert seen == {mj.FREE, mj.CONTACT, mj.NECKED}


def test_grad_is_finite(setup) -> None:  # type: ignore[no-untyped-def]
    params, z, _, grad = setup
    (gp, gz), _ = grad(params, z)
    assert all(np.isfinite(np.asarray(g)).all() for g in gp)
    assert np.isfinite(np.asarray(gz)).all()
    assert np.abs(np.asarray(gp.alpha)).max() > 0 and np.abs(np.asarray(gp.sigma_y)).max() > 0


def test_grad_matches_central_differences(setup) -> None:  # type: ignore[no-untyped-def]
    params, z, loss, grad = setup
    (gp, gz), _ = grad(params, z)
    rng = np.random.default_rng(0)
    # parameters: a random relative direction over every field
    u = [jnp.asarray(rng.standard_normal(np.shape(f))) for f in params]
    h = 1e-7
    plus = mj.Params(*(f * (1.0 + h * d) for f, d in zip(params, u, strict=True)))
    minus = mj.Params(*(f * (1.0 - h * d) for f, d in zip(params, u, strict=True)))
    fd = (float(loss(plus, z)) - float(loss(minus, z))) / (2.0 * h)
    ad = sum(float(jnp.sum(g * f * d)) for g, f, d in zip(gp, params, u, strict=True))
    assert ad == pytest.approx(fd, rel=1e-5)
    # depths: a smooth direction (a random sine per foot, 1 nm), which keeps every step's branch
    t = np.arange(STEPS)[:, None] * DT
    dz = jnp.asarray(np.sin(2.0 * np.pi * rng.uniform(0.5, 3.0, z.shape[1]) * t))
    eps = 1e-9
    fdz = (float(loss(params, z + eps * dz)) - float(loss(params, z - eps * dz))) / (2.0 * eps)
    adz = float(jnp.sum(gz * dz))
    assert adz == pytest.approx(fdz, rel=1e-5)
