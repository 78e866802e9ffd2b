"""``mudforce reproduce``: the report's files, its documented keys, determinism, and option checks."""

from __future__ import annotations

import json
import re
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

from mudforce.errors import InputError
from mudforce.reproduce import ReproduceConfig
from mudforce_cli_harness import assert_refused, run_batch, run_cli

SEED = "7"


def _run(*args: str, path_first: tuple[Path, ...] = ()) -> subprocess.CompletedProcess[str]:
    return run_cli(["reproduce", *args], env={"PYTHONHASHSEED": "0"}, timeout=240, path_first=path_first)


#: ``--quick`` of two water contents instead of five (the driest, whose slow withdrawal never necks, and the
#: reference one of Figs. 2, 6 and 11): every stage, table and figure of the report, for 40 % of its fits. Put
#: before the package on the path by a ``sitecustomize``; that ``--quick`` itself has all five is checked by
#: test_quick_has_every_water_content.
HOOK = """
import dataclasses
from mudforce.reproduce import experiments
_quick = experiments.ReproduceConfig.quick_config.__func__
def _smaller(cls, seed=0):
    return dataclasses.replace(_quick(cls, seed), water_contents=(0.15, 0.25))
experiments.ReproduceConfig.quick_config = classmethod(_smaller)
"""
WATER = [0.15, 0.25]


@pytest.fixture(scope="module")
def reports(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One quick report, in the command's own process (``--jobs 1``: two workers would each start the whole
    stack again, ~2-4 s more CPU). That the number of jobs changes nothing is checked below, at the level of
    the fits and the figures, for a fraction of a second report's cost; ``--jobs 2`` from the command line
    starts its workers in tests/reproduce/test_reproduce_interrupt.py."""
    hook = tmp_path_factory.mktemp("hook")
    (hook / "sitecustomize.py").write_text(HOOK)
    out = tmp_path_factory.mktemp("reproduce") / "a"
    proc = _run("--quick", "--seed", SEED, "--out", str(out), "--jobs", "1", path_first=(hook,))
    assert proc.returncode == 0, proc.stderr
    assert "wrote" in proc.stdout
    return out


def test_quick_has_every_water_content() -> None:
    config = ReproduceConfig.quick_config()
    assert config.water_contents == (0.15, 0.2, 0.25, 0.3, 0.35) and config.quick


def test_report_files_and_keys(reports: Path) -> None:
    out = reports
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert len(pngs) == 10 and "tracking.png" in pngs  # nine of the paper's, and tracking across a change of mud
    summary = json.loads((out / "summary.json").read_text())
    assert summary["config"]["seed"] == int(SEED) and summary["config"]["quick"] is True
    rows = summary["table_i"]
    assert [r["water_content"] for r in rows] == WATER
    for row in rows:
        assert set(row["fitted"]) >= {"k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "beta", "sigma_y", "zeta",
                                      "omega_0"}
        assert row["paper"]["alpha"] > 0 and row["rmse_N"] > 0
    crit = summary["critical_withdrawal_velocity"]
    assert crit[0]["paper_m_s"] == pytest.approx(17e3 / 1.35e6, rel=1e-5)
    base = summary["baselines"]
    assert set(base) == {"mud_model", "granular_rft", "drft", "maxwell_only"}
    for entry in base.values():
        assert entry["rmse_N"] > 0
    for name in ("granular_rft", "drft", "maxwell_only"):
        assert base["mud_model"]["rmse_N"] < base[name]["rmse_N"]


def test_report_html_captions_every_figure(reports: Path) -> None:
    out = reports
    text = (out / "report.html").read_text()
    images = re.findall(r'<img src="([^"]+)"', text)
    assert len(images) >= 8
    for src in images:
        assert (out / src).is_file()
    captions = re.findall(r"<figcaption><b>([^<]+)</b>", text)
    assert len(captions) == len(images)
    assert all("Paper" in c for c in captions)
    for fig in ("Fig. 2", "Fig. 6", "Fig. 7", "Fig. 8", "Fig. 9", "Fig. 10", "Fig. 11"):
        assert any(fig in c for c in captions), fig


def test_the_number_of_jobs_changes_no_fit_and_no_figure_byte(tmp_path: Path) -> None:
    """The fits and the figures of the report are the same in two worker processes as in one, byte for byte
    (the summary and the HTML are pure functions of them)."""
    from mudforce._plumbing.progress import Progress
    from mudforce.estimation.calibration.fit import FitOptions
    from mudforce.reproduce.experiments import make_experiments
    from mudforce.reproduce.figures import figure_specs, write_figures
    from mudforce.reproduce.jobs import executor, run_fits, sort_fits

    small = FitOptions(starts=1, popsize=5, maxiter=8, max_nfev=60)
    # 0.35 - 0.1 is 0.24999999999999997, the reference W = 25 % to float rounding, as ReproduceConfig takes it:
    # Fig. 2 looked up table[0.25], a KeyError after every fit of the run
    config = ReproduceConfig(water_contents=(0.35 - 0.1,), velocities=(0.01, 0.03), repeats=1, rate=50.0,
                             fit_options=small, velocity_fit_options=small, seed=int(SEED), quick=True)
    dataset, _ = make_experiments(config)
    quiet = Progress(10**6, "test", quiet=True)

    def report(pool: object, folder: Path) -> tuple[dict[object, object], dict[str, bytes]]:
        fits = run_fits(config, dataset, pool, quiet)
        specs = figure_specs(config, dataset, *sort_fits(fits))
        keep = [spec for spec in specs if spec[0].startswith(("fig02", "fig07"))]  # two figures drawn in turn
        assert len(keep) == 2, [spec[0] for spec in specs]
        folder.mkdir()
        write_figures(folder, keep, pool, quiet)
        return ({job: fit.to_dict() for job, fit in fits.items()},
                {p.name: p.read_bytes() for p in sorted(folder.iterdir())})

    pool = executor(2)
    try:
        in_two = report(pool, tmp_path / "two")
    finally:
        pool.shutdown()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # one repeat: Fig. 2 draws no scatter band (it was numpy's NaN, warned of)
        in_one = report(None, tmp_path / "one")
    assert in_one == in_two


def test_bad_seeds_and_unwritable_outs_are_one_line_exit_2(tmp_path: Path) -> None:
    """Each refused in one line, exit 2, before anything is written (one subprocess for all of them)."""
    blocker = tmp_path / "file"
    blocker.write_text("not a directory\n")
    seeds = ["-1", "abc", "1.5", str(2**40), "1_0"]  # "1_0": int() took it as 10
    runs = run_batch([(["reproduce", "--quick", "--seed", seed, "--out", str(tmp_path / "r")], tmp_path)
                      for seed in seeds]
                     + [(["reproduce", "--quick", "--out", str(out)], tmp_path) for out in (blocker, blocker / "sub")])
    for run in runs[:len(seeds)]:
        assert_refused(run, "--seed")
    for run in runs[len(seeds):]:
        assert_refused(run, "--out")
    assert not (tmp_path / "r").exists()
    assert blocker.read_text() == "not a directory\n"


def test_config_refuses_bad_values() -> None:
    with pytest.raises(InputError):
        ReproduceConfig(seed=-3)
    with pytest.raises(InputError):
        ReproduceConfig(water_contents=(0.15, 0.35))
    assert ReproduceConfig(velocities=np.array([0.01, 0.03])).velocities.size == 2  # not numpy's ValueError
    # the bound on all trials' samples lies far above the full report's 56,385 (and the quick one's 10,360)
    ReproduceConfig(repeats=88)  # 1,653,960 samples
    ReproduceConfig(rate=1000.0, repeats=8)  # 1,501,840


@pytest.mark.parametrize(("fields", "message"), [
    # were a TypeError (a scalar, a string), a ValueError (an array's truth value), taken (True as one repeat, a
    # scatter of -1 as none, a speed twice: made once, fitted twice), run for ever (10**400 repeats) or an
    # AttributeError in make_experiments (fit_options=None)
    ({"velocities": 0.01}, r"velocities must be a sequence of numbers \[m/s\], got shape \(\)"),
    ({"water_contents": "0.25"}, r"water_contents must be an array of real numbers \[-\], got string"),
    ({"velocities": (0.01, 0.01)}, r"velocities repeats a value"),
    ({"repeats": True}, r"repeats must be an integer >= 1, got True"),
    ({"repeats": 10**5000}, r"repeats must be at most 1000 .*, got an integer of 16610 bits"),
    ({"repeat_scatter": -1.0}, r"repeat_scatter must be within \[0, 1\] -, got -1.0"),
    ({"fit_options": None}, r"fit_options must be a FitOptions, got NoneType"),
    # two values alike to 6 digits were made and fitted as two, under one trial name (w20_v10_r1.csv four times),
    # and summary.json kept one of their RMSEs under one key ("0.2") and one necking verdict ("0.01")
    ({"water_contents": (0.2, 0.200000000001, 0.25)},
     r"water_contents 0.2 and 0.200000000001 are the same to 6 significant digits \(both 0.2 in summary.json"),
    ({"velocities": (0.01, 0.0100000001)}, r"velocities 0.01 and 0.0100000001 are the same to 6 significant digits"),
    # refused by make_experiments, after reproduce() had made the output folder's parents, and not naming the field
    ({"rate": -1.0}, r"rate: sampling rate must be finite and > 0 \[Hz\], got -1.0$"),
    ({"velocities": (0.01, -0.01)}, r"velocities: intrusion velocity must be finite and > 0 \[m/s\], got -0.01$"),
    ({"water_contents": (0.25, 0.9)}, r"water content 0.9 is outside Table I's range \[0.15, 0.35\]"),
    ({"force_noise": float("nan")}, r"force_noise must be finite \[N\], got nan$"),
    ({"depth_noise": -1e-5}, r"depth_noise must be >= 0 \[m\], got -1e-05$"),
    ({"bias": "0.5"}, r"bias must be a number \[N\], got str '0.5'$"),
    # each trial was bounded, not their sum: 54.75 billion samples were accepted, to run for weeks
    ({"rate": 1e5, "velocities": (0.001, 0.002), "repeats": 1000},
     r"the report would simulate 54,750,010,000 samples \(5 water contents x 2 speeds x 1000 repeats at 100000 Hz\), "
     r"more than 5,000,000; lower the rate, the repeats or the number of speeds, or raise the slowest speeds$"),
])
def test_config_refuses_bad_fields_in_one_line(fields: dict[str, object], message: str) -> None:
    with pytest.raises(InputError, match=f"^{message}") as info:
        ReproduceConfig(**fields)  # type: ignore[arg-type]
    assert "\n" not in str(info.value)


def test_synthesize_refuses_a_noise_that_is_no_number_in_one_line() -> None:
    from mudforce.estimation.calibration import synthesize

    # np.isfinite raised TypeError on these; a bool was taken as 1
    for noise in ("0.2", 10**5000, True):
        with pytest.raises(InputError, match=r"^force noise must be a (real )?number"):
            synthesize(force_noise=noise)  # type: ignore[arg-type]
    # a count of repeats past MAX_REPEATS ran for ever (10**400), as ReproduceConfig's did
    from mudforce.estimation.calibration.synth import synthesize_gait

    for make in (synthesize, synthesize_gait):
        with pytest.raises(InputError, match=r"^repeats must be at most 1000 .*, got 1e\+20$"):
            make(repeats=10**20)


def test_reproduce_refuses_bad_jobs_config_and_log_before_any_work(tmp_path: Path) -> None:
    """Each in one line, before matplotlib is warmed up and before the folder is made: jobs=10**6 was taken (a fork
    pool starts all its workers at its first job: a million processes), a config of another kind and a log that
    is not callable were an AttributeError ('str' object has no attribute 'seed') and a TypeError after the
    experiments were made."""
    from mudforce.reproduce import reproduce

    out = tmp_path / "r"
    for kwargs, message in (({"jobs": 10**6}, r"jobs must be at most 64 \(worker processes\), got 1000000$"),
                            ({"jobs": 65}, r"jobs must be at most 64"), ({"jobs": True}, r"jobs must be an integer"),
                            ({"config": "quick"}, r"config must be a ReproduceConfig or None, got str$"),
                            ({"log": 5}, r"log must be a callable \(e.g. print\) or None, got int$")):
        with pytest.raises(InputError, match=f"^{message}"):
            reproduce(out, quiet=True, **kwargs)  # type: ignore[arg-type]
    assert not out.exists()
    # an out that is no path: a bare TypeError from pathlib (io.check_replaceable_dir)
    with pytest.raises(InputError, match=r"^--out: a folder is a path \(str or os.PathLike\), got int$"):
        reproduce(5, quiet=True)  # type: ignore[arg-type]
