"""Issue 20, items 1, 3, 4 and 5: folders never overwritten, JSON keys once, negative values, synth's bounds.

1. ``synth --out DIR`` replaces only a new, empty or earlier synth folder, whole
   (staged, swapped in); anything else in DIR is refused and left byte for byte.
3. A key twice in one JSON object (parameter file, manifest, fit.json) and a
   manifest foot in two units are refused, naming the key and the file.
4. ``--bias -0.5N`` is an option and its value, in every command; an option that
   may not be negative says so itself.
5. Every generator option of ``synth`` is bounded by what the readers accept.

Every command line runs through ``mudforce.cli.main`` in ONE subprocess
(``run_batch``, a module fixture), each in its own folder.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.estimation.calibration.dataset import MANIFEST_NAME, Dataset, Trial, load_dataset, save_dataset
from mudforce.model.foot import Foot
from mudforce_cli_harness import Run, assert_refused, run_batch, snapshot

SMALL = ["--repeats", "1", "--velocities", "40mm/s", "--hold", "1s", "--quiet"]
USER_CSV = "time_s,depth_m,force_N\n0,0,0\n"
GOOD_PARAMS = {"k_m_i": 260000.0, "b_m_i": 290000.0, "k_m_w": 1210000.0, "b_m_w": 1350000.0, "alpha": 40000.0,
               "beta": 0.54, "sigma_y": 6000.0, "zeta": 0.49, "omega_0": 2.23, "rho_m": 1840.0, "lambda": 0.013}
FOOT = '{"shape": "cuboid", "length_m": 0.051, "width_m": 0.038}'


def _fake_trial(name: str, n: int = 30) -> Trial:
    """A trial of the right form, without simulating (the test process stays free of the kernel)."""
    time = np.arange(n) * 0.01
    depth = 0.02 * np.sin(np.pi * time / time[-1]) - 0.005
    return Trial(name, 0.25, time, depth, np.maximum(depth, 0.0) * 1e3, 0.04, 1)


def _earlier_synth(folder: Path) -> None:
    """What an earlier ``mudforce synth`` left: a manifest with "synthetic", and the CSV it lists."""
    save_dataset(Dataset(foot=Foot.paper(), trials=(_fake_trial("w25_v40_r1.csv"),),
                         extra={"synthetic": {"seed": 0}}), folder)


def _manifest(foot: str = FOOT, trial: str = '"file": "t.csv", "water_content": 0.25') -> str:
    return f'{{"foot": {foot}, "trials": [{{{trial}}}]}}\n'


def _tree(root: Path) -> tuple[list[str], dict[str, Any]]:
    """Every path under ``root`` (folders too, hidden ones too) and every file's bytes."""
    return sorted(str(p.relative_to(root)) for p in root.rglob("*")), snapshot(root)


def _synth(out: str, *args: str) -> list[str]:
    return ["synth", "--out", out, *args]


def _setup(case: str, root: Path) -> None:
    if case in ("user-folder", "user-folder-force"):
        (root / "mine").mkdir()
        (root / "mine" / "w25_v10_r1.csv").write_text(USER_CSV)
    elif case == "measured-dataset-force":
        (root / "mine").mkdir()
        (root / "mine" / MANIFEST_NAME).write_text(_manifest(trial='"file": "w25_v40_r1.csv", "water_content": 0.25'))
        (root / "mine" / "w25_v40_r1.csv").write_text(USER_CSV)
    elif case in ("earlier", "earlier-force", "earlier-notes-force", "earlier-link-force"):
        _earlier_synth(root / "mine")
        if case == "earlier-notes-force":
            (root / "mine" / "notes.txt").write_text("my notes\n")
        if case == "earlier-link-force":
            (root / "precious.csv").write_text(USER_CSV)
            (root / "mine" / "w25_v40_r1.csv").unlink()
            (root / "mine" / "w25_v40_r1.csv").symlink_to(root / "precious.csv")
    elif case == "empty":
        (root / "mine").mkdir()
    elif case == "params-dup-alpha":
        text = json.dumps(GOOD_PARAMS, indent=2)
        (root / "p.json").write_text(text.replace('"beta"', '"alpha": 1.0,\n  "beta"'))
    elif case == "manifest-dup-water":
        (root / "ds").mkdir()
        (root / "ds" / MANIFEST_NAME).write_text(
            _manifest(trial='"file": "t.csv", "water_content": 0.15, "water_content": 0.25'))
        (root / "ds" / "t.csv").write_text(USER_CSV)
    elif case == "manifest-foot-two-units":
        (root / "ds").mkdir()
        (root / "ds" / MANIFEST_NAME).write_text(
            _manifest(foot='{"shape": "cuboid", "length_m": 0.051, "length_mm": 60, "width_m": 0.038}'))
        (root / "ds" / "t.csv").write_text(USER_CSV)
    elif case == "manifest-dup-nested":
        (root / "ds").mkdir()
        (root / "ds" / MANIFEST_NAME).write_text(
            '{"foot": ' + FOOT + ', "synthetic": {"seed": 1, "seed": 2}, "trials": [{"file": "t.csv", '
            '"water_content": 0.25}]}\n')
        (root / "ds" / "t.csv").write_text(USER_CSV)


#: id -> (argv, words of the refusal, or None for a command that must succeed)
CASES: dict[str, tuple[list[str], tuple[str, ...] | None]] = {
    # item 1: folders
    "user-folder": (_synth("mine", *SMALL), ("--out mine", "'w25_v10_r1.csv'", "not part of a mudforce synth")),
    "user-folder-force": (_synth("mine", "--force", *SMALL), ("--out mine", "'w25_v10_r1.csv'")),
    "measured-dataset-force": (_synth("mine", "--force", *SMALL), ("--out mine", "'dataset.json' and 1 more")),
    "earlier": (_synth("mine", *SMALL), ("--out mine", "--force")),
    "earlier-notes-force": (_synth("mine", "--force", *SMALL), ("'notes.txt'", "not part of a mudforce synth")),
    "earlier-link-force": (_synth("mine", "--force", *SMALL), ("'w25_v40_r1.csv'",)),
    "earlier-force": (_synth("mine", "--force", "--repeats", "1", "--velocities", "20mm/s", "--hold", "1s",
                             "--quiet"), None),
    "empty": (_synth("mine", *SMALL), None),
    # item 3: JSON keys once, one unit per quantity
    "params-dup-alpha": (["simulate", "--params", "p.json", "--out", "o.csv"], ("p.json", "'alpha'", "twice")),
    "manifest-dup-water": (["fit", "ds", "--out", "f.json"], ("dataset.json", "'water_content'", "twice")),
    "manifest-foot-two-units": (["fit", "ds", "--out", "f.json"], ("dataset.json", "length_m", "length_mm")),
    "manifest-dup-nested": (["fit", "ds", "--out", "f.json"], ("dataset.json", "'seed'", "twice")),
    # item 4: negative values reach their option
    "bias-negative": (_synth("neg", "--bias", "-0.5N", *SMALL), None),
    "approach-negative": (_synth("x", "--approach", "-5mm"), ("--approach", "'-5mm'", "must not be negative")),
    "force-noise-negative": (_synth("x", "--force-noise", "-0.1N"), ("--force-noise", "must not be negative")),
    "depth-noise-negative": (_synth("x", "--depth-noise", "-1mm"), ("--depth-noise", "must not be negative")),
    "bias-minus-inf": (_synth("x", "--bias", "-infN"), ("--bias", "'-infN'")),
    "jitter-negative": (_synth("x", "--motion", "gait", "--jitter", "-1e-3"), ("jitter", "-0.001")),
    # the gait's own words, 'jitter must be within ... got inf', named no option
    "jitter-huge": (_synth("x", "--motion", "gait", "--jitter", "1e400"), ("--jitter: inf must be within [0, 0.4]",)),
    # a NaN is not a number, not one out of range: "--jitter: nan must be within [0, 0.4]", "'nan' is a gain of nan,
    # outside [0.5, 2]" (and drop's "--tilt: 'nan' is outside -180 to 180 degrees")
    "jitter-nan": (_synth("x", "--motion", "gait", "--jitter", "nan"), ("--jitter: nan is not a finite number",)),
    "gain-nan": (_synth("x", "--force-gain", "nan"), ("--force-gain: 'nan' is not a finite number", "e.g. 1.05")),
    "gain-inf-percent": (_synth("x", "--force-gain", "-inf%"), ("--force-gain: '-inf%' is not a finite number",)),
    "height-negative": (["drop", "--mass", "5kg", "--water-content", "25%", "--height", "-5mm", "--out", "d.csv"],
                        ("--height", "must not be negative")),
    "rise-negative": (["simulate", "--water-content", "25%", "--rise", "-5mm", "--out", "o.csv"],
                      ("--rise", "-5mm")),
    "level-negative": (["identify", "t.csv", "--level", "-5%"], ("--level", "-5%", "e.g. 95%")),
    # the option's own example, not a water content's ("expected e.g. 25%" for a gain's uncertainty)
    "gain-uncertainty-negative": (["identify", "t.csv", "--force-gain-uncertainty", "-5%"],
                                  ("--force-gain-uncertainty: '-5%' must not be negative", "e.g. 5%")),
    # a level that rounds to 100 % was refused as if outside "between 0% and 100%"
    "level-rounds-to-100": (["identify", "t.csv", "--level", "99.99999999999%"],
                            ("--level: '99.99999999999%' rounds to 100%", "at most 99.9999999%")),
    "level-150": (["identify", "t.csv", "--level", "150%"], ("--level: '150%' must be below 100%",)),
    "reproduce-seed-negative": (["reproduce", "--out", "r", "--seed", "-3"], ("--seed", "-3")),
    # item 5: synth's options bounded by the readers
    "depth-noise-100m": (_synth("x", "--depth-noise", "100m"), ("--depth-noise 100m", "+-100 m", "at most 14.28 m")),
    "depth-at-the-bound": (_synth("x", "--depth", "100m", "--velocities", "1m/s"),
                           ("--depth 100m", "+-100 m", "no room left")),
    "gait-depth-noise": (_synth("x", "--motion", "gait", "--depth-noise", "20m"), ("--depth-noise 20m", "+-100 m")),
    "force-noise-big": (_synth("x", "--force-noise", "1e7N"), ("--force-noise", "1000 N")),
    "bias-big": (_synth("x", "--bias", "-2e4N"), ("--bias", "'-2e4N'", "+-10000 N")),
    "rate-too-low": (_synth("x", "--rate", "1e-4Hz"), ("--rate", "0.001 Hz")),
    "rate-few-samples": (_synth("x", "--rate", "1Hz", "--hold", "1s"), ("--rate 1Hz", "9 samples", "20")),
    "too-long": (_synth("x", "--hold", "1e9s", "--rate", "1e-3Hz", "--velocities", "0.01mm/s", "--repeats", "1"),
                 ("1e+09 s", "--hold")),  # (slow enough that a sample every 1000 s cuts no intrusion)
    "water-outside": (_synth("x", "--water-content", "25%,50%"), ("--water-content", "'50%'", "15% to 35%")),
    "force-beyond-readers": (_synth("x", "--foot", "cuboid:10mx10m", "--depth", "10m", "--velocities", "1m/s",
                                    "--hold", "1s", "--repeats", "1"), ("force reaches", "+-1e+07 N")),
    "at-the-bounds": (_synth("edge", "--bias", "-1e4N", "--force-noise", "1e3N", "--depth-noise", "10mm", *SMALL),
                      None),
}


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Run, Path, Any]]:
    roots = {}
    for case in CASES:
        root = tmp_path_factory.mktemp(case)
        _setup(case, root)
        roots[case] = root
    before = {case: _tree(root) for case, root in roots.items()}
    results = run_batch([(argv, roots[case]) for case, (argv, _) in CASES.items()])
    return {case: (run, roots[case], before[case]) for case, run in zip(CASES, results, strict=True)}


@pytest.mark.parametrize("case", [c for c, (_, words) in CASES.items() if words is not None])
def test_refused_with_one_line_and_nothing_touched(runs: dict[str, tuple[Run, Path, Any]],
                                                   case: str) -> None:
    run, root, before = runs[case]
    assert_refused(run, *CASES[case][1] or ())
    assert _tree(root) == before  # the user's files byte for byte; no output, no hidden sibling left


def test_synth_replaces_an_earlier_dataset_whole(runs: dict[str, tuple[Run, Path, Any]]) -> None:
    run, root, _ = runs["earlier-force"]
    assert (run.returncode, run.stderr) == (0, "")
    assert sorted(os.listdir(root / "mine")) == ["dataset.json", "w25_v20_r1.csv"]  # the old trial is gone
    assert os.listdir(root) == ["mine"]  # nothing staged left beside it
    assert [t.velocity for t in load_dataset(root / "mine").trials] == [0.02]
    run, root, _ = runs["empty"]
    assert (run.returncode, sorted(os.listdir(root / "mine"))) == (0, ["dataset.json", "w25_v40_r1.csv"])


def test_negative_bias_and_values_at_the_bounds_are_written_and_read(
        runs: dict[str, tuple[Run, Path, Any]]) -> None:
    run, root, _ = runs["bias-negative"]
    assert (run.returncode, run.stderr) == (0, "")
    manifest = json.loads((root / "neg" / MANIFEST_NAME).read_text())
    assert manifest["synthetic"]["bias_N"] == -0.5
    run, root, _ = runs["at-the-bounds"]
    assert (run.returncode, run.stderr) == (0, "")
    trial = load_dataset(root / "edge").trials[0]
    assert abs(np.median(trial.force[:5]) + 1e4) < 5e3  # the bias, -1e4 N, under 1e3 N of noise


def test_every_command_reads_a_negative_value_as_the_option_s_value() -> None:
    """One rule for all: each subcommand's parser takes ``-0.5N``, ``-5mm``, ``-1e-3``, ``-inf`` as values,
    and no option of any command could be mistaken for one."""
    import argparse

    from mudforce.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert len(sub.choices) == 9
    for name, command in sub.choices.items():
        for word in ("-0.5N", "-5mm", "-1e-3", "-.5", "-infN", "-nan"):
            assert command._negative_number_matcher.match(word), (name, word)
        assert not command._has_negative_number_optionals, name
        assert not command._negative_number_matcher.match("--out") and not command._negative_number_matcher.match("-h")


def test_synth_interrupted_while_writing_leaves_the_earlier_folder(tmp_path: Path,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """A Ctrl-C while the new dataset is written: exit 130, the earlier dataset byte for byte, nothing beside."""
    import mudforce.estimation.calibration.dataset as dataset_module
    import mudforce.estimation.calibration.synth as synth_module
    from mudforce.cli import main

    _earlier_synth(tmp_path / "mine")
    before = snapshot(tmp_path)
    trials = tuple(_fake_trial(f"w25_v{v}_r1.csv") for v in (10, 20, 40))
    monkeypatch.setattr(synth_module, "synthesize", lambda *a, **k: Dataset(foot=Foot.paper(), trials=trials))
    written = []

    def interrupted(trial: Trial) -> str:
        written.append(trial.name)
        if len(written) == 2:
            raise KeyboardInterrupt
        return "time_s,depth_m,force_N\n"

    monkeypatch.setattr(dataset_module, "_trial_csv", interrupted)
    assert main(["synth", "--out", str(tmp_path / "mine"), "--force", "--quiet"]) == 130
    assert len(written) == 2 and snapshot(tmp_path) == before and os.listdir(tmp_path) == ["mine"]


def test_load_json_refuses_a_key_twice_everywhere(tmp_path: Path) -> None:
    from mudforce.estimation.calibration.results import load_fit
    from mudforce.io import load_json

    path = tmp_path / "fit.json"
    path.write_text('{"model": "chen2024", "model": "other", "conditions": []}')
    with pytest.raises(InputError, match=r"fit\.json: the key 'model' appears twice"):
        load_fit(path)
    path.write_text('[{"a": 1}, {"b": {"c": 1, "c": 1}}]')  # even with equal values, at any depth
    with pytest.raises(InputError, match="'c' appears twice"):
        load_json(path, "file")
    path.write_text('{"a": {"c": 1}, "b": {"c": 2}}')  # one key in two objects is fine
    assert load_json(path, "file") == {"a": {"c": 1}, "b": {"c": 2}}


def test_save_dataset_writes_nothing_the_readers_refuse(tmp_path: Path) -> None:
    good = _fake_trial("a.csv")
    deep = Trial("b.csv", 0.25, good.time, good.depth * 1e4, good.force, 0.04, 1)
    short = _fake_trial("c.csv", n=10)
    crowded = Trial("d.csv", 0.25, 1e8 + good.time * 1e-3, good.depth, good.force, 0.04, 1)
    for bad, words in ((deep, r"b\.csv: the depth reaches 149\.7\d* m, beyond the \+-100 m"),
                       (short, r"c\.csv: only 10 samples"), (crowded, "d.csv: the times .* would not increase")):
        with pytest.raises(InputError, match=words):
            save_dataset(Dataset(foot=Foot.paper(), trials=(good, bad)), tmp_path / "out")
        assert not (tmp_path / "out").exists()
