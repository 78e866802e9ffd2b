"""Calibration inputs and helpers: dataset loading and validation, motion fit, tare, drag, identify (their
command lines: tests/cli/test_fit_cli.py, test_fit_drag_cli.py, test_identify_cli.py)."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from mudforce.errors import InputError
from mudforce.estimation.calibration import (
    fit_drag,
    fit_motion,
    identify_water_content,
    load_dataset,
    load_trial,
    parse_foot,
    prepare_trial,
    synthesize,
    tare,
)
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.calibration.preprocess import snap_reversal
from mudforce.model.foot import Foot
from mudforce.motions.protocol import Protocol


@pytest.fixture(scope="module")
def small(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A written synthetic dataset: W = 25%, 10 and 40 mm/s, one repeat each."""
    out = tmp_path_factory.mktemp("ds")
    synthesize(out, water_contents=[0.25], velocities=[0.01, 0.04], repeats=1, seed=3)
    return out


# ------------------------------------------------------------------------ dataset loading
def test_roundtrip_folder(small: Path) -> None:
    ds = load_dataset(small)
    assert [t.name for t in ds.trials] == ["w25_v10_r1.csv", "w25_v40_r1.csv"]
    assert ds.water_contents == [0.25]
    assert ds.trials[0].velocity == 0.01 and ds.trials[0].repeat == 1
    assert_allclose(ds.foot.area, 0.051 * 0.038)
    assert ds.extra is not None and "synthetic" in ds.extra
    # the manifest itself is accepted too
    assert len(load_dataset(small / "dataset.json").trials) == 2


def test_tidy_csv_and_mm_columns(small: Path, tmp_path: Path) -> None:
    ds = load_dataset(small)
    lines = ["trial,water_content,time_s,depth_mm,force_N"]
    for t in ds.trials:
        rows = zip(t.time, t.depth, t.force, strict=True)
        lines += [f"{t.name},0.25,{float(a)!r},{float(z) * 1e3!r},{float(f)!r}" for a, z, f in rows]
    path = tmp_path / "tidy.csv"
    path.write_text("\n".join(lines) + "\n")
    tidy = load_dataset(path)
    assert [t.name for t in tidy.trials] == [t.name for t in ds.trials]
    assert_allclose(tidy.trials[1].depth, ds.trials[1].depth, rtol=1e-12)


def _manifest(folder: Path, data: object) -> Path:
    (folder / "dataset.json").write_text(json.dumps(data))
    return folder


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda m: m.pop("foot"), 'missing "foot"'),
        (lambda m: m.update(trials=[]), '"trials" must be a non-empty list'),
        (lambda m: m.update(extra=1), "unknown key(s) extra"),
        (lambda m: m["foot"].update(shape="blob"), "foot.shape is 'blob'"),
        (lambda m: m["foot"].update(width_m=-1), "foot.width_m is -1"),
        (lambda m: m["trials"][0].update(water_content=25), "water_content is 25"),
        (lambda m: m["trials"][0].update(water_content="25%"), "water_content is '25%'"),
        (lambda m: m["trials"][0].pop("water_content"), 'missing "water_content"'),
        (lambda m: m["trials"][0].update(file="nope.csv"), "nope.csv not found"),
        (lambda m: m["trials"][1].update(file="w25_v10_r1.csv"), "listed twice"),
        (lambda m: m["trials"][0].update(velocity_m_s=0), "velocity_m_s is 0"),
        (lambda m: m["trials"][0].update(speed=1), "unknown key(s) speed"),
        # 10**400 was taken (a written copy could not be read back), as a Trial's was
        (lambda m: m["trials"][0].update(repeat=1001), "trials[0]: repeat is 1001; expected an integer in [0, 1000]"),
    ],
)
def test_bad_manifests(small: Path, tmp_path: Path, change: object, message: str) -> None:
    for f in small.glob("*.csv"):
        (tmp_path / f.name).write_text(f.read_text())
    manifest = json.loads((small / "dataset.json").read_text())
    change(manifest)  # type: ignore[operator]
    _manifest(tmp_path, manifest)
    with pytest.raises(InputError, match=None) as info:
        load_dataset(tmp_path)
    assert message in str(info.value)
    assert "\n" not in str(info.value)
    assert str(tmp_path / "dataset.json") in str(info.value)


def test_one_file_under_two_names_is_listed_twice(small: Path, tmp_path: Path) -> None:
    """A link to a trial file listed beside it counted that trial twice in every fit, silently (2026-11-29)."""
    for f in small.glob("*.csv"):
        (tmp_path / f.name).write_text(f.read_text())
    manifest = json.loads((small / "dataset.json").read_text())
    first = manifest["trials"][0]["file"]
    for link, kind in (("again.csv", os.symlink), ("hard.csv", os.link)):
        kind(tmp_path / first, tmp_path / link)
        changed = json.loads(json.dumps(manifest))
        changed["trials"][1]["file"] = link
        _manifest(tmp_path, changed)
        with pytest.raises(InputError) as info:
            load_dataset(tmp_path)
        assert f"trials[1]: file '{link}' is '{first}' under another name, listed twice" in str(info.value)
        assert "\n" not in str(info.value)


def test_malformed_json_and_missing_folder(tmp_path: Path) -> None:
    (tmp_path / "dataset.json").write_text('{"foot": ')
    with pytest.raises(InputError, match="malformed JSON at line 1"):
        load_dataset(tmp_path)
    with pytest.raises(InputError, match="not found"):
        load_dataset(tmp_path / "missing")
    (tmp_path / "sub").mkdir()
    with pytest.raises(InputError, match=r"no dataset\.json"):
        load_dataset(tmp_path / "sub")


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        (["time_s,depth_m,force_N", "0,0.1,1", "0.01,0.1"], "row 3 has 2 fields"),
        (["time_s,depth_m,force_N", "0,0.1,1", "0.01,nan,1"], "row 3, column depth_m: 'nan' is not finite"),
        (["time_s,depth_m,force_N", "0,0.1,1", "0.01,abc,1"], "row 3, column depth_m: 'abc' is not a number"),
        (["time_s,depth_m", "0,0.1"], "missing column force_N"),
        (["time_s,depth_m,force_N"], "no data rows"),
    ],
)
def test_bad_trial_csv(small: Path, tmp_path: Path, rows: list[str], message: str) -> None:
    manifest = json.loads((small / "dataset.json").read_text())
    manifest["trials"] = manifest["trials"][:1]
    (tmp_path / "w25_v10_r1.csv").write_text("\n".join(rows) + "\n")
    _manifest(tmp_path, manifest)
    with pytest.raises(InputError) as info:
        load_dataset(tmp_path)
    assert message in str(info.value) and "w25_v10_r1.csv" in str(info.value)


def test_short_and_backwards_trials(tmp_path: Path) -> None:
    path = tmp_path / "t.csv"
    path.write_text("time_s,depth_m,force_N\n" + "".join(f"{i * 0.01},0,0\n" for i in range(5)))
    with pytest.raises(InputError, match="only 5 samples"):
        load_trial(path)
    with pytest.raises(InputError, match="missing column water_content"):
        load_dataset(path)  # not a tidy CSV
    rows = [f"{0.01 * i},{-0.001},{0.0}" for i in range(30)]
    rows[10] = "0.05,0,0"
    path.write_text("time_s,depth_m,force_N\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputError, match="row 12, column time_s: time goes backwards"):
        load_trial(path)


def test_time_errors_name_the_files_own_row_and_column(tmp_path: Path) -> None:
    """Rows count the file's lines (blank lines included) and the column is the file's spelling."""
    rows = [f"{10 * i},{-0.001},{0.0}" for i in range(30)]
    rows[10] = "50,0,0"
    path = tmp_path / "ms.csv"
    path.write_text("time_ms,depth_m,force_N\n\n" + "\n".join(rows) + "\n")  # a blank line after the header
    with pytest.raises(InputError, match="row 13, column time_ms: time goes backwards"):
        load_trial(path)
    tidy = tmp_path / "tidy.csv"
    lines = [f"a,0.25,{0.01 * i},-0.001,0" for i in range(30)]
    lines[10] = "a,0.25,0.01,-0.001,0"
    tidy.write_text("trial,water_content,time_s,depth_m,force_N\n\n" + "\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"tidy.csv \(trial 'a'\): row 13, column time_s: time goes backwards"):
        load_dataset(tidy)


def test_parse_foot() -> None:
    assert parse_foot("paper") == Foot.paper()
    assert_allclose(parse_foot("cuboid:51mm,38mm").area, 0.051 * 0.038)
    assert_allclose(parse_foot("disc:40mm").width, 0.04)
    assert_allclose(parse_foot("custom:19.38cm2,38mm").area, 19.38e-4)
    # one parser for every --foot: the forms of `mudforce simulate` work here too
    assert parse_foot("cuboid:51mmx38mm") == parse_foot("cuboid:51mm,38mm")
    assert parse_foot("area:19.38cm2,width:38mm") == parse_foot("custom:19.38cm2,38mm")
    with pytest.raises(InputError, match="expected paper, cuboid"):
        parse_foot("triangle:3mm")


# ------------------------------------------------------------------------ motion, reversal, tare
@pytest.mark.parametrize("velocity", [0.01, 0.02, 0.04])
def test_reversal_located_to_a_small_fraction_of_a_sample(velocity: float) -> None:
    """Motion capture noise 0.05 mm at 100 Hz: the corners come out to < 0.15 sample (rms < 0.06)."""
    protocol = Protocol.paper(velocity=velocity, approach=0.005)
    time, depth = protocol.sample()
    corners, _ = protocol.breakpoints()
    rng = np.random.default_rng(7)
    errors = []
    for _ in range(10):
        motion = fit_motion(time, depth + 5e-5 * rng.standard_normal(time.size))
        errors.append(np.array(motion.corner_time[1:3]) - corners[1:3])
    err = np.array(errors) / 0.01  # in samples
    assert np.max(np.abs(err)) < 0.15
    assert np.sqrt(np.mean(err**2)) < 0.06


def test_reversal_sample_settled_by_the_force_drop() -> None:
    """A reversal on a sample: the motion alone is ambiguous, the force drop decides."""
    ds = synthesize(water_contents=[0.25], velocities=[0.01], repeats=1, seed=1, depth_noise=5e-5)
    tr = ds.trials[0]
    true_reversal = 0.005 / 0.01 + 0.02 / 0.01 + 6.0  # exactly on sample 850
    motion = fit_motion(tr.time, tr.depth)
    for shift in (-0.2e-2, 0.2e-2):  # either side of the sample, within the ambiguity
        shifted = type(motion)((motion.corner_time[0], motion.corner_time[1], true_reversal + shift,
                                motion.corner_time[3]), motion.start_depth, motion.hold_depth, motion.end_depth,
                               motion.depth_noise)
        snapped = snap_reversal(tr.time, tr.force, shifted)
        assert true_reversal <= snapped.reversal_time < true_reversal + 0.01 * 0.01
    prepared = prepare_trial(tr)
    assert prepared.reversal_index == 851  # samples 0..850 are before the withdrawal


def test_tare_removes_bias() -> None:
    ds = synthesize(water_contents=[0.25], velocities=[0.01], repeats=1, seed=5, force_noise=0.3, bias=2.5)
    tr = ds.trials[0]
    motion = fit_motion(tr.time, tr.depth)
    bias, noise, count = tare(tr.time, tr.force, motion)
    assert count == 50  # contact at 0.5 s: samples 0 to 0.49 s
    assert abs(bias - 2.5) < 4 * 0.3 / np.sqrt(count)
    assert 0.2 < noise < 0.4
    assert_allclose(motion.contact_time, 0.5, atol=2e-3)


def test_trial_starting_in_the_mud_estimates_its_bias() -> None:
    """The protocol refinement refuses it; the general path accepts it and leaves the bias to the fit."""
    time = np.arange(0, 5, 0.01)
    depth = np.interp(time, [0, 1, 3, 5], [0.005, 0.02, 0.02, -0.01])
    force = np.random.default_rng(0).standard_normal(time.size)
    with pytest.raises(InputError, match="starts 5 mm below the surface"):
        prepare_trial(Trial("x.csv", 0.25, time, depth, force), protocol=True)
    prepared = prepare_trial(Trial("x.csv", 0.25, time, depth, force))
    assert prepared.motion is None and prepared.bias_estimated and prepared.bias == 0.0
    with pytest.raises(InputError, match="never goes below the surface"):
        prepare_trial(Trial("y.csv", 0.25, time, -0.01 + 0 * time, np.zeros_like(time)))


# ------------------------------------------------------------------------ drag, identify
def test_fit_drag_recovers_lambda() -> None:
    """Synthetic sliding runs: 10 speeds x 3 repeats, force noise 2% of the largest force."""
    area, rho = Foot.paper().area, 1840.0
    v = np.repeat(np.linspace(0.1, 1.0, 10), 3)
    clean = 0.013 * rho * area * v**2
    rng = np.random.default_rng(11)
    lams, ses = [], []
    for _ in range(40):
        fit = fit_drag(v, clean + 0.02 * clean.max() * rng.standard_normal(v.size), area, rho_m=rho)
        lams.append(fit.lambda_)
        ses.append(fit.stderr)
    lams_a = np.array(lams)
    assert abs(np.mean(lams_a) - 0.013) < 3 * np.std(lams_a) / np.sqrt(40)
    # the standard error is honest: it matches the scatter over repeats to 30%
    assert 0.7 < np.mean(ses) / np.std(lams_a) < 1.3
    with pytest.raises(InputError, match="more than one non-zero speed"):
        fit_drag([0.0, 0.0, 0.0], [0.0, 1.0, 2.0], area)


@pytest.mark.parametrize("water_content", [0.15, 0.22, 0.35])
def test_identify_water_content(water_content: float) -> None:
    ds = synthesize(water_contents=[water_content], velocities=[0.02], repeats=1, seed=2, force_noise=0.3)
    result = identify_water_content(ds.trials[0], ds.foot)
    assert abs(result.water_content - water_content) < 0.005
    lo, hi = result.interval
    assert lo - 1e-6 <= water_content <= hi + 1e-6
    assert result.rmse < 0.36




@pytest.mark.parametrize(("fields", "message"), [
    ({"water_content": "0.25"}, "t.csv: water_content is '0.25'; expected a number in (0, 1)"),
    ({"water_content": None}, "t.csv: water_content is None; expected a number in (0, 1)"),
    ({"water_content": 25.0}, "t.csv: water_content is 25.0; expected a number in (0, 1)"),
    ({"name": 3}, "a trial's name must be a str, got int"),
    ({"velocity": "fast"}, "t.csv: velocity is 'fast'; expected None or a number > 0 [m/s]"),
    ({"velocity": -0.01}, "t.csv: velocity is -0.01; expected None or a number > 0 [m/s]"),
    ({"repeat": 1.5}, "t.csv: repeat is 1.5; expected None or an integer in [0, 1000]"),
    # at most MAX_REPEATS: 10**400 was taken and saved, and the saved manifest could not be read back ("an integer
    # of 401 digits"); 10**5000 made the writer say "a result is not finite"
    pytest.param({"repeat": 10**400}, "t.csv: repeat is an integer of 1329 bits; expected None or an integer in [0, "
                 "1000]", id="r"),
    ({"repeat": 1001}, "t.csv: repeat is 1001; expected None or an integer in [0, 1000]"),
    ({"repeat": -1}, "t.csv: repeat is -1; expected None or an integer in [0, 1000]"),
    # math.isnan(10**5000) and float(10**400) raised OverflowError
    pytest.param({"water_content": 10**5000}, "t.csv: water_content is an integer of 16610 bits; expected", id="w"),
    pytest.param({"velocity": 10**400}, "t.csv: velocity is an integer of 1329 bits; expected None", id="v"),
])
def test_a_trial_made_in_python_has_its_labels_checked(fields: dict[str, object], message: str) -> None:
    """A Trial's labels were taken as given: water_content="x" (or 25 for 25 %) was fitted and came back as the
    fit's water_content "x", a name that was not a string broke messages later; now refused as a manifest's
    are. An unknown water content (NaN, load_trial's default) is still taken."""
    t = np.arange(30) * 0.01
    base = {"name": "t.csv", "water_content": 0.25, "time": t, "depth": 0.01 * t, "force": t}
    with pytest.raises(InputError) as info:
        Trial(**{**base, **fields})  # type: ignore[arg-type]
    assert str(info.value).startswith(message), str(info.value)
    unknown = Trial(**{**base, "water_content": float("nan"), "velocity": np.float64(0.01),  # type: ignore[arg-type]
                       "repeat": np.int64(2)})
    assert np.isnan(unknown.water_content) and type(unknown.repeat) is int and type(unknown.velocity) is float


@pytest.mark.parametrize(("water_content", "message"), [
    ("0.25", "t.csv: water_content is '0.25'; expected a number in (0, 1)"),  # float() parsed it
    (b"0.25", "t.csv: water_content is b'0.25'; expected a number in (0, 1)"),  # float() parsed it
    ([0.25], "t.csv: water_content is [0.25]; expected a number in (0, 1)"),  # float() raised TypeError
])
def test_load_trial_checks_the_water_content_as_a_trial_does(tmp_path: Path, water_content: object,
                                                              message: str) -> None:
    path = tmp_path / "t.csv"
    path.write_text("time_s,depth_m,force_N\n" + "".join(f"{i * 0.01},0,{i}\n" for i in range(30)))
    with pytest.raises(InputError) as info:
        load_trial(path, water_content)  # type: ignore[arg-type]
    assert str(info.value).startswith(message), str(info.value)
    assert load_trial(path, np.float64(0.25)).water_content == 0.25 and math.isnan(load_trial(path).water_content)


_T30 = np.arange(30) * 0.01
_TRIAL30 = Trial("t.csv", 0.25, _T30, 0.01 * _T30, _T30)


@pytest.mark.parametrize(("fields", "message"), [
    # the fits and save_dataset raised AttributeError ('str' object has no attribute 'area' / 'shape')
    ({"foot": "paper"}, "a Dataset's foot must be a Foot, got str"),
    # TypeError: 'Trial' object is not iterable
    ({"trials": _TRIAL30}, "a Dataset's trials must be a tuple of Trial, got one Trial: pass (trial,)"),
    ({"trials": (3,)}, "a Dataset's trials[0] must be a Trial, got int"),  # AttributeError: no attribute 'name'
    # fit_dataset returned an empty FitResult; save_dataset wrote a dataset.json that load_dataset refuses
    ({"trials": ()}, "a Dataset's trials must be a non-empty tuple of Trial, got an empty tuple"),
    # written into dataset.json, which load_dataset then refused (unknown key(s) notes); "trials" replaced the trials
    ({"extra": {"notes": "x"}}, "a Dataset's extra holds notes; expected only description and synthetic (what "
                                "dataset.json keeps)"),
    ({"extra": {"trials": []}}, "a Dataset's extra holds trials; expected only description and synthetic (what "
                                "dataset.json keeps)"),
    ({"extra": "x"}, "a Dataset's extra must be a mapping or None, got str"),
], ids=["foot-str", "one-trial", "not-trials", "no-trials", "extra-notes", "extra-trials", "extra-str"])
def test_a_dataset_made_in_python_is_checked_when_made(fields: dict[str, object], message: str) -> None:
    from mudforce.estimation.calibration import Dataset

    with pytest.raises(InputError) as info:
        Dataset(**{"foot": Foot.paper(), "trials": (_TRIAL30,), **fields})  # type: ignore[arg-type]
    assert str(info.value) == message
    listed = Dataset(Foot.paper(), [_TRIAL30], extra={"description": "x"})  # type: ignore[arg-type]
    assert listed.trials == (_TRIAL30,)


def test_what_is_no_dataset_is_refused_by_the_fits_and_save_dataset(tmp_path: Path) -> None:
    """A list of trials raised AttributeError ('list' object has no attribute 'conditions'), a dict given to
    save_dataset AttributeError (no attribute 'trials')."""
    from mudforce.estimation.calibration import fit_by_velocity, fit_dataset, save_dataset

    for fit in (fit_dataset, fit_by_velocity):
        with pytest.raises(InputError, match=r"^dataset must be a Dataset \(load_dataset, synthesize\), got list; "
                                             r"fit a list of trials of one mud with fit_condition$"):
            fit([_TRIAL30], quiet=True)  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"^save_dataset takes a Dataset, got dict$"):
        save_dataset({"trials": []}, tmp_path / "out")  # type: ignore[arg-type]
    assert not (tmp_path / "out").exists()


def test_save_dataset_refuses_an_unknown_water_content_and_writes_nothing_it_cannot_finish(tmp_path: Path) -> None:
    """A trial of unknown water content (NaN) made the manifest's writer say "a result is not finite" after the
    trial's CSV was written, as a NaN in extra did: a folder with a CSV and no dataset.json."""
    from mudforce.estimation.calibration import Dataset, save_dataset

    unknown = Trial("t.csv", math.nan, _T30, 0.01 * _T30, _T30)
    with pytest.raises(InputError, match=r"^trial t.csv has no water content \(NaN\), and dataset.json needs each "
                                         r"trial's; give it its water_content \(e.g. 0.25\)$"):
        save_dataset(Dataset(Foot.paper(), (unknown,)), tmp_path / "a")
    with pytest.raises(InputError, match=r"^a result is not finite"):
        save_dataset(Dataset(Foot.paper(), (_TRIAL30,), extra={"description": math.nan}), tmp_path / "b")
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()


def test_load_dataset_refuses_a_name_the_file_system_cannot_take_in_one_line(tmp_path: Path) -> None:
    """A name too long raised Path.is_dir()'s OSError (mudforce fit LONG exited 1, as for a failing disk); a NUL
    said 'not found' with the NUL printed raw."""
    with pytest.raises(InputError, match=r"^\S+x: cannot read \(File name too long\)$"):
        load_dataset(tmp_path / ("x" * 300))
    with pytest.raises(InputError, match=r"^the file name 'a\\x00b' contains a NUL character; expected a dataset "
                                         r"folder, its dataset.json, or a tidy CSV$"):
        load_dataset("a\x00b")
