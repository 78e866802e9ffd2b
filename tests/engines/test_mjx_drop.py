"""mudforce.engines.mjx: worlds with their own mud in one jit.

(`mudforce drop --engine mjx`, resting at the exact drop's depth without chatter, and the unknown engine's
refusal are checked in tests/cli/test_drop3d_cli.py, in the subprocesses it already starts.)"""

from __future__ import annotations

import copy
from typing import Any

import numpy as np
import pytest

from jax_compile import light_jit

pytest.importorskip("jax")
pytest.importorskip("mujoco.mjx")

from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters


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


@pytest.mark.parametrize(("height", "words"), [
    (True, "must be an array of real numbers"),  # was a surface 1 m up
    ("0.01", "must be an array of real numbers"),  # was parsed
    (1e39, r"must be within \+-100 m"),  # was inf
    (1e12, r"must be within \+-100 m"),  # was taken: a foot 1e12 m deep pushed up by 1.4e9 N
    ([0.0, 0.0], r"must be one height \[m\] or one per foot \(1\), got shape \(2,\)"),  # numpy's ValueError
    (float("nan"), "must be finite"),
])
def test_add_mud_refuses_a_surface_height_that_is_no_height(height: object, words: str) -> None:
    import mudforce.engines.mjx as mud
    from mudforce.errors import InputError

    with pytest.raises(InputError, match=f"^surface_height {words}"):
        mud.add_mud(mud.drop_model(5.0), ["sole"], MudParameters.from_water_content(0.25), surface_height=height,
                    dtype="float32")  # type: ignore[arg-type]


@pytest.mark.parametrize(("call", "words"), [
    (lambda mud, model, p: mud.add_mud(model, [5], p), "^feet must be a name or a non-empty sequence of names"),
    (lambda mud, model, p: mud.add_mud(model, None, p), "^feet must be a name or a non-empty sequence of names"),
    (lambda mud, model, p: mud.add_mud(model, [], p), "^feet must be a name or a non-empty sequence of names"),
    (lambda mud, model, p: mud.add_mud(model, ["sole", "sole"], p), r"^feet must be distinct names"),  # was taken
    (lambda mud, model, p: mud.add_mud(None, ["sole"], p), "^model must be a compiled mujoco.MjModel"),
    (lambda mud, model, p: mud.add_mud(model, ["sole"], 5), "^make_params needs MudParameters"),
    (lambda mud, model, p: mud.add_mud(model, ["sole"], p, foot=5), "^foot must be a Foot"),
    (lambda mud, model, p: mud.add_mud(model, ["sole"], [p, p]), r"^got 2 per-foot entries .* for 1 sites"),
    (lambda mud, model, p: mud.add_mud(model, ["sole"], p, foot=[Foot.paper()] * 2), "^got 2 per-foot entries"),
    (lambda mud, model, p: mud.init(None), "^patch must be a MudPatch"),  # was an AttributeError
    # MuJoCo's add_mud takes geoms and bodies; it said "no site named 'foot' in the model"
    (lambda mud, model, p: mud.add_mud(model, ["foot"], p), "^'foot' is a body, not a site; MJX's add_mud takes sites"),
    (lambda mud, model, p: mud.add_mud(model, ["box"], p), "^'box' is a geom, not a site"),
    (lambda mud, model, p: mud.add_mud(model, ["heel"], p), "^no site named 'heel' in the model; MJX's add_mud"),
])
def test_add_mud_and_init_refuse_what_is_no_patch(call: Any, words: str) -> None:
    import mudforce.engines.mjx as mud
    from mudforce.errors import InputError

    with pytest.raises(InputError, match=words):
        call(mud, mud.drop_model(5.0), MudParameters.from_water_content(0.25))


def test_step_refuses_a_state_or_patch_of_another_model_before_tracing_mjx() -> None:
    """Refused before mjx.forward is traced: each ended in an AttributeError or JAX's TypeError."""
    from mujoco import mjx

    import mudforce.engines.mjx as mud
    import mudforce.jax as mj
    from mudforce.errors import InputError

    model = mud.drop_model(5.0)
    other = copy.copy(model)
    other.site_bodyid[0] = 0  # the same count of sites, the sole on another body
    patch = mud.add_mud(model, ["sole"], MudParameters.from_water_content(0.25))
    two = patch._replace(sites=np.zeros(2, np.int32), bodies=np.ones(2, np.int32))  # two feet on the one site
    of_two = mud.MudState(mj.State(*[np.zeros(2)] * 9), np.zeros(2, bool), np.zeros(2))  # numpy: no new op compiled
    m = mjx.put_model(model)
    for args, words in (
        ((m, None, of_two, patch), r"^the state has 2 feet and the patch 1: a state of another patch\?"),
        ((m, None, mud.init(patch), two), r"^the state has 1 foot and the patch 2"),  # was 'depths must be one'
        ((m, None, mj.init(1), patch), "^state must be a MudState"),  # was an AttributeError
        ((m, None, mud.init(patch), None), "^patch must be a MudPatch"),
        ((model, None, mud.init(patch), patch), r"^m must be MJX's \(mjx.put_model"),  # 'no attribute impl'
        ((mjx.put_model(other), None, mud.init(patch), patch), r"^the patch's sites \[0\] \(on bodies \[1\]\) are "
         r"not this model's \(1 sites\): a patch of another model\?"),  # was taken
    ):
        with pytest.raises(InputError, match=words):
            mud.step(*args)


@pytest.mark.parametrize(("duration", "words"), [
    (5e-4, r"duration 0.0005 s is shorter than one step \(dt = 0.001 s\)"),  # was the start alone
    (float("nan"), "duration must be finite"),  # was math.floor's ValueError
    (1e300, "samples is too many"),
])
def test_simulate_drop_refuses_a_duration_as_the_other_drops_do(duration: float, words: str) -> None:
    import mudforce.engines.mjx as mud
    from mudforce.errors import InputError

    with pytest.raises(InputError, match=words):
        mud.simulate_drop(5.0, MudParameters.from_water_content(0.25), duration=duration)


@pytest.mark.parametrize(("arguments", "words"), [
    ({"mass": float("nan")}, "^mass must be finite"),  # was a model of NaN mass
    ({"mass": True}, "^mass must be a number"),  # was MuJoCo's two-line XML ValueError
    ({"mass": -1.0}, r"^mass must be > 0"),  # was MuJoCo's ValueError
    ({"height": 1e12}, r"^height must be within \+-100 m of the mud surface"),  # was a release 1e12 m up
    ({"height": -1.0}, "^height must be >= 0"),  # was a release 1 m under the surface
    ({"height": "0"}, "^height must be a number"),  # was a TypeError
    ({"dt": 0.0}, r"^dt must be > 0"),  # was a model of step 0 (simulate_drop: ZeroDivisionError)
    ({"dt": 1e-300}, r"^dt must be within \[1e-09, 1000\] s"),
    ({"dt": 5000.0}, r"^dt must be within \[1e-09, 1000\] s"),
    ({"thickness": 1e300}, r"^thickness must be within \[1e-06, 100\] m"),  # was a foot 1e300 m thick
    ({"thickness": 1e-12}, r"^thickness must be within \[1e-06, 100\] m"),  # was MuJoCo's ValueError
    ({"foot": 5}, "^foot must be a Foot"),  # was an AttributeError
])
def test_drop_model_refuses_what_mujocos_drop_model_refuses(arguments: dict[str, object], words: str) -> None:
    import mudforce.engines.mjx as mud
    from mudforce.engines import mujoco as cpu
    from mudforce.errors import InputError

    given = {"mass": 5.0, **arguments}
    mass = given.pop("mass")
    for drop_model in (mud.drop_model, cpu.drop_model):  # the same refusal, in the same words
        with pytest.raises(InputError, match=words):
            drop_model(mass, **given)  # type: ignore[arg-type]


@pytest.mark.parametrize(("arguments", "words"), [
    ({"dt": 0.0}, r"^dt must be > 0"),  # was ZeroDivisionError
    ({"dt": -1e-3}, r"^dt must be > 0"),  # was "duration 0.002 s is shorter than one step (dt = -0.001 s)"
    ({"dt": "0.001"}, "^dt must be a number"),  # was MuJoCo's XML ValueError
    ({"mass": -1.0}, r"^mass must be > 0"),  # was MuJoCo's ValueError
    # MuJoCo's simulate_drop's refusal (engines._checks.check_mass): was a foot ending 1.03e6 m above the mud
    ({"mass": 1e-9}, r"^mass 1e-09 kg is too light for a MuJoCo time step of 0.001 s in this mud: .* from 0.00234 kg"),
    ({"height": -0.1}, "^height must be >= 0"),  # was a drop from under the surface
    ({"params": None}, "^params must be a MudParameters"),  # was a TypeError
    ({"weight": 2.0}, r"^weight must be within \[0, 1\]"),  # was taken: the band extrapolated
    ({"weight": float("nan")}, r"^weight must be within \[0, 1\]"),  # was NaN forces
    ({"weight": True}, "^weight must be a number"),  # was taken as 1
    ({"weight": "0.5"}, "^weight must be a number"),  # was parsed
])
def test_simulate_drop_refuses_bad_arguments_before_compiling(arguments: dict[str, object], words: str) -> None:
    import mudforce.engines.mjx as mud
    from mudforce.errors import InputError

    given: dict[str, object] = {"mass": 5.0, "params": MudParameters.from_water_content(0.25), "duration": 0.002,
                                **arguments}
    with pytest.raises(InputError, match=words):
        mud.simulate_drop(given.pop("mass"), given.pop("params"), **given)  # type: ignore[arg-type]
