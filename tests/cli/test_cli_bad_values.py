"""One line and exit 2, never a traceback nor a non-finite output, whatever the values (issue 15, items 4-6).

Every case runs through ``mudforce.cli.main`` in one subprocess
(``run_batch``), each in its own folder; refused cases must leave that
folder exactly as it was.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest

from mudforce import Foot
from mudforce.estimation.calibration.synth import synthesize
from mudforce_cli_harness import Run, assert_refused, run_batch, snapshot

GOOD_PARAMS = '{"k_m_i": 260000.0, "b_m_i": 290000.0, "k_m_w": 1210000.0, "b_m_w": 1350000.0, "alpha": 40000.0, ' \
              '"beta": 0.54, "sigma_y": 6000.0, "zeta": 0.49, "omega_0": 2.23, "rho_m": 1840.0, "lambda": 0.013}'
TRAJ = "time_s,depth_m\n" + "".join(f"{0.01 * k:.2f},{0.0005 * k:.4f}\n" for k in range(30))
SLIDING = "velocity_m_s,force_N\n0.1,0.5\n0.2,1.9\n0.3,4.3\n-0.2,-1.8\n"
FOOT = {"shape": "cuboid", "length_m": 0.051, "width_m": 0.038}


def _manifest(trials: list[dict[str, object]], foot: object = FOOT) -> str:
    return json.dumps({"foot": foot, "trials": trials})


def _sim(*args: str) -> list[str]:
    return ["simulate", "--water-content", "25%", *args, "--out", "out.csv"]


def _traj(text: str) -> list[str]:
    return ["simulate", "--water-content", "25%", "--trajectory", "traj.csv", "--out", "out.csv"]


#: (id, argv, files, words); files: name -> text, "@trial" is replaced by a synthetic trial's CSV
REFUSED: list[tuple[str, list[str], dict[str, str], tuple[str, ...]]] = [
    # item 5: huge and odd values, one line each
    ("foot-1e300m-simulate", _sim("--foot", "disc:1e300m"), {}, ("--foot", "too large")),
    ("foot-1e300m-identify", ["identify", "t.csv", "--foot", "disc:1e300m"], {"t.csv": "@trial"}, ("--foot",)),
    ("foot-1e300m-fit-drag", ["fit-drag", "s.csv", "--foot", "cuboid:1e300mx1mm"], {"s.csv": SLIDING}, ("--foot",)),
    ("foot-too-small", _sim("--foot", "disc:10um"), {}, ("disc diameter", "within")),
    ("params-400-digits", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace("260000.0", "1" + "0" * 400)}, ("p.json", "401 digits")),
    ("params-5000-digits", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace("260000.0", "1" + "0" * 5000)}, ("p.json", "digits")),
    ("params-1e400", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace("260000.0", "1e400")}, ("p.json", "overflows")),
    ("params-NaN-token", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace("260000.0", "NaN")}, ("p.json", "NaN")),
    ("params-nested", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": "[" * 100_000 + "]" * 100_000}, ("p.json", "nested too deeply")),
    ("params-denormal-stiffness", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace("260000.0", "1e-310")}, ("k_m_i", "within")),
    ("params-zeta-1e160", ["simulate", "--params", "p.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS.replace('"zeta": 0.49', '"zeta": 1e160')}, ("zeta", "within")),
    ("manifest-400-digits", ["fit", "ds", "--out", "f.json"],
     {"ds/dataset.json": _manifest([{"file": "a.csv", "water_content": 0.25, "repeat": int("1" * 400)}])},
     ("dataset.json", "digits")),
    ("manifest-nested", ["fit", "ds", "--out", "f.json"], {"ds/dataset.json": "{" + '"a":[' * 50_000},
     ("dataset.json",)),
    ("fix-nan", ["fit", "ds", "--out", "f.json", "--fix", "beta=nan"], {}, ("--fix", "beta=nan")),
    ("fix-twice", ["fit", "ds", "--out", "f.json", "--fix", "beta=0.5,beta=0.6"], {}, ("--fix", "twice")),
    ("free-and-fix", ["fit", "ds", "--out", "f.json", "--free", "lambda", "--fix", "lambda=0.01"], {},
     ("--free", "--fix", "conflict")),
    # an empty value is refused, not taken as "not given" (the manifest's foot, no shared parameter, silently)
    ("fit-empty-foot", ["fit", "ds", "--out", "f.json", "--foot", ""], {}, ("--foot", "''")),
    ("fit-empty-shared", ["fit", "ds", "--out", "f.json", "--shared", ""], {}, ("--shared", "empty list")),
    ("fit-empty-free", ["fit", "ds", "--out", "f.json", "--free", ""], {}, ("--free", "empty list")),
    ("fit-empty-fix", ["fit", "ds", "--out", "f.json", "--fix", ""], {}, ("--fix", "empty list")),
    ("fit-seed-negative", ["fit", "ds", "--out", "f.json", "--seed", "-1"], {}, ("--seed",)),
    ("synth-seed-negative", ["synth", "--out", "new", "--seed", "-1"], {}, ("--seed",)),
    ("synth-depth-1e300m", ["synth", "--out", "new", "--depth", "1e300m"], {}, ("--depth", "too large")),
    ("synth-depth-beyond-model", ["synth", "--out", "new", "--depth", "500m"], {}, ("--depth", "100 m")),
    ("synth-hold-1e300s", ["synth", "--out", "new", "--hold", "1e300s"], {}, ("--hold",)),
    ("synth-rate-huge", ["synth", "--out", "new", "--rate", "1e8Hz"], {}, ("samples",)),
    # a gait's walks are as long as --duration: the advice named --hold and --depth, which a gait refuses
    ("synth-gait-too-many-samples", ["synth", "--out", "new", "--motion", "gait", "--duration", "1e9s"], {},
     ("3e+11 samples", "lower --rate, --duration or the number of trials")),
    ("synth-repeats-100000", ["synth", "--out", "new", "--repeats", "100000"], {}, ("--repeats",)),
    # int() and float() took "1_0" as 10 (and other scripts' digits); the command line reads plain ASCII numbers
    # a seed or count past 4,300 digits was echoed digit by digit (argparse's "invalid int value: '999...'", the
    # range checks' "--repeats: 999... must be within"); now by its size
    ("synth-seed-5000-digits", ["synth", "--out", "new", "--seed", "9" * 5000], {},
     ("argument --seed: an integer of 5000 digits is too large (at most 4300 digits are read)",)),
    ("synth-repeats-4000-digits", ["synth", "--out", "new", "--repeats", "9" * 4000], {},
     ("--repeats: an integer of 13288 bits must be within [1, 1000]",)),
    ("reproduce-seed-5000-digits", ["reproduce", "--out", "new", "--seed", "9" * 5000], {},
     ("--seed: an integer of 5000 digits is too large", "expected an integer in [0, 4294967295]")),
    ("reproduce-jobs-4000-digits", ["reproduce", "--out", "new", "--jobs", "9" * 4000], {},
     ("--jobs: an integer of 13288 bits is out of range",)),
    ("synth-repeats-underscore", ["synth", "--out", "new", "--repeats", "1_0"], {}, ("--repeats", "'1_0'")),
    ("synth-seed-underscore", ["synth", "--out", "new", "--seed", "1_0"], {}, ("--seed", "'1_0'")),
    ("fit-seed-underscore", ["fit", "ds", "--out", "f.json", "--seed", "1_0"], {}, ("--seed", "'1_0'")),
    ("synth-gain-underscore", ["synth", "--out", "new", "--force-gain", "1_0%"], {}, ("--force-gain", "'1_0%'")),
    ("synth-jitter-arabic-digits", ["synth", "--out", "new", "--motion", "gait", "--jitter", "\u0660.\u0661"], {},
     ("--jitter",)),
    ("synth-jitter-underscore", ["synth", "--out", "new", "--motion", "gait", "--jitter", "0_1"], {},
     ("--jitter", "invalid float value: '0_1'")),
    ("synth-repeated-water", ["synth", "--out", "new", "--water-content", "25%,25%"], {},
     ("--water-content", "repeated")),
    ("synth-repeated-velocity", ["synth", "--out", "new", "--velocities", "10mm/s,0.01m/s"], {},
     ("--velocities", "repeated")),
    ("simulate-hold-1e300s", _sim("--hold", "1e300s"), {}, ("--hold",)),
    ("fit-drag-tiny-speeds", ["fit-drag", "s.csv"], {"s.csv": "velocity_m_s,force_N\n1e-160,1\n2e-160,2\n"},
     ("fit-drag",)),
    ("fit-drag-huge-force", ["fit-drag", "s.csv"], {"s.csv": "velocity_m_s,force_N\n0.1,1e300\n0.2,2\n"},
     ("force_N", "magnitude")),
    ("fit-drag-huge-density", ["fit-drag", "s.csv", "--rho-m", "1e300kg/m3"], {"s.csv": SLIDING}, ("--rho-m",)),
    ("fit-drag-huge-area", ["fit-drag", "s.csv", "--area", "200m2"], {"s.csv": SLIDING}, ("--area",)),
    # an empty value is refused, not taken as "not given" (the paper's foot, silently)
    ("fit-drag-empty-area", ["fit-drag", "s.csv", "--area", ""], {"s.csv": SLIDING}, ("--area", "''")),
    ("fit-drag-empty-foot", ["fit-drag", "s.csv", "--foot", ""], {"s.csv": SLIDING}, ("--foot", "''")),
    # item 4: finite input, non-finite output is refused at the source
    ("trajectory-depth-1e307", _traj(""), {"traj.csv": "time_s,depth_m\n0,0\n0.01,-1e307\n0.02,0\n"},
     ("traj.csv", "row 3", "depth_m")),
    # the step's refusal named neither the file nor the sample ("the time step before sample 2 is 1999.99 s")
    ("trajectory-step-1e-12", _traj(""), {"traj.csv": "time_s,depth_m\n0,0\n1e-12,0.001\n0.02,0\n"},
     ("traj.csv: the sample at time 1e-12 s (sample 2)", "time steps", "1e-09")),
    ("trajectory-step-2000s", _traj(""), {"traj.csv": "time_s,depth_m\n0,0\n0.01,0.001\n2000,0.002\n"},
     ("traj.csv: the sample at time 2000.0 s (sample 3) comes 1999.99 s after the last", "[1e-09, 1000] s")),
    ("fit-bias-1e300", ["fit", "big", "--out", "f.json"], {"big/dataset.json": "@manifest-big", "big/a.csv": "@big"},
     ("a.csv", "force_N", "magnitude")),
    # item 6: inputs mean one thing
    ("csv-duplicate-column", _traj(""), {"traj.csv": "time_s,depth_m,depth_m\n0,0,0\n0.01,0.001,0\n"},
     ("traj.csv", "depth_m", "more than once")),
    ("csv-two-spellings", _traj(""), {"traj.csv": "time_s,depth_m,depth_mm\n0,0,0\n0.01,0.001,1\n"},
     ("traj.csv", "depth_m", "depth_mm")),
    ("csv-underscore-number", _traj(""), {"traj.csv": "time_s,depth_m\n0,0\n0.01,1_0\n"},
     ("traj.csv", "row 3", "not a number")),
    ("csv-arabic-digits", _traj(""), {"traj.csv": "time_s,depth_m\n0,0\n0.01,\u0661\n"},
     ("traj.csv", "row 3", "not a number")),
    ("unit-arabic-digits", _sim("--depth", "\u0662\u0660mm"), {}, ("--depth",)),
    ("unit-underscore", _sim("--depth", "2_0mm"), {}, ("--depth",)),
    # a space inside a unit is no part of it: "20m m" ran as 20 mm; a literal that underflows is not zero
    ("unit-space-inside", _sim("--depth", "20m m"), {}, ("--depth", "unknown length unit 'm m'")),
    ("unit-underflow-to-zero", _sim("--rise", "1e-400mm"), {}, ("--rise", "too small")),
    # forces were compared case-free: mega- read as milli-newtons (0.5 MN, 5e5 N, beyond the bound, ran as 0.5 mN)
    ("unit-meganewton", ["synth", "--out", "new", "--bias", "0.5MN"], {}, ("--bias", "unknown force unit 'MN'")),
    # areas were compared case-free: "20MM2" ran as 20 mm^2, where "20MM" is refused as a length
    ("unit-area-capitals", ["fit-drag", "s.csv", "--area", "20MM2"], {"s.csv": SLIDING},
     ("--area", "unknown area unit 'MM2'", "m2, cm2, mm2")),
    ("unit-area-capitals-foot", _sim("--foot", "area:19.38CM2,width:38mm"), {}, ("--foot", "unknown area unit 'CM2'")),
    # "as a area", "expected a area": the article follows the kind
    ("unit-area-unreadable", ["fit-drag", "s.csv", "--area", "big"], {"s.csv": SLIDING},
     ("--area", "cannot read 'big' as an area;")),
    ("unit-area-no-unit", ["fit-drag", "s.csv", "--area", "5"], {"s.csv": SLIDING},
     ("--area", "expected an area with a unit")),
    # an empty name (an unset shell variable) was read as the folder '.': ".: is a directory; expected a CSV file"
    ("empty-trajectory", _sim("--trajectory", ""), {}, ("--trajectory: empty name ''; expected a CSV file",)),
    # a pipe was read for its header (depths or poses?), then again from its start: '<(cat t.csv)' was reported as
    # "/dev/fd/63: file is empty", and a named pipe without a writer made the command wait for ever
    ("trajectory-pipe", _sim("--trajectory", "fifo.csv"), {"fifo.csv": "@fifo"},
     ("--trajectory: 'fifo.csv' is a pipe, which can be read only once", "expected a CSV file")),
    ("empty-params", ["simulate", "--params", " ", "--out", "out.csv"], {},
     ("--params: empty name ' '; expected a parameter file (JSON)",)),
    ("empty-trial", ["identify", ""], {}, ("TRIAL.csv: empty name ''",)),
    ("empty-sliding", ["fit-drag", ""], {}, ("FILE.csv: empty name ''",)),
    ("empty-dataset", ["fit", "", "--out", "f.json"], {}, ("DATASET: empty name ''", "a dataset folder")),
    ("empty-recording", ["track", "", "--out", "out.csv"], {}, ("FILE.csv: empty name ''",)),
    ("manifest-dotdot", ["fit", "ds2", "--out", "f.json"],
     {"ds2/dataset.json": _manifest([{"file": "../secret.csv", "water_content": 0.25}]),
      "secret.csv": "root:x:0:0:secret\n"}, ("relative to the dataset folder",)),
    ("manifest-absolute", ["fit", "ds2", "--out", "f.json"],
     {"ds2/dataset.json": "@manifest-absolute", "secret.csv": "root:x:0:0:secret\n"},
     ("relative to the dataset folder",)),
    ("manifest-link-out", ["fit", "ds2", "--out", "f.json"],
     {"ds2/dataset.json": _manifest([{"file": "link.csv", "water_content": 0.25}]),
      "secret.csv": "root:x:0:0:secret\n", "ds2/link.csv": "@link:../secret.csv"}, ("outside the dataset folder",)),
    ("identify-zero-force", ["identify", "t.csv"], {"t.csv": "@zero-force"}, ("force",)),
    ("velocity-too-small", ["simulate", "--water-content", "25%", "--velocity", "1e-12m/s", "--out", "out.csv"], {},
     ("--velocity",)),
    # an option given twice with different values: argparse kept the last without a word (drop ran a 6 kg foot,
    # params printed W = 30%, fit-drag fitted with 20 cm2, an abbreviation too); now refused, naming both
    ("repeated-mass", ["drop", "--mass", "5kg", "--ma", "6kg", "--water-content", "25%", "--out", "out.csv"], {},
     ("mudforce drop: error: argument --mass: given twice ('5kg', then '6kg'); give it once",)),
    ("repeated-water-content", ["params", "--water-content", "25%", "--water-content=30%"], {},
     ("argument --water-content: given twice ('25%', then '30%')",)),
    ("repeated-area", ["fit-drag", "s.csv", "--area", "19cm2", "--area", "20cm2"], {"s.csv": SLIDING},
     ("argument --area: given twice",)),
    ("repeated-params", ["simulate", "--params", "p.json", "--params", "q.json", "--out", "out.csv"],
     {"p.json": GOOD_PARAMS, "q.json": GOOD_PARAMS}, ("argument --params: given twice ('p.json', then 'q.json')",)),
]


def _materialise(root: Path, files: dict[str, str], trial: str) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if text == "@fifo":
            os.mkfifo(path)
            continue
        if text.startswith("@link:"):
            path.symlink_to(text[len("@link:"):])
            continue
        if text == "@trial":
            text = trial
        elif text == "@zero-force":
            lines = trial.splitlines()
            text = "\n".join([lines[0], *(",".join([*line.split(",")[:2], "0"]) for line in lines[1:])]) + "\n"
        elif text == "@big":
            lines = trial.splitlines()
            text = "\n".join([lines[0], *(",".join([*line.split(",")[:2], "1e300"]) for line in lines[1:])]) + "\n"
        elif text == "@manifest-big":
            text = _manifest([{"file": "a.csv", "water_content": 0.25}])
        elif text == "@manifest-absolute":
            text = _manifest([{"file": str(root / "secret.csv"), "water_content": 0.25}])
        path.write_text(text, encoding="utf-8")


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Run, Path, dict[str, bytes | str]]]:
    source = tmp_path_factory.mktemp("source")
    synthesize(source / "ds", velocities=(0.02,), repeats=1, seed=2)
    trial = (source / "ds" / "w25_v20_r1.csv").read_text()
    cases = []
    for case_id, argv, files, _ in REFUSED:
        root = tmp_path_factory.mktemp(case_id)
        if argv[1:2] == ["ds"]:
            synthesize(root / "ds", velocities=(0.02,), repeats=1, seed=2)
        (root / "out.csv").write_text("previous output\n")
        _materialise(root, files, trial)
        cases.append((argv, root))
    befores = [snapshot(root) for _, root in cases]
    results = run_batch(cases)
    return {c[0]: (r, root, b) for c, r, (_, root), b in zip(REFUSED, results, cases, befores, strict=True)}


@pytest.mark.parametrize(("case_id", "words"), [(c[0], c[3]) for c in REFUSED], ids=[c[0] for c in REFUSED])
def test_refused_in_one_line(runs: dict[str, tuple[Run, Path, dict[str, bytes | str]]], case_id: str,
                             words: tuple[str, ...]) -> None:
    """Exit 2, one line naming the problem, no traceback, no other file's content echoed, nothing changed."""
    run, root, before = runs[case_id]
    assert_refused(run, *words)
    assert len(run.stderr) < 400  # a value is shown short, not digit by digit
    assert "root:x" not in run.stderr  # an error never echoes another file's content
    assert snapshot(root) == before


def test_the_simulate_command_refuses_a_depth_beyond_100_m(tmp_path: Path) -> None:
    base = ["simulate", "--water-content", "25%", "--out", "out.csv"]
    deep, fast = run_batch([([*base, "--depth", "101m", "--velocity", "10m/s"], tmp_path),
                            ([*base, "--rate", "1e9Hz"], tmp_path)])
    assert deep.returncode == 2 and deep.stderr.count("\n") == 1 and "within +-100 m" in deep.stderr, deep.stderr
    assert fast.returncode == 2 and "--rate" in fast.stderr and "samples" in fast.stderr, fast.stderr
    assert not (tmp_path / "out.csv").exists()


def test_accepted_meanings(tmp_path: Path) -> None:
    """A BOM is accepted; fit-drag warns about a negative lambda; identify says when the manifest's foot
    differs from the one assumed, and does not call 8e-5 N "well above" a noise of 0 N; fit.json is valid
    JSON with finite numbers only."""
    (tmp_path / "bom.csv").write_bytes(b"\xef\xbb\xbf" + TRAJ.encode())
    (tmp_path / "neg.csv").write_text("velocity_m_s,force_N\n0.1,-0.5\n0.2,-1.9\n0.3,-4.3\n")
    synthesize(tmp_path / "disc", velocities=(0.02,), repeats=1, seed=3, foot=Foot.disc(0.08))
    synthesize(tmp_path / "clean", velocities=(0.02,), repeats=1, seed=3, force_noise=0.0, depth_noise=0.0, bias=0.0)
    results = run_batch([
        (["simulate", "--water-content", "25%", "--trajectory", "bom.csv", "--out", "o.csv", "--quiet"], tmp_path),
        (["fit-drag", "neg.csv"], tmp_path),
        (["identify", "disc/w25_v20_r1.csv", "--json"], tmp_path),
        (["identify", "clean/w25_v20_r1.csv", "--foot", "paper", "--json"], tmp_path),
        (["params", "--water-content", "25%", "--water-content", "25%", "--json", "--json"], tmp_path),  # one meaning
    ])
    for r in results:
        assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert "lambda" in results[1].stderr and "negative" in results[1].stderr
    disc = json.loads(results[2].stdout)
    assert any("manifest names the foot disc 80 mm" in w for w in disc["warnings"])
    clean = json.loads(results[3].stdout)
    assert abs(clean["water_content"] - 0.25) < 1e-3
    assert not any("well above" in w for w in clean["warnings"]), clean["warnings"]
    assert json.loads(results[4].stdout)["beta"] == 0.54


def test_fit_json_is_strict_json() -> None:
    """The JSON writer refuses non-finite numbers, so fit.json never holds an Infinity token."""
    from mudforce.errors import InputError
    from mudforce.io import dumps_json

    with pytest.raises(InputError, match="not finite"):
        dumps_json({"rmse_N": math.inf})


def test_minus_zero_is_zero(tmp_path: Path) -> None:
    """'-0N' was read as a negative zero, which reached the outputs: a synth dataset's "bias_N": -0.0 (other bytes
    than with 0N), identify's "force_gain_uncertainty": -0.0; a signed zero is now zero."""
    base = ["synth", "--velocities", "20mm/s", "--repeats", "1", "--quiet"]
    results = run_batch([([*base, "--out", "minus", "--bias", "-0N"], tmp_path),
                         ([*base, "--out", "plus", "--bias", "0N"], tmp_path),
                         (["identify", "plus/w25_v20_r1.csv", "--json", "--force-gain-uncertainty", "-0%"], tmp_path)])
    for r in results:
        assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert snapshot(tmp_path / "minus") == snapshot(tmp_path / "plus")
    assert '"force_gain_uncertainty": 0.0,' in results[2].stdout


def test_greek_mu_is_the_micro_sign(tmp_path: Path) -> None:
    """'μm' (U+03BC, the Greek letter) was refused while 'µm' (U+00B5, the micro sign) was read, in a message listing
    'µm', which looks the same; both now mean micrometres."""
    base = ["simulate", "--water-content", "25%", "--quiet"]
    results = run_batch([([*base, "--depth", "20000\u03bcm", "--velocity", "10000\u03bcm/s", "--out", "greek.csv"],
                          tmp_path),
                         ([*base, "--depth", "20000\u00b5m", "--velocity", "10000\u00b5m/s", "--out", "micro.csv"],
                          tmp_path)])
    for r in results:
        assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert (tmp_path / "greek.csv").read_bytes() == (tmp_path / "micro.csv").read_bytes()
