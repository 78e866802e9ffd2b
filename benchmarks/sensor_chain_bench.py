"""The sensor-chain bench of ``python benchmarks/bench_estimation.py --sensor-chain`` (see docs/estimation.md).

Measures, and asserts nothing: how ``identify_water_content``, ``fit_condition``
and ``MudTracker`` fare on recordings made as a robot's sensors would make
them. Every recording starts clean, simulated at 2 kHz along the true path:

* ``robot``: one foot (front left) of the MuJoCo quadruped of
  :mod:`mudforce.motions.quadruped` (walk, walk-fast, trot, trot-fast, bound in
  turn), with the vertical force MuJoCo applied to it (the load it carried:
  while the foot sticks, anywhere in the mud's rest band);
* ``robot-model``: the same foot path with the model's force along it
  (:func:`mudforce.simulate`, exact): what the kinematic model explains;
* ``gait``: :func:`mudforce.motions.gait.gait` walks with the model's force.

Water contents are drawn uniformly in [15 %, 35 %], a force bias in
[-1, 1] N; every recording carries 0.2 N of force noise and 0.03 mm of depth
noise and is sampled at 100 Hz unless the corruption says otherwise. Each
corruption of :data:`ROWS` is applied with :func:`mudforce.motions.sensor_chain.apply`,
seeded per (recording, corruption).

Counts per corruption:

* identify: within 1.5 points; interval covers the truth; flagged (any
  warning, e.g. the misfit warning: ``model_misses_data``, or refused in
  one line, e.g. when an offset puts every sample above the surface; a
  refusal is honest and counts as neither within nor covering); confidently
  wrong (interval misses the truth and nothing flagged). Standard rows pass
  when >= 90 % are within 1.5 points and >= 90 % covered; hard rows when
  none is confidently wrong.
* fit (``--fit-recordings`` of each source, on the rows marked for fits):
  every free parameter within 3 standard errors (on the logarithm) of
  Table I's value at the true water content; flagged (any warning, a
  parameter not determined, or refused); confidently wrong (some parameter beyond 3
  standard errors, or not determined, and no warning).
* tracker, over the samples 3 s or more after the start, pooled: share
  within 1.5 points, share covered by the 95 % interval; a sample whose
  interval misses the truth is confidently wrong unless a change of mud or
  the tracker's misfit flag is raised at it (as a share, and a count); the
  recordings' median interval width; and the change flags raised
  (every one false: no recording changes mud). Standard rows pass when
  >= 80 % of the samples are covered and >= 80 % within 1.5 points; hard
  rows when no sample is confidently wrong; every row only with at most one
  false change flag per 10 minutes of recording (issue 23, point 5).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from mudforce._plumbing.progress import Progress
from mudforce.errors import InputError
from mudforce.estimation.calibration import fit_condition, identify_water_content
from mudforce.estimation.calibration.dataset import Trial
from mudforce.estimation.tracker import track
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.gait import gait
from mudforce.motions.sensor_chain import SensorChain, apply, drift_path
from mudforce.steppers.simulation import simulate

FINE_RATE = 2000.0  # [Hz] the clean simulation
RATE = 100.0  # [Hz] the recordings' rate unless a row sets it
FORCE_NOISE = 0.2  # [N]
DEPTH_NOISE = 3e-5  # [m]
TRACK_AFTER = 3.0  # [s] the tracker is judged from this time on
SOURCES = ("robot", "robot-model", "gait")

# (name, set, corruptions beyond the baseline noise, fit this row?)
ROWS: list[tuple[str, str, dict[str, float], bool]] = [
    ("clean (100 Hz)", "baseline", {}, True),
    ("offset +2 mm", "standard", {"depth_offset": 0.002}, True),
    ("offset -2 mm", "standard", {"depth_offset": -0.002}, False),
    ("delay 5 ms", "standard", {"force_delay": 0.005}, False),
    ("low-pass 10 ms", "standard", {"force_lowpass": 0.01}, True),
    ("gain +5 %", "standard", {"force_gain": 1.05}, True),
    ("gain -5 %", "standard", {"force_gain": 0.95}, False),
    ("depth noise 0.3 mm", "standard", {"depth_noise": 3e-4}, False),
    ("depth noise 1 mm", "standard", {"depth_noise": 1e-3}, True),
    ("drift +2 mm / 30 s", "standard", {"drift": 0.002}, True),
    ("drift -2 mm / 30 s", "standard", {"drift": -0.002}, False),
    ("50 Hz", "standard", {"rate": 50.0}, True),
    ("standard, all (+)", "standard", {"depth_offset": 0.002, "force_delay": 0.005, "force_lowpass": 0.01,
                                       "force_gain": 1.05, "depth_noise": 3e-4, "drift": 0.002, "rate": 50.0}, True),
    ("standard, all (-)", "standard", {"depth_offset": -0.002, "force_lowpass": 0.01, "force_gain": 0.95,
                                       "depth_noise": 1e-3, "drift": -0.002, "rate": 50.0}, False),
    ("offset +5 mm", "hard", {"depth_offset": 0.005}, True),
    ("offset -5 mm", "hard", {"depth_offset": -0.005}, False),
    ("low-pass 30 ms", "hard", {"force_lowpass": 0.03}, True),
    ("delay 20 ms", "hard", {"force_delay": 0.02}, False),
    ("delay 10 ms + low-pass 10 ms", "hard", {"force_delay": 0.01, "force_lowpass": 0.01}, False),
    ("20 Hz", "hard", {"rate": 20.0}, True),
    ("hard, all", "hard", {"depth_offset": 0.005, "force_delay": 0.01, "force_lowpass": 0.01, "rate": 20.0}, True),
]


def _clean(kind: str, index: int, seed: int, duration: float) -> list[tuple[str, float, Foot, np.ndarray,
                                                                             np.ndarray, np.ndarray]]:
    """The clean fine recordings of one unit: (source, W, foot, time, depth, force) per source."""
    rng = np.random.default_rng([seed, 0 if kind == "robot" else 1, index])
    w = float(rng.uniform(0.15, 0.35))
    if kind == "robot":
        from mudforce.motions.quadruped import GAITS, ROBOT_FOOT, robot_walk

        name = list(GAITS)[index % len(GAITS)]
        run = robot_walk(name, w, seed=int(rng.integers(0, 2**31)), duration=duration)
        return [("robot", w, ROBOT_FOOT, run.time, run.depth, run.force_contact),
                ("robot-model", w, ROBOT_FOOT, run.time, run.depth, run.force)]
    foot = Foot.paper()
    path = gait(int(rng.integers(0, 2**31)), duration=duration, rate=FINE_RATE)
    force = simulate(path.time, path.depth, MudParameters.from_water_content(w), foot, velocity_filter="exact").force
    return [("gait", w, foot, path.time, path.depth, np.asarray(force))]


def _fit_row(fit: Any, w: float, truth: dict[str, float] | None = None) -> dict[str, Any]:
    """One fit judged against ``truth`` (name -> value [SI]; Table I's row at ``w`` [-] by default)."""
    truth = MudParameters.from_water_content(w).to_dict() if truth is None else truth
    beyond, undetermined = [], []
    for name in fit.free:
        se = fit.stderr[name]
        value = fit.parameters[name]
        if se is None or not math.isfinite(se) or se <= 0.0:
            undetermined.append(name)
            continue
        z = math.log(value / truth[name]) / (se / value)
        if abs(z) > 3.0:
            beyond.append(name)
    flagged = bool(fit.warnings) or bool(undetermined)
    ok = not beyond and not undetermined
    return {"ok": ok, "flagged": flagged, "wrong": not ok and not flagged, "beyond": beyond,
            "params": len(fit.free)}


def run_unit(kind: str, index: int, seed: int, duration: float, fit_recordings: int,
             tracker_only: bool = False, rows: Sequence[int] | None = None) -> list[dict[str, Any]]:
    """Every row's results (or those of ``rows``, indices into :data:`ROWS`) on the recordings of one unit (one
    MuJoCo run: two sources; one gait: one). A row's recordings are the same whichever rows run with it."""
    out = []
    for source, w, foot, t, z, f in _clean(kind, index, seed, duration):
        bias = float(np.random.default_rng([seed, 2, index, SOURCES.index(source)]).uniform(-1.0, 1.0))
        for r, (_row, _, corruption, fit_it) in enumerate(ROWS):
            if rows is not None and r not in rows:
                continue
            fields = {"force_noise": FORCE_NOISE, "depth_noise": DEPTH_NOISE, "force_bias": bias, "rate": RATE,
                      **corruption}
            chain = SensorChain(**fields)
            cseed = int(np.random.default_rng([seed, 3, index, SOURCES.index(source), r]).integers(0, 2**32 - 1))
            tt, zz, ff = apply(t, z, f, chain, cseed)
            trial = Trial(f"{source}{index}", w, tt, zz, ff)
            try:
                if tracker_only:
                    raise InputError("--tracker-only")
                res = identify_water_content(trial, foot)
            except InputError:  # refused in one line (e.g. the offset hides every contact): honest, no answer
                res = None
            covered = res is not None and res.interval[0] <= w <= res.interval[1]
            flagged = res is None or bool(res.warnings)
            tr = track(tt, zz, ff, foot)
            late = tt - tt[0] >= TRACK_AFTER
            tw = tr.water_content[late]
            tcov = (tr.low[late] <= w + 1e-12) & (w <= tr.high[late] + 1e-12)
            misfit = getattr(tr, "misfit", None)  # (absent before the misfit flag: the bench also runs on old code)
            tflag = tr.changed[late] if misfit is None else tr.changed[late] | misfit[late]
            item: dict[str, Any] = {
                "seed": seed, "row": r, "source": source, "index": index, "w": w,
                "error": math.nan if res is None else (res.water_content - w) * 100.0, "covered": covered,
                "flagged": flagged, "refused": res is None, "identified": not tracker_only,
                "wrong": not covered and not flagged,
                "t_n": int(late.sum()), "t_within": int(np.sum(np.abs(tw - w) <= 0.015)), "t_cov": int(tcov.sum()),
                "t_wrong": int(np.sum(~tcov & ~tflag)), "t_final": (tr.water_content[-1] - w) * 100.0,
                "t_changes": int(np.sum(tr.changed)),  # every one false: no recording changes mud
                "t_minutes": float(tt[-1] - tt[0]) / 60.0,
                "t_width": float(np.median(tr.high[late] - tr.low[late])) * 100.0 if late.any() else math.nan,
            }
            item.update(_nuisances(res, tr, late, chain, tt, cseed))
            if fit_it and index < fit_recordings and not tracker_only:
                start = time.perf_counter()
                try:
                    item["fit"] = _fit_row(fit_condition([trial], foot, seed=index), w)
                except InputError:  # refused: honest, no answer
                    item["fit"] = {"ok": False, "flagged": True, "wrong": False, "beyond": [], "params": 0}
                item["fit"]["seconds"] = time.perf_counter() - start
            out.append(item)
    return out


def _nuisances(res: Any, tr: Any, late: np.ndarray, chain: SensorChain, tt: np.ndarray,
               cseed: int) -> dict[str, Any]:
    """The surface offset and the force lag each estimator read, against the chain's (issue 23, point 3): identify's
    beyond three standard errors (None where it gave none, or where the offset drifts: no one value is the truth),
    the tracker's samples after TRACK_AFTER beyond three spreads. The offset's truth is ``-(depth_offset +
    drift(t))`` (the models follow the depth plus the offset); the lag's the chain's mean delay, ``force_delay +
    force_lowpass``."""
    offset = -(chain.depth_offset + drift_path(tt, chain, cseed))
    lag = chain.force_delay + chain.force_lowpass
    out: dict[str, Any] = {"i_offset": None, "i_lag": None, "t_offset": None, "t_lag": None,
                           "i_warned": res is not None and bool(res.warnings)}
    if res is not None and math.isfinite(getattr(res, "depth_offset_stderr", math.nan)):
        if chain.drift == 0.0:
            out["i_offset"] = bool(abs(res.depth_offset - offset[0]) > 3.0 * res.depth_offset_stderr)
        out["i_lag"] = bool(abs(res.force_lag - lag) > 3.0 * res.force_lag_stderr)
    if getattr(tr, "depth_offset_stderr", None) is not None and late.any():  # (absent on old code)
        out["t_offset"] = int(np.sum(np.abs(tr.depth_offset[late] - offset[late])
                                     > 3.0 * tr.depth_offset_stderr[late]))
        out["t_lag"] = int(np.sum(np.abs(tr.force_lag[late] - lag) > 3.0 * tr.force_lag_stderr[late]))
    return out


def _units(args: argparse.Namespace) -> list[tuple[str, int]]:
    return [("robot", i) for i in range(args.robots)] + [("gait", i) for i in range(args.walks)]


def _identify_passes(rs: Sequence[dict[str, Any]]) -> bool:
    """A standard row's acceptance for identify on the recordings ``rs``: >= 90 % within 1.5 points and covered."""
    n = len(rs)
    return bool(n) and sum(abs(x["error"]) <= 1.5 for x in rs) >= 0.9 * n and sum(x["covered"] for x in rs) >= 0.9 * n


def _tracker_passes(rs: Sequence[dict[str, Any]]) -> bool:
    """A standard row's acceptance for the tracker on the recordings ``rs`` (before its false change flags): >= 80 %
    of the samples after TRACK_AFTER within 1.5 points and covered."""
    n = sum(x["t_n"] for x in rs)
    return bool(n) and sum(x["t_within"] for x in rs) >= 0.8 * n and sum(x["t_cov"] for x in rs) >= 0.8 * n


def _pct(k: int, n: int) -> str:
    return f"{k}/{n} ({k / n:.0%})" if n else "-"


def _tables(results: Sequence[dict[str, Any]], sources: Sequence[str]) -> list[str]:
    ran = sorted({x["row"] for x in results})
    # (--tracker-only: identify did not run, and its table would read every recording as refused)
    identified = any(x.get("identified", True) for x in results)
    lines = ["### identify_water_content", "",
             "| corruption | set | n | within 1.5 pt | covers truth | flagged (refused) | confidently wrong | "
             "wrong by source (" + " / ".join(sources) + ") | median abs error [pt] | acceptance |",
             "|---|---|---|---|---|---|---|---|---|---|"] if identified else [
             "### identify_water_content", "", "Not run (--tracker-only)."]
    for r in ran if identified else ():
        row, kind = ROWS[r][:2]
        rs = [x for x in results if x["row"] == r]
        n = len(rs)
        within = sum(abs(x["error"]) <= 1.5 for x in rs)
        cov = sum(x["covered"] for x in rs)
        flag = sum(x["flagged"] for x in rs)
        wrong = sum(x["wrong"] for x in rs)
        by = " / ".join(str(sum(x["wrong"] for x in rs if x["source"] == s)) for s in sources)
        refused = sum(x["refused"] for x in rs)
        errors = [abs(x["error"]) for x in rs if not x["refused"]]
        med = float(np.median(errors)) if errors else math.nan
        if kind == "hard":
            verdict = "pass" if wrong == 0 else "FAIL"
        else:
            verdict = "pass" if _identify_passes(rs) else "FAIL"
        lines.append(f"| {row} | {kind} | {n} | {_pct(within, n)} | {_pct(cov, n)} | {_pct(flag, n)} ({refused}) | "
                     f"{_pct(wrong, n)} | {by} | {med:.2f} | {verdict} |")
    if any("fit" in x for x in results):
        lines += ["", "### fit_condition (one recording per fit)", "",
                  "| corruption | set | fits | all parameters within 3 SE | flagged | confidently wrong | "
                  "parameters beyond 3 SE | median time [s] | acceptance |", "|---|---|---|---|---|---|---|---|---|"]
    for r in ran:
        row, kind, _, fit_it = ROWS[r]
        fs = [x["fit"] for x in results if x["row"] == r and "fit" in x]
        if not fit_it or not fs:
            continue
        n = len(fs)
        ok = sum(f["ok"] for f in fs)
        flag = sum(f["flagged"] for f in fs)
        wrong = sum(f["wrong"] for f in fs)
        beyond = sum(len(f["beyond"]) for f in fs)
        total = sum(f["params"] for f in fs)
        verdict = "pass" if wrong == 0 and (kind == "hard" or all(f["ok"] or f["flagged"] for f in fs)) else "FAIL"
        lines.append(f"| {row} | {kind} | {n} | {_pct(ok, n)} | {_pct(flag, n)} | {_pct(wrong, n)} | "
                     f"{beyond}/{total} | {np.median([f['seconds'] for f in fs]):.1f} | {verdict} |")
    lines += ["", f"### MudTracker (samples {TRACK_AFTER:g} s or more after the start, pooled)", "",
              "| corruption | set | recordings | samples within 1.5 pt | samples covered | "
              "recordings covered >= 80 % | samples confidently wrong | median abs final error [pt] | "
              "median interval width [pt] | change flags (all false) | per 10 min | acceptance |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in ran:
        row, kind = ROWS[r][:2]
        rs = [x for x in results if x["row"] == r]
        n = sum(x["t_n"] for x in rs)
        within = sum(x["t_within"] for x in rs)
        cov = sum(x["t_cov"] for x in rs)
        wrong = sum(x["t_wrong"] for x in rs)
        good = sum(x["t_cov"] >= 0.8 * x["t_n"] for x in rs if x["t_n"])
        med = float(np.median([abs(x["t_final"]) for x in rs])) if rs else math.nan
        # (each recording's median width after TRACK_AFTER, their median: how much the intervals say)
        width = float(np.median([x.get("t_width", math.nan) for x in rs])) if rs else math.nan
        if kind == "hard":
            verdict = "pass" if wrong == 0 else "FAIL"
        else:
            verdict = "pass" if _tracker_passes(rs) else "FAIL"
        changes = sum(x.get("t_changes", 0) for x in rs)
        rate = 10.0 * changes / max(sum(x.get("t_minutes", 0.0) for x in rs), 1e-9)
        if rate > 1.0:  # issue 23: at most one false change flag per 10 minutes
            verdict = "FAIL"
        lines.append(f"| {row} | {kind} | {len(rs)} | {within / max(n, 1):.0%} | {cov / max(n, 1):.0%} | "
                     f"{good}/{len(rs)} | {wrong / max(n, 1):.1%} ({wrong}) | {med:.2f} | {width:.1f} | {changes} | "
                     f"{rate:.2f} | {verdict} |")
    lines += ["", "### The nuisances (issue 23, point 3): read beyond three standard errors", "",
              "identify: recordings whose surface offset or force lag is beyond three standard errors of the chain's "
              "(the offset not judged under a drift), and how many of those identify gave no warning; MudTracker: "
              "samples after "
              f"{TRACK_AFTER:g} s beyond three spreads. The lag's truth is the chain's mean delay (delay plus "
              "low-pass).", "",
              "| corruption | set | identify: offset | identify: lag | MudTracker: offset | MudTracker: lag |",
              "|---|---|---|---|---|---|"]
    for r in ran:
        row, kind = ROWS[r][:2]
        rs = [x for x in results if x["row"] == r]
        cells = []
        for key, per in (("i_offset", False), ("i_lag", False), ("t_offset", True), ("t_lag", True)):
            got = [x for x in rs if x.get(key) is not None]
            k = sum(int(x[key]) for x in got)
            n = sum(x["t_n"] for x in got) if per else len(got)
            if not got:
                cells.append("-")
            elif per:  # the tracker's: samples
                cells.append(f"{k / max(n, 1):.1%} ({k})")
            else:  # identify's: recordings, and those it gave no warning
                quiet = sum(int(x[key]) for x in got if not x["i_warned"])
                cells.append(f"{k}/{n} ({quiet} unwarned)")
        lines.append(f"| {row} | {kind} | " + " | ".join(cells) + " |")
    return lines


def _run_units(unit: Callable[..., list[dict[str, Any]]], units: Sequence[tuple[str, int]], args: argparse.Namespace,
               label: str, *rest: Any) -> list[dict[str, Any]]:
    """``unit(kind, i, *rest)`` over every unit, on ``args.jobs`` worker processes, with a progress line; the
    results in the order of completion (the caller sorts them)."""
    results: list[dict[str, Any]] = []
    with Progress(len(units), label, quiet=args.quiet) as progress:
        if args.jobs == 1:
            for kind, i in units:
                results += unit(kind, i, *rest)
                progress.update(1, f"{kind} {i}")
            return results
        from concurrent.futures import as_completed

        from mudforce.reproduce.jobs import executor

        pool = executor(args.jobs)
        try:
            futures = {pool.submit(unit, kind, i, *rest): (kind, i) for kind, i in units}
            for future in as_completed(futures):
                results += future.result()
                progress.update(1, "{} {}".format(*futures[future]))
        finally:
            pool.shutdown()
    return results


def parse_rows(spec: str | None) -> list[int] | None:
    """``--rows``: comma-separated row numbers as the tables list them (from 1) and set names (``baseline``,
    ``standard``, ``hard``); indices into :data:`ROWS`, None for every row."""
    if not spec:
        return None
    rows: set[int] = set()
    for token in (x.strip() for x in spec.split(",")):
        sets = [r for r, (_, kind, _, _) in enumerate(ROWS) if kind == token]
        if sets:
            rows.update(sets)
        elif token.isdigit() and 1 <= int(token) <= len(ROWS):
            rows.add(int(token) - 1)
        else:
            raise InputError(f"--rows: {token!r} is not a row; expected row numbers 1-{len(ROWS)} as the tables "
                             "list them, or baseline, standard, hard, comma-separated (e.g. 3,6,standard)")
    return sorted(rows)


def parse_seeds(spec: str | None, seed: int) -> list[int]:
    """``--seeds``: ``A-B`` (inclusive) or comma-separated seeds; ``[seed]`` when not given."""
    if not spec:
        return [seed]
    try:
        if "-" in spec:
            a, b = (int(x) for x in spec.split("-", 1))
            seeds = list(range(a, b + 1))
        else:
            seeds = [int(x) for x in spec.split(",")]
    except ValueError:
        seeds = []
    if not seeds or min(seeds) < 0:
        raise InputError(f"--seeds: {spec!r} is not a list of seeds; expected A-B or comma-separated seeds >= 0 "
                         "(e.g. 97-106)")
    return seeds


def _wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The Wilson score interval of a share k/n [-] (95 % by default)."""
    if n == 0:
        return math.nan, math.nan
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return centre - half, centre + half


def _per_recording(rs: Sequence[dict[str, Any]], key: str) -> tuple[float, float, float]:
    """The tracker's pooled share of samples ``key`` [-], and a 95 % interval on it read over recordings (the samples
    of one recording are not independent; each recording's share, weighted by its samples: a ratio estimator)."""
    n = np.array([x["t_n"] for x in rs if x["t_n"]], dtype=float)
    k = np.array([x[key] for x in rs if x["t_n"]], dtype=float)
    if n.size < 2:
        return math.nan, math.nan, math.nan
    share = k.sum() / n.sum()
    resid = (k - share * n) / n.mean()
    se = float(np.sqrt(np.sum(resid**2) / (n.size * (n.size - 1))))
    return share, max(share - 1.96 * se, 0.0), min(share + 1.96 * se, 1.0)


def _pooled_table(results: Sequence[dict[str, Any]], seeds: Sequence[int]) -> list[str]:
    """Across seeds: each standard row's shares pooled over every seed's recordings, with 95 % intervals, and how
    many seeds pass it alone (the letter asks >= 90 % of identify's recordings within and covered, >= 80 % of the
    tracker's samples); none where only hard rows ran."""
    if all(ROWS[x["row"]][1] == "hard" for x in results):
        return []
    lines = [f"### Pooled over {len(seeds)} seeds ({seeds[0]}-{seeds[-1]})" if seeds == list(range(seeds[0],
             seeds[-1] + 1)) else f"### Pooled over seeds {', '.join(map(str, seeds))}", "",
             "Shares pooled over every seed's recordings, with 95 % intervals (identify's: Wilson's on the "
             "recordings; the tracker's: over recordings, its samples pooled within each), and the seeds on which "
             "the row passes alone.", "",
             "| corruption | set | identify within 1.5 pt | identify covers | identify: seeds passing | "
             "tracker within 1.5 pt | tracker covered | tracker: seeds passing |", "|---|---|---|---|---|---|---|---|"]

    def share(k: int, n: int) -> str:
        lo, hi = _wilson(k, n)
        return f"{k}/{n} = {k / n:.1%} [{lo:.1%}, {hi:.1%}]" if n else "-"

    def tshare(rs: Sequence[dict[str, Any]], key: str) -> str:
        s, lo, hi = _per_recording(rs, key)
        return f"{s:.1%} [{lo:.1%}, {hi:.1%}]" if math.isfinite(s) else "-"

    for r in sorted({x["row"] for x in results}):
        row, kind = ROWS[r][:2]
        if kind == "hard":
            continue
        rs = [x for x in results if x["row"] == r]
        n = len(rs) if any(x.get("identified", True) for x in rs) else 0  # (none ran: --tracker-only)
        within = sum(abs(x["error"]) <= 1.5 for x in rs)
        cov = sum(x["covered"] for x in rs)
        per_seed = [[x for x in rs if x["seed"] == seed] for seed in seeds]
        i_pass = f"{sum(_identify_passes(ss) for ss in per_seed)}/{len(seeds)}" if n else "-"
        t_pass = sum(_tracker_passes(ss) for ss in per_seed)
        lines.append(f"| {row} | {kind} | {share(within, n)} | {share(cov, n)} | {i_pass} | "
                     f"{tshare(rs, 't_within')} | {tshare(rs, 't_cov')} | {t_pass}/{len(seeds)} |")
    return lines


def run_bench(args: argparse.Namespace) -> int:
    """Run the bench and print its tables (markdown); returns 0."""
    from mudforce.io.units import parse_quantity

    duration = parse_quantity(args.duration or "30s", "time", name="--duration")
    rows = parse_rows(args.rows)
    seeds = parse_seeds(args.seeds, args.seed)
    if args.robots:
        try:
            import mujoco  # noqa: F401
        except ImportError:
            print("the robot recordings need MuJoCo: pip install 'mudforce[mujoco]' (or pass --robots 0)",
                  file=sys.stderr)
            return 2
    if args.jobs < 1 or min(args.robots, args.walks, args.fit_recordings) < 0:
        raise InputError("--jobs must be >= 1; --robots, --walks and --fit-recordings >= 0")
    start = time.perf_counter()
    results = []
    for seed in seeds:
        label = "sensor-chain bench" + (f", seed {seed}" if len(seeds) > 1 else "")
        results += _run_units(run_unit, _units(args), args, label, seed, duration, args.fit_recordings,
                              args.tracker_only, rows)
    # (independent of the workers)
    results.sort(key=lambda x: (x["seed"], SOURCES.index(x["source"]), x["index"], x["row"]))
    elapsed = time.perf_counter() - start
    sources = [s for s in SOURCES if any(x["source"] == s for x in results)]
    first = min(x["row"] for x in results) if results else 0
    counts = ", ".join(f"{sum(1 for x in results if x['source'] == s and x['row'] == first)} {s}" for s in sources)
    print(f"## Sensor-chain bench: {counts} recordings of {duration:g} s, "
          + (f"seed {seeds[0]}" if len(seeds) == 1 else f"seeds {args.seeds}, pooled"))
    print()
    print(f"Every row: force noise {FORCE_NOISE:g} N, depth noise {DEPTH_NOISE * 1e3:g} mm, a bias in [-1, 1] N, "
          f"{RATE:g} Hz unless the row says otherwise; W in [15 %, 35 %].")
    print()
    print("\n".join(_tables(results, sources)))
    pooled = _pooled_table(results, seeds) if len(seeds) > 1 else []
    if pooled:
        print()
        print("\n".join(pooled))
    print()
    print(f"wall time {elapsed:.0f} s with --jobs {args.jobs}")
    return 0


# ---------------------------------------------------------------------------- the misfit flag (issue 23, point 4)
FLAG_SOURCES = ("gait", "robot", "robot-model", "F = kz (gait)", "alpha x2, sigma_y x0.3 (gait)",
                "F = kz (robot)", "alpha x2, sigma_y x0.3 (robot)")


def run_flag_unit(kind: str, index: int, seed: int, duration: float, rates: Sequence[float],
                  known_depth_noise: bool, family_window: float | None = None,
                  with_fit: bool = False) -> list[dict[str, Any]]:
    """identify's misfit flag, and MudTracker's, on one unit's clean recordings and on two off-family muds along the
    same path.

    Off family: a granular law ``F = k z`` (``k`` matching the model's peak) and the mud with ``alpha`` x2 and
    ``sigma_y`` x0.3, each simulated at 2 kHz along the true path; every force through ``SensorChain(force_noise,
    depth_noise, force_bias, rate)`` at each rate (seeded per unit, source and rate).
    """
    import dataclasses

    out = []
    recs = _clean(kind, index, seed, duration)
    _, w, foot, t, z, model_force = recs[-1]
    q = MudParameters.from_water_content(w)
    odd = dataclasses.replace(q, alpha=2.0 * q.alpha, sigma_y=0.3 * q.sigma_y)
    depth_in = np.maximum(z, 0.0)
    path = "robot" if kind == "robot" else "gait"
    forces = [(s, f) for s, *_, f in recs] + [
        (f"F = kz ({path})", float(np.max(model_force)) / float(np.max(depth_in)) * depth_in),
        (f"alpha x2, sigma_y x0.3 ({path})", np.asarray(simulate(t, z, odd, foot, velocity_filter="exact").force))]
    for s, (source, f) in enumerate(forces):  # s: the source's place in the unit (seeds the chain)
        bias = float(np.random.default_rng([seed, 2, index, s]).uniform(-1.0, 1.0))
        for rate in rates:
            chain = SensorChain(force_noise=FORCE_NOISE, depth_noise=DEPTH_NOISE, force_bias=bias, rate=rate)
            cseed = int(np.random.default_rng([seed, 5, index, s, int(rate)]).integers(0, 2**32 - 1))
            tt, zz, ff = apply(t, z, f, chain, cseed)
            try:
                res = identify_water_content(Trial(f"{source}{index}", w, tt, zz, ff), foot,
                                             depth_noise=DEPTH_NOISE if known_depth_noise else None)
            except InputError:
                out.append({"source": source, "rate": rate, "refused": True})
                continue
            covered = res.interval[0] <= w <= res.interval[1]
            # MudTracker's own (online) flag on the same recording: raised on any sample, and the samples after
            # TRACK_AFTER whose interval misses the truth with the flag down
            # (with the family check where asked: the tracker's own estimates and flag are the same bits either way)
            tr = track(tt, zz, ff, foot) if family_window is None else track(tt, zz, ff, foot,
                                                                               family_window=family_window)
            late = tt - tt[0] >= TRACK_AFTER
            missed = (tr.low[late] > w) | (w > tr.high[late])
            own = np.asarray(tr.misfit, dtype=bool)
            item = {"source": source, "rate": rate, "refused": False, "ratio": res.misfit_ratio,
                    "flag": res.model_misses_data, "covered": covered,
                    "wrong": not covered and not res.warnings,
                    "t_flag": bool(np.any(own)),
                    "t_share": float(np.mean(own[late])) if late.any() else 0.0,
                    "t_wrong": int(np.sum(missed & ~own[late]))}
            if family_window is not None:
                # the family check beside the tracker (the tracker's own estimates are the same bits with it or
                # without): checks flagged and told nothing, and the samples from the first check on whose interval
                # misses the truth with both flags down
                fam = tr.family_checks
                flags = np.asarray(tr.family_misfit)
                after = np.arange(tt.size) >= (fam[0][0] if fam else tt.size)
                miss = (tr.low > w) | (w > tr.high)
                item.update(f_checks=len(fam), f_flagged=sum(v.model_misses_data is True for _, v in fam),
                            f_none=sum(v.model_misses_data is None for _, v in fam), f_any=bool(flags.any()),
                            f_n=int(after.sum()), f_share=float(np.mean((flags | own)[after])) if after.any()
                            else 0.0, f_wrong=int(np.sum(miss & after & ~flags & ~own)))
            if with_fit:  # fit's own misfit flag on the same recording (one recording a fit, seeded as the bench's)
                fit = fit_condition([Trial(f"{source}{index}", w, tt, zz, ff)], foot, seed=index)
                # judged against the mud that made the force: the odd mud's own parameters; a linear law has none
                truth = odd.to_dict() if source.startswith("alpha x2") else None
                wrong = None if source.startswith("F = kz") else _fit_row(fit, w, truth)["wrong"]
                item.update(fit_ratio=fit.misfit_ratio, fit_flag=fit.model_misses_data, fit_wrong=wrong)
            out.append(item)
    return out


def _print_flag_table(results: Sequence[dict[str, Any]], rates: Sequence[float],
                      cell: Callable[[list[dict[str, Any]]], str]) -> None:
    """One table of the flag bench: a row per source, a column per rate, each cell ``cell`` of its recordings."""
    print("| source | " + " | ".join(f"{r:g} Hz" for r in rates) + " |")
    print("|---|" + "---|" * len(rates))
    for source in FLAG_SOURCES:
        cells = []
        for rate in rates:
            rs = [x for x in results if x["source"] == source and x["rate"] == rate]
            if not rs:
                break
            cells.append(cell(rs))
        if cells:
            print(f"| {source} | " + " | ".join(cells) + " |")


def run_flag_bench(args: argparse.Namespace) -> int:
    """The misfit flag's table: in family (gait, robot, robot-model) it should stay quiet, off family fire."""
    from mudforce.io.units import parse_quantity

    duration = parse_quantity(args.duration or "10s", "time", name="--duration")
    rates = [parse_quantity(r, "frequency", name="--flag-rates") for r in args.flag_rates.split(",")]
    family_window = None if args.family_window is None else parse_quantity(args.family_window, "time",
                                                                           name="--family-window")
    if args.jobs < 1:
        raise InputError("--jobs must be >= 1")
    start = time.perf_counter()
    results = _run_units(run_flag_unit, _units(args), args, "misfit-flag bench", args.seed, duration, rates,
                         args.known_depth_noise, family_window, args.fit_flag)
    # the cells count and pool their recordings: the same tables in any order of completion
    print(f"## identify's misfit flag: {args.robots} MuJoCo runs, {args.walks} gait walks of {duration:g} s, "
          f"seed {args.seed}; depth noise {'given' if args.known_depth_noise else 'estimated'}")
    print()
    print(f"Force noise {FORCE_NOISE:g} N, depth noise {DEPTH_NOISE * 1e3:g} mm, a bias in [-1, 1] N. Each cell: "
          "misfit ratio min-max, flagged / recordings (model_misses_data: the ratio > 1.25, the tail's share > "
          "4.5 %, what another mud explains > 0.9, or two of these past 80 % of their limits); covered; confidently "
          "wrong (refused).")
    print()
    def identify_cell(rs: list[dict[str, Any]]) -> str:
        ok = [x for x in rs if not x["refused"]]
        ratios = [x["ratio"] for x in ok]
        span = f"{min(ratios):.2f}-{max(ratios):.2f}" if ratios else "-"
        return (f"{span}, {sum(x['flag'] for x in ok)}/{len(rs)}; covered {sum(x['covered'] for x in ok)}; "
                f"wrong {sum(x['wrong'] for x in ok)} ({len(rs) - len(ok)})")

    def tracker_cell(rs: list[dict[str, Any]]) -> str:
        ok = [x for x in rs if not x["refused"]]
        if not ok:
            return "-"
        return (f"{sum(x['t_flag'] for x in ok)}/{len(ok)}; {np.mean([x['t_share'] for x in ok]):.1%}; "
                f"wrong {sum(x['t_wrong'] for x in ok)}")

    _print_flag_table(results, rates, identify_cell)
    print()
    print(f"MudTracker's own misfit flag on the same recordings (track, default options). Each cell: flagged (the "
          f"flag raised on any sample) / recordings; the mean share of samples flagged after {TRACK_AFTER:g} s; "
          "samples after it confidently wrong (the interval misses the truth, the flag down).")
    print()
    _print_flag_table(results, rates, tracker_cell)
    print()
    if family_window is not None:
        def family_cell(rs: list[dict[str, Any]]) -> str:
            ok = [x for x in rs if not x["refused"]]
            if not ok:
                return "-"
            return (f"{sum(x['f_any'] for x in ok)}/{len(ok)}; {sum(x['f_flagged'] for x in ok)}/"
                    f"{sum(x['f_checks'] for x in ok)} ({sum(x['f_none'] for x in ok)}); "
                    f"{np.mean([x['f_share'] for x in ok]):.1%}; wrong {sum(x['f_wrong'] for x in ok)}")

        print(f"MudTracker with its family check (track(family_window={family_window:g}): identify's misfit flag on "
              f"the last {family_window:g} s, every 2.5 s). Each cell: recordings flagged by a check / recordings; "
              "checks flagged / checks (told nothing); the mean share of the samples from the first check on with "
              "either flag raised; samples from the first check on confidently wrong (the interval misses the "
              "truth, both flags down).")
        print()
        _print_flag_table(results, rates, family_cell)
        print()
    if args.fit_flag:
        def fit_cell(rs: list[dict[str, Any]]) -> str:
            ok = [x for x in rs if not x["refused"]]
            if not ok:
                return "-"
            ratios = [x["fit_ratio"] for x in ok]
            judged = [x["fit_wrong"] for x in ok if x["fit_wrong"] is not None]
            return (f"{min(ratios):.2f}-{max(ratios):.2f}, {sum(x['fit_flag'] for x in ok)}/{len(ok)}; "
                    f"wrong {sum(judged) if judged else '-'}")

        print("fit_condition's own misfit flag on the same recordings (one recording a fit, seed the unit's index). "
              "Each cell: misfit ratio min-max, flagged (model_misses_data: the ratio > 1.25) / recordings; fits "
              "confidently wrong (a parameter beyond 3 standard errors of the mud that made the force, nothing "
              "warned; '-' for the linear law, which has no such parameters). The two off-family muds are inside "
              "fit's nine-parameter family (alpha z^beta with beta free; alpha and sigma_y free): its flag cannot "
              "tell them, identify's does.")
        print()
        _print_flag_table(results, rates, fit_cell)
        print()
    print(f"wall time {time.perf_counter() - start:.0f} s")
    return 0
