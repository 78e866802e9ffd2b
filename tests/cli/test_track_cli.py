"""``mudforce track`` through a subprocess: the columns, the plot, bad input (exit 2, one line, nothing clobbered)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from mudforce.estimation.tracker import track
from mudforce.motions.gait import walk
from mudforce_cli_harness import assert_refused, run_batch, run_cli, snapshot

EXPECTED = ["time_s", "water_content", "water_content_low", "water_content_high", "force_predicted_N", "force_N",
            "changed", "misfit", "depth_offset_m", "depth_offset_stderr_m", "force_lag_s", "force_lag_stderr_s",
            "force_bias_N"]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 20 s walk, 20 % then 30 % water, written with depth in mm."""
    folder = tmp_path_factory.mktemp("track")
    wk = walk([0.20, 0.30], change_times=[8.0], seed=2, duration=20.0, force_noise=0.3, bias=0.7)
    path = folder / "walk.csv"
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["time_s", "depth_mm", "force_N"])
        for row in zip(wk.time.tolist(), (wk.depth * 1e3).tolist(), wk.force.tolist(), strict=True):
            writer.writerow([repr(v) for v in row])
    return path


def test_track_writes_the_estimates_and_a_plot(recording: Path) -> None:
    folder = recording.parent
    proc = run_cli(["track", recording.name, "--out", "track.csv", "--plot", "track.png"], folder)
    assert proc.returncode == 0, proc.stderr
    assert "final water content: 30 %" in proc.stdout
    with (folder / "track.csv").open(newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == EXPECTED
    data = np.array(rows[1:], dtype=float)
    wk = walk([0.20, 0.30], change_times=[8.0], seed=2, duration=20.0, force_noise=0.3, bias=0.7)
    assert data.shape == (wk.time.size, len(EXPECTED))
    np.testing.assert_allclose(data[:, 5], wk.force, rtol=1e-12)
    assert abs(data[-1, 1] - 0.30) <= 0.01 and data[-1, 2] <= 0.30 <= data[-1, 3]
    assert data[:, 6].sum() == 1  # one change flagged
    # the same estimates and intervals as the Python API with its defaults (the online tracker's own branch rule)
    given = np.loadtxt(recording, delimiter=",", skiprows=1)
    r = track(given[:, 0], given[:, 1] * 1e-3, given[:, 2])
    np.testing.assert_allclose(data[:, 1:4], np.column_stack([r.water_content, r.low, r.high]), rtol=0, atol=1e-12)
    # and the sensor nuisances, sample by sample, with the summary's line at the end
    assert r.depth_offset is not None and r.depth_offset_stderr is not None and r.force_lag is not None
    assert r.force_lag_stderr is not None
    np.testing.assert_array_equal(data[:, 8:], np.column_stack([r.depth_offset, r.depth_offset_stderr, r.force_lag,
                                                                r.force_lag_stderr, r.bias]))
    assert (f"surface offset {1e3 * r.depth_offset[-1]:+.2f} +- {1e3 * r.depth_offset_stderr[-1]:.2f} mm (the model "
            f"follows the depth plus it), force lag {1e3 * r.force_lag[-1]:.1f} +- {1e3 * r.force_lag_stderr[-1]:.1f} "
            "ms (the mean delay of one or two low-pass stages)") in proc.stdout
    assert "branch rule: the tracker's own, online" in proc.stdout
    assert (folder / "track.png").read_bytes().startswith(b"\x89PNG")
    # the misfit flag over the whole recording, which the final estimate alone hid (a force of noise alone read
    # 34.1 % [27.5, 35.2] with the flag cleared by the end, without a word)
    misfit = data[:, EXPECTED.index("misfit")].astype(bool)
    assert ("model misses the data (misfit): never flagged" in proc.stdout) == (not misfit.any()), proc.stdout


def test_the_summary_says_where_the_misfit_was_flagged_and_when_the_interval_reaches_the_family_s_end() -> None:
    """The summary's two lines read TrackResult's model_misses_data and family_edge, which a Python user of track()
    had no way to see (the flag and the edge were worked out in the CLI alone: a force of noise alone tracked to
    34.0 % [27.1, 35.2] with its misfit flag raised on 70 % of the samples, and the result said neither)."""
    from mudforce.cli.track import _edge_line, _misfit_line
    from mudforce.estimation.tracker import TrackResult

    t = np.arange(5) * 0.5

    def result(misfit: list[int], low: float = 0.23, high: float = 0.27, **kw: tuple[float, float]) -> TrackResult:
        x = np.zeros(5)
        return TrackResult(t, x, x, x, np.full(5, low), np.full(5, high), x, np.zeros(5, dtype=bool), x, x,
                           np.array(misfit, dtype=bool), **kw)  # type: ignore[arg-type]

    r = result([0, 1, 1, 0, 0])
    assert r.model_misses_data and r.family_edge == ""
    assert _misfit_line(r) == (
        "model misses the data (misfit): flagged on 40 % of the samples, last at 1 s: the mud may not be in the "
        "model's family, or the recording not what it seems")
    assert _misfit_line(result([1] * 5)).endswith("last at 2 s (flagged at the end): the mud may not be "
                                                  "in the model's family, or the recording not what it seems")
    quiet = result([0] * 5)
    assert not quiet.model_misses_data and _misfit_line(quiet) == "model misses the data (misfit): never flagged"
    wet, dry = result([0] * 5, 0.28, 0.352), result([0] * 5, 0.148, 0.2)
    assert (wet.family_edge, dry.family_edge, quiet.family_edge) == ("wet", "dry", "")
    assert _edge_line(wet) == "the interval reaches the family's wet end (35 %): the mud may be wetter"
    assert _edge_line(dry) == "the interval reaches the family's dry end (15 %): the mud may be drier"
    assert _edge_line(quiet) == ""
    # an interval over the whole family (a recording that told little) reaches both ends: the summary said wet alone
    both = result([0] * 5, 0.148, 0.352)
    assert both.family_edge == "both" and _edge_line(both) == _edge_line(wet) + "\n" + _edge_line(dry)
    # a family check that found the mud off the family while the tracker's own flag stayed down: the misfit line
    # reads the tracker's own flag (it read the first flagged sample of none: IndexError), the family line the check's
    from mudforce.cli.track import _family_line
    from mudforce.estimation.family_check import FamilyVerdict

    checked = result([0] * 5, family_misfit=np.array([0, 0, 1, 1, 1], dtype=bool),  # type: ignore[arg-type]
                     family_checks=((2, FamilyVerdict(1.0, 0.0, 3, True)),))  # type: ignore[arg-type]
    assert checked.model_misses_data and _misfit_line(checked) == "model misses the data (misfit): never flagged"
    assert _family_line(checked, 1.0, 0.5).startswith(
        "family check (identify's misfit flag on the last 1 s, every 0.5 s): 1 check, 0 told nothing, 1 found the "
        "mud off the family (first at 1 s, and at the end)")
    # the ends of the grid the tracker ran on (track() records them), not the default grid's
    narrow = result([0] * 5, 0.22, 0.3, water_content_range=(0.2, 0.3))
    assert narrow.family_edge == "wet"
    assert _edge_line(narrow).startswith("the interval reaches the family's wet end (30 %)")


def test_the_family_check_adds_a_column_and_a_line_and_finds_a_granular_law_off_the_family(tmp_path: Path) -> None:
    """``--family-check 10s``: identify's misfit flag on the last 10 s every 2.5 s (FamilyCheck), a column
    family_misfit (1 from the first check that found the mud off the family) and a summary line; the other columns
    the same as without it."""
    wk = walk(0.24, seed=6, duration=15.0, force_noise=0.2, bias=0.3)
    kz = float(np.max(wk.force)) / float(np.max(wk.depth)) * np.maximum(wk.depth, 0.0) + 0.3
    for name, force in (("walk.csv", wk.force), ("kz.csv", kz)):
        with (tmp_path / name).open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["time_s", "depth_m", "force_N"])
            for row in zip(wk.time.tolist(), wk.depth.tolist(), force.tolist(), strict=True):
                writer.writerow([repr(v) for v in row])
    runs = run_batch([(["track", "walk.csv", "--out", "w.csv", "--family-check", "10s"], tmp_path),
                      (["track", "kz.csv", "--out", "k.csv", "--family-check", "10s"], tmp_path),
                      (["track", "kz.csv", "--out", "plain.csv"], tmp_path)])
    for run in runs:
        assert run.returncode == 0, run.stderr
    assert ("family check (identify's misfit flag on the last 10 s, every 2.5 s): 3 checks, 0 told nothing, none "
            "found the mud off the family") in runs[0].stdout
    assert ("family check (identify's misfit flag on the last 10 s, every 2.5 s): 3 checks, 0 told nothing, 3 "
            "found the mud off the family (first at 10 s, and at the end): the mud may not be in the model's "
            "family") in runs[1].stdout
    assert "family check" not in runs[2].stdout
    rows = {name: list(csv.reader((tmp_path / name).open(newline=""))) for name in ("w.csv", "k.csv", "plain.csv")}
    assert rows["k.csv"][0] == [*EXPECTED, "family_misfit"] and rows["plain.csv"][0] == EXPECTED
    flags = np.array([r[-1] for r in rows["k.csv"][1:]], dtype=int)
    assert flags[:1000].sum() == 0 and flags[1000:].all()  # from the first check (10 s, sample 1000) on
    assert not np.array([r[-1] for r in rows["w.csv"][1:]], dtype=int).any()
    assert [r[:-1] for r in rows["k.csv"]] == rows["plain.csv"]


BAD_INPUTS = [
    (None, ["missing.csv", "--out", "o.csv"], "file not found"),
    ("time_s,depth_m\n0,0\n0.01,0\n", ["in.csv", "--out", "o.csv"], "missing column force_N"),
    ("time_s,depth_m,force_N\n0,0,0\n0,0,0\n", ["in.csv", "--out", "o.csv"], "time repeats"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,x,0\n", ["in.csv", "--out", "o.csv"], "is not a number"),
    ("time_s,depth_m,force_N\n0,0,0\n", ["in.csv", "--out", "o.csv"], "at least 2 samples"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n", ["in.csv", "--out", "in.csv"], "is the input file"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n", ["in.csv", "--out", "o.csv", "--plot", "o.jpg"], ".png"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n", ["in.csv", "--out", "o.csv", "--foot", "blob"], "--foot"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n", ["in.csv", "--out", "o.csv", "--family-check", "10"],
     "--family-check"),
    ("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n", ["in.csv", "--out", "o.csv", "--family-check", "10s",
                                                    "--family-every", "0s"], "--family-every"),
]


def test_bad_input_exits_2_with_one_line_and_clobbers_nothing(tmp_path: Path) -> None:
    """Each case in its own folder, all of them through one subprocess (run_batch)."""
    folders, befores = [], []
    for i, (make, _, _) in enumerate(BAD_INPUTS):
        folder = tmp_path / str(i)
        folder.mkdir()
        if make is not None:
            (folder / "in.csv").write_text(make)
        (folder / "o.csv").write_bytes(b"previous output\n")
        folders.append(folder)
        befores.append(snapshot(folder))
    runs = run_batch([(["track", *args], folder) for (_, args, _), folder in zip(BAD_INPUTS, folders, strict=True)])
    for run, (_, _, message), folder, before in zip(runs, BAD_INPUTS, folders, befores, strict=True):
        assert_refused(run, message)
        assert snapshot(folder) == before


def test_an_out_that_cannot_be_written_whole_is_left_as_it_was(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                               capsys: pytest.CaptureFixture[str]) -> None:
    """--out alone was written in place (Path.write_text): a write that failed (a full disk, a file size limit: 20 kB
    of a 30 kB CSV) left the old file replaced by the part written. Now through atomic_open, as every output: a
    failure leaves it as it was, and no temporary file. A full disk is the system's failure, not bad input: exit 1
    (it was 2, as a refused path), one line naming the file. (In process, the tracker replaced by a canned result:
    the write is what is tested.)"""
    import os

    from mudforce.cli import main
    from mudforce.estimation import tracker

    n = 3
    x = np.linspace(0.0, 0.02, n)
    canned = tracker.TrackResult(x, x, x, x, x, x, x, np.zeros(n, dtype=bool), x, x)
    monkeypatch.setattr(tracker, "track", lambda *args, **kwargs: canned)
    (tmp_path / "in.csv").write_text("time_s,depth_m,force_N\n0,0,0\n0.01,0,0\n0.02,0,0\n")
    (tmp_path / "o.csv").write_bytes(b"previous output\n")
    monkeypatch.chdir(tmp_path)

    def full(fd: int) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    assert main(["track", "in.csv", "--out", "o.csv", "--quiet"]) == 1
    assert capsys.readouterr().err.strip() == "mudforce track: error: cannot write o.csv: No space left on device"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.csv", "o.csv"]
    assert (tmp_path / "o.csv").read_bytes() == b"previous output\n"
