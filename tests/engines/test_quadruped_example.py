"""examples/quadruped_in_mud.py at a small size: the trotting quadruped sinks a plausible amount and does not skate."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from load_example import load_example

pytest.importorskip("mujoco")


@pytest.fixture(scope="module")
def example():  # type: ignore[no-untyped-def]
    return load_example("quadruped_in_mud")


def test_the_quadruped_sinks_plausibly_and_slips_less_than_on_a_frictionless_floor(example) -> None:  # type: ignore[no-untyped-def]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # toes at the rigid ground's edge touch its side
        mud = example.run(1.5, resolution=0.01, start=0.3)  # all four toes in the dry mud
    skate = example.run(1.5, frictionless=True, start=0.3)
    dry = mud.region == 0
    # a toe's steps in the dry mud before it first reaches the wet one: a toe that slides back across the
    # boundary arrives in the dry patch as deep as the wet mud let it sink, with a fresh state there
    before_wet = np.cumsum(mud.region == 1, axis=0) == 0
    deepest = float(np.nanmax(np.where(dry & before_wet, mud.sinkage, np.nan)))
    assert 0.003 < deepest < 0.05  # a 11.6 kg robot on 50 mm toes in 15 % mud: a few cm at most
    slip = float(np.sum(mud.slip_speed * dry))
    assert slip < 0.5 * float(np.sum(skate.slip_speed))
    assert np.sum(mud.power) > 0.0  # the mud takes energy


def test_the_command_line_trots_and_refuses_bad_values_in_one_line(example, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """`python examples/quadruped_in_mud.py` failed on its defaults ("unknown quantity kind 's'"); a bad value is one
    line and exit status 2."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # toes at the rigid ground's edge touch its side
        example.main(["--duration", "0.5s", "--out", str(tmp_path / "q.png")])
    printed = capsys.readouterr().out
    assert printed.startswith("t   0.500  x ") and (tmp_path / "q.png").is_file()
    for argv, message in ((["--duration", "6"], "--duration: '6' has no unit"),
                          (["--dry", "50%"], "water content 0.5 is outside Table I's range"),
                          (["--dt", "20ms"], "--dt must be within 0.1ms to 10ms, got 20ms"),
                          (["--duration", "0.2s"], "--duration must be from one gait cycle (0.5s) to 600s"),
                          # found only when saved, after the trot: matplotlib's ValueError, a traceback
                          (["--out", "q.xyz"], "--out: 'q.xyz' must end in .png (only PNG is written)")):
        with pytest.raises(SystemExit) as info:
            example.main(argv)
        assert info.value.code == 2 and message in capsys.readouterr().err


def test_the_3d_adapter_s_state_replays_a_trot_bit_for_bit(example) -> None:  # type: ignore[no-untyped-def]
    """``MudAdapter3D.state`` with MuJoCo's own state (``mj_getState``, ``mjSTATE_INTEGRATION``) replays a trot
    across two muds bit for bit; a state of another adapter is refused in one line and nothing changes."""
    import mujoco

    from mudforce import InputError
    from mudforce.engines.mujoco import MudAdapter3D, MudPatch
    from mudforce.model.parameters import MudParameters

    model = example.quadruped_spec(dt=2e-3).compile()
    data = mujoco.MjData(model)
    data.qpos[0] = 0.45  # the front toes near the boundary between the two muds: feet change patch while replayed
    patches = [MudPatch(MudParameters.from_water_content(0.15), extent=(0.0, 0.7, -1.0, 1.0)),
               MudPatch(MudParameters.from_water_content(0.30), extent=(0.7, 50.0, -1.0, 1.0))]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        mud = MudAdapter3D(model, data, example.FEET, patches, resolution=0.02)

        def trot(steps: int) -> np.ndarray:
            out = np.empty((steps, model.nq))
            for k in range(steps):
                data.ctrl[:] = example.trot(data.time)
                mud.step()
                out[k] = data.qpos
            return out

        trot(150)
        kind = mujoco.mjtState.mjSTATE_INTEGRATION
        physics = np.empty(mujoco.mj_stateSize(model, kind))
        mujoco.mj_getState(model, data, physics, kind)
        saved = mud.state
        first = trot(150)
        mujoco.mj_setState(model, data, physics, kind)
        mud.state = saved
        again = trot(150)
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first[0], first[-1])  # it moved
    other = MudAdapter3D(model, mujoco.MjData(model), example.FEET[:2], patches[:1], resolution=0.02).state
    before = mud.state
    with pytest.raises(InputError, match="taken from an adapter of the same feet, shapes and patches"):
        mud.state = other
    with pytest.raises(InputError, match="AdapterState3D"):
        mud.state = "saved"  # type: ignore[assignment]
    after = mud.state
    assert all(np.array_equal(a, b) for a, b in zip(before.arrays, after.arrays, strict=True))
