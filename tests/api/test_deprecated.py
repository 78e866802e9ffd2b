"""Every name renamed in 0.2 still works for one release, with a DeprecationWarning naming the new name.

One test per renamed thing (the table is docs/api.md, "Renamed in 0.2"); each is cheap. The old names are not
in any ``__all__`` (``test_public_all.py`` pins the new lists).
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import mudforce
from mudforce import InputError, MudContacts, MudParameters, MudTracker
from mudforce.engines.dynamics import simulate_foot

W25 = MudParameters.from_water_content(0.25)
HAS_MUJOCO = importlib.util.find_spec("mujoco") is not None
HAS_JAX = importlib.util.find_spec("jax") is not None
needs_mujoco = pytest.mark.skipif(not HAS_MUJOCO, reason="mujoco is not installed")
needs_jax = pytest.mark.skipif(not HAS_JAX, reason="jax is not installed")


def test_chen2024_citation_is_citation() -> None:
    with pytest.warns(DeprecationWarning, match=r"mudforce\.CHEN2024 .*mudforce\.CITATION"):
        old = mudforce.CHEN2024  # type: ignore[attr-defined]
    assert old == mudforce.CITATION and "arXiv:2403.02617" in old
    import mudforce.model.parameters as parameters

    with pytest.warns(DeprecationWarning, match=r"parameters\.CHEN2024 .*parameters\.CITATION"):
        assert parameters.CHEN2024 == parameters.CITATION  # type: ignore[attr-defined]
    assert "CHEN2024" not in mudforce.__all__ and "CHEN2024" not in parameters.__all__
    # the one CHEN2024 left is the model, as the other models are named after theirs
    from mudforce.estimation.calibration import CHEN2024, ForceModel

    assert isinstance(CHEN2024, ForceModel)
    with pytest.raises(AttributeError):
        mudforce.CHEN2025  # type: ignore[attr-defined]  # noqa: B018


def test_track_estimate_interval_is_low_and_high() -> None:
    tracker = MudTracker()
    est = tracker.update(0.0, 0.0, 0.01)
    with pytest.warns(DeprecationWarning, match=r"TrackEstimate\.interval .*low and .*high"):
        assert est.interval == (est.low, est.high)


def test_tracker_update_keywords_are_depth_force_dt() -> None:
    old, new = MudTracker(), MudTracker()
    with pytest.warns(DeprecationWarning, match=r"update\(depth_m=, force_N=, dt_s=\) .*depth=, force=, dt="):
        a = old.update(depth_m=-0.01, force_N=0.3, dt_s=0.01)
    assert a == new.update(depth=-0.01, force=0.3, dt=0.01)
    with pytest.raises(InputError, match="give depth= only"):
        old.update(depth=0.0, depth_m=0.0, force=0.0, dt=0.01)  # type: ignore[call-arg]


def test_mud_contacts_snapshot_restore_and_states_are_state() -> None:
    feet = MudContacts(W25, 2)
    feet.step(np.array([0.0, 0.0]), 0.01)
    feet.step(np.array([0.002, 0.001]), 0.01)
    with pytest.warns(DeprecationWarning, match=r"snapshot\(\) .*MudContacts\.state"):
        snap = feet.snapshot()
    assert np.array_equal(snap, feet.state)
    with pytest.warns(DeprecationWarning, match=r"MudContacts\.states .*MudContacts\.state"):
        assert np.array_equal(feet.states, feet.state)
    after = feet.step(np.array([0.003, 0.002]), 0.01)
    with pytest.warns(DeprecationWarning, match=r"restore\(snapshot\) .*MudContacts\.state = snapshot"):
        feet.restore(snap)
    assert np.array_equal(feet.step(np.array([0.003, 0.002]), 0.01), after)


def test_simulate_foot_depth0_is_minus_height() -> None:
    new = simulate_foot(5.0, W25, duration=0.05, height=0.01)
    with pytest.warns(DeprecationWarning, match=r"depth0=.*height=-depth0"):
        old = simulate_foot(5.0, W25, duration=0.05, depth0=-0.01)
    assert np.array_equal(old.depth, new.depth) and np.array_equal(old.force, new.force)
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="give height"):
        simulate_foot(5.0, W25, duration=0.05, height=0.01, depth0=-0.01)


@needs_jax
def test_jax_make_params_order_and_mud_keyword() -> None:
    from mudforce.jax import make_params
    from mudforce.model.foot import Foot

    new = make_params(W25, 3, Foot.disc(0.05))
    with pytest.warns(DeprecationWarning, match=r"make_params\(params, n, foot\)"):
        old = make_params(W25, Foot.disc(0.05), 3)  # type: ignore[arg-type]
    with pytest.warns(DeprecationWarning, match=r"make_params\(mud=\.\.\.\).*params="):
        kw = make_params(mud=W25, n=3, foot=Foot.disc(0.05))  # type: ignore[call-arg]
    for a, b, c in zip(new, old, kw, strict=True):
        assert np.array_equal(np.asarray(a), np.asarray(b)) and np.array_equal(np.asarray(a), np.asarray(c))
    assert np.asarray(new.area).shape == (3,)
    assert float(np.asarray(new.area)[0]) == pytest.approx(Foot.disc(0.05).area, rel=1e-6)


@needs_mujoco
def test_mujoco_drop_spec_timestep_and_states() -> None:
    import mujoco

    import mudforce.engines.mujoco as mm

    with pytest.warns(DeprecationWarning, match=r"drop_spec .*drop_model"):
        spec = mm.drop_spec(5.0, timestep=2e-3)  # type: ignore[attr-defined]
    assert isinstance(spec, mujoco.MjSpec)
    with pytest.warns(DeprecationWarning, match=r"drop_model\(timestep=\.\.\.\).*dt="):
        model = mm.drop_model(5.0, timestep=2e-3)  # type: ignore[call-arg]
    assert model.opt.timestep == 2e-3 == mm.drop_model(5.0, dt=2e-3).opt.timestep
    assert spec.compile().opt.timestep == 2e-3
    adapter = mm.MudAdapter(model, mujoco.MjData(model), ["sole"], mm.MudPatch(W25))
    with pytest.warns(DeprecationWarning, match=r"MudAdapter\.states .*MudAdapter\.state"):
        assert np.array_equal(adapter.states, adapter.state)
    with pytest.warns(DeprecationWarning, match=r"simulate_drop\(timestep=\.\.\.\).*dt="):
        res = mm.simulate_drop(5.0, W25, duration=0.004, timestep=2e-3)  # type: ignore[call-arg]
    assert res.time.tolist() == [0.0, 2e-3, 4e-3]


@needs_mujoco
@needs_jax
def test_mjx_patch_contact_make_patch_and_timestep() -> None:
    pytest.importorskip("mujoco.mjx")
    import mudforce.engines.mjx as mx

    with pytest.warns(DeprecationWarning, match=r"mjx\.Patch .*mjx\.MudPatch"):
        assert mx.Patch is mx.MudPatch  # type: ignore[attr-defined]
    with pytest.warns(DeprecationWarning, match=r"mjx\.Contact .*mjx\.MudState"):
        assert mx.Contact is mx.MudState  # type: ignore[attr-defined]
    with pytest.warns(DeprecationWarning, match=r"drop_model\(timestep=\.\.\.\).*dt="):
        model = mx.drop_model(5.0, timestep=2e-3)  # type: ignore[call-arg]
    assert model.opt.timestep == 2e-3
    with pytest.warns(DeprecationWarning, match=r"mjx\.make_patch .*mjx\.add_mud"):
        make_patch = mx.make_patch  # type: ignore[attr-defined]
    old = make_patch(model, sites=["sole"], mud=W25)
    new = mx.add_mud(model, ["sole"], W25)
    for a, b in zip(jax_leaves(old), jax_leaves(new), strict=True):
        assert np.array_equal(a, b)
    state = mx.init(new)
    with pytest.warns(DeprecationWarning, match=r"step\(contact=\.\.\.\).*state="), pytest.raises(AttributeError):
        mx.step(None, None, contact=state, patch=new)  # type: ignore[call-arg]  # (warned before it runs)
    with pytest.raises(InputError, match="give dt= only"):
        mx.simulate_drop(5.0, W25, timestep=2e-3, dt=1e-3)  # type: ignore[call-arg]  # (both: refused, nothing run)


def jax_leaves(tree: object) -> list[np.ndarray]:
    import jax

    return [np.asarray(leaf) for leaf in jax.tree_util.tree_leaves(tree)]


# ---------------------------------------------------------------- modules moved in 0.2 (the layout by concept)
def _needs(module: str) -> tuple[str, ...]:
    return {"mudforce.mjx": ("mujoco.mjx",), "mudforce.mujoco": ("mujoco",), "mudforce.jax3d": ("jax",)}.get(module, ())


def test_every_moved_module_is_the_new_one_and_warns() -> None:
    """`import mudforce.<old>` gives the very module object of the new path (one module, two names), warns with
    the new path, and a submodule of a moved package follows it; docs/api.md lists the same table."""
    import subprocess
    import sys
    from pathlib import Path

    from mudforce._plumbing.moved import MOVED

    table = (Path(__file__).resolve().parents[2] / "docs" / "api.md").read_text(encoding="utf-8")
    olds = [o for o in sorted(MOVED) if all(importlib.util.find_spec(n.split(".")[0]) for n in _needs(o))]
    code = "\n".join([
        "import importlib, sys, warnings",
        "import mudforce",
        "from mudforce._plumbing.moved import MOVED",
        f"for old in {olds!r}:",
        "    with warnings.catch_warnings(record=True) as seen:",
        "        warnings.simplefilter('always')",
        "        module = importlib.import_module(old)",
        "    new = importlib.import_module(MOVED[old])",
        "    assert module is new and module.__spec__.name == MOVED[old], old",
        "    assert any(w.category is DeprecationWarning and MOVED[old] in str(w.message) for w in seen), old",
        "import mudforce.calibration.fit as f",
        "assert f is sys.modules['mudforce.estimation.calibration.fit']",
        "print('ok')",
    ])
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]
    for old, new in MOVED.items():
        assert f"| `{old}` | `{new}` |" in table


def test_plotters_moved_with_their_results_warn() -> None:
    import mudforce.io.plotting as plotting
    from mudforce.steppers.plots import plot_result

    with pytest.warns(DeprecationWarning, match="mudforce.steppers.plots.plot_result"):
        assert plotting.plot_result is plot_result


@needs_mujoco
def test_patch_height_is_surface_height() -> None:
    import mudforce.engines.mujoco as mm

    with pytest.warns(DeprecationWarning, match=r"MudPatch\(height=\.\.\.\).*MudPatch\(surface_height=\.\.\.\)"):
        old = mm.MudPatch(W25, height=0.25, extent=(0.0, 1.0, 0.0, 1.0))
    new = mm.MudPatch(W25, 0.25, (0.0, 1.0, 0.0, 1.0))
    assert old == new and new.surface_height == 0.25
    with pytest.warns(DeprecationWarning, match=r"MudPatch\.height .*MudPatch\.surface_height"):
        assert new.height == 0.25  # type: ignore[misc]
    with pytest.raises(InputError, match="give surface_height= only"):
        mm.MudPatch(W25, surface_height=0.1, height=0.1)


@needs_mujoco
@needs_jax
def test_mjx_add_mud_height_is_surface_height() -> None:
    pytest.importorskip("mujoco.mjx")
    import mudforce.engines.mjx as mx

    model = mx.drop_model(5.0)
    with pytest.warns(DeprecationWarning, match=r"add_mud\(height=\.\.\.\).*surface_height="):
        old = mx.add_mud(model, ["sole"], W25, height=0.3)  # type: ignore[call-arg]
    new = mx.add_mud(model, ["sole"], W25, surface_height=0.3)
    for a, b in zip(jax_leaves(old), jax_leaves(new), strict=True):
        assert np.array_equal(a, b)
    with pytest.warns(DeprecationWarning, match=r"MudPatch\.height .*MudPatch\.surface_height"):
        assert float(new.height[0]) == pytest.approx(0.3)  # type: ignore[misc]
    with pytest.raises(InputError, match="give surface_height= only"):
        mx.add_mud(model, ["sole"], W25, height=0.3, surface_height=0.3)  # type: ignore[call-arg]
