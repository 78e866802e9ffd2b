"""Intrusion datasets: a folder with ``dataset.json`` and one CSV per trial, or one tidy CSV.

Layout (documented in ``docs/calibration.md``)::

    DIR/dataset.json
    DIR/w25_v10_r1.csv        columns time_s, depth_m (or depth_mm), force_N
    ...

``dataset.json``::

    {"foot": {"shape": "cuboid", "length_m": 0.051, "width_m": 0.038},
     "trials": [{"file": "w25_v10_r1.csv", "water_content": 0.25,
                 "velocity_m_s": 0.01, "repeat": 1}, ...]}

A tidy CSV holds every trial in one file, with the columns
``trial, water_content, time_s, depth_m, force_N`` (one row per sample).

Every value is SI once loaded: time [s], depth [m] positive below the
undisturbed surface, force [N] positive up (resistance), water content a
volume fraction [-].
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mudforce.errors import InputError, is_integer, is_real, real_array, shown
from mudforce.io import atomic_write_text, check_input_name, dumps_json, load_json
from mudforce.io.tables import COLUMN_LIMITS, COLUMN_UNITS, check_time, read_columns
from mudforce.model.foot import Foot, parse_foot

__all__ = [
    "MANIFEST_NAME",
    "MIN_SAMPLES",
    "Dataset",
    "Trial",
    "foot_from_json",
    "foot_to_json",
    "load_dataset",
    "load_trial",
    "parse_foot",
    "save_dataset",
]

#: The manifest's file name inside a dataset folder.
MANIFEST_NAME = "dataset.json"

#: Fewest samples a trial may have [-] (the motion fit needs a handful per segment).
MIN_SAMPLES = 20
#: Most trials per water content (and speed) one synthetic dataset makes [-] (ours; the paper's protocol has 3): past
#: it a count is a mistake, which ran for hours or for ever (10**400). A trial's repeat number is at most this too.
#: (Importable from :mod:`~mudforce.estimation.calibration.synth`, which makes the datasets.)
MAX_REPEATS = 1000
#: Largest finite float64 [-]: a label beyond it (a Python int such as 10**400) cannot be held as a float.
_FLOAT_MAX = float(np.finfo(np.float64).max)

_TRIAL_COLUMNS = {"time": COLUMN_UNITS["time"], "depth": COLUMN_UNITS["depth"], "force": COLUMN_UNITS["force"]}
_EXTRA_KEYS = ("description", "synthetic")  # a manifest's entries a Dataset keeps verbatim (its extra)
_TOP_KEYS = ("foot", "trials", *_EXTRA_KEYS)
_TRIAL_KEYS = ("file", "water_content", "velocity_m_s", "repeat")


@dataclass(frozen=True, eq=False)
class Trial:
    """One measured intrusion: the foot goes down from above the surface, holds, and comes back up.

    Attributes
    ----------
    name : str
        The trial's file name (or its id in a tidy CSV).
    water_content : float
        Volume fraction of water of the mud [-], e.g. 0.25.
    time : ndarray
        Sample times [s], strictly increasing.
    depth : ndarray
        Measured foot depth below the undisturbed surface [m], positive down.
    force : ndarray
        Measured vertical force on the foot [N], positive up, not tared.
    velocity : float or None
        Nominal intrusion/withdrawal speed from the manifest [m/s] (metadata;
        the fit measures the actual speed from ``depth``).
    repeat : int or None
        Repeat number within its condition, in [0, :data:`MAX_REPEATS`] (1000).
    """

    name: str
    water_content: float
    time: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    velocity: float | None = None
    repeat: int | None = None

    def __post_init__(self) -> None:
        # the labels, checked as a manifest's are (a string water content reached a fit's result as its label)
        if not isinstance(self.name, str):
            raise InputError(f"a trial's name must be a str, got {type(self.name).__name__}")
        w = self.water_content
        if not is_real(w) or not (0.0 < w < 1.0 or (not is_integer(w) and math.isnan(w))):  # isnan(10**400) raised
            raise InputError(f"{self.name}: water_content is {shown(w)}; expected a number in (0, 1), e.g. 0.25 for "
                             "25%, or NaN (unknown)")
        object.__setattr__(self, "water_content", float(w))
        v = self.velocity
        if v is not None and not (is_real(v) and 0.0 < v <= _FLOAT_MAX):  # float(10**400) raised OverflowError
            raise InputError(f"{self.name}: velocity is {shown(v)}; expected None or a number > 0 [m/s], e.g. 0.01")
        if v is not None:
            object.__setattr__(self, "velocity", float(v))
        r = self.repeat
        # at most MAX_REPEATS: 10**400 was taken, saved, and the saved manifest could not be read back
        if r is not None and (not is_integer(r) or not 0 <= r <= MAX_REPEATS):
            raise InputError(f"{self.name}: repeat is {shown(r)}; expected None or an integer in [0, {MAX_REPEATS}]")
        if r is not None:
            object.__setattr__(self, "repeat", int(r))
        # the calibration's entry: real numbers only (complex, boolean, string and object arrays refused)
        for attr, unit in (("time", "s"), ("depth", "m"), ("force", "N")):
            object.__setattr__(self, attr, real_array(getattr(self, attr), f"{self.name}: {attr}", unit))
        # the shape, finite values and time order, checked of arrays as the readers check a file (a Trial made in
        # Python met none of it: a NaN force or backwards time reached the fits as a LinAlgError or a ValueError;
        # found 2026-11-29). The readers' bounds (COLUMN_LIMITS) are checked where a trial is used or saved
        t, z, f = self.time, self.depth, self.force
        if t.ndim != 1 or z.shape != t.shape or f.shape != t.shape:
            raise InputError(f"{self.name}: time, depth and force must be 1-D of one length, got {t.shape}, "
                             f"{z.shape}, {f.shape}")
        for attr, values, unit in (("time", t, "s"), ("depth", z, "m"), ("force", f, "N")):
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                k = int(bad[0])
                raise InputError(f"{self.name}: {attr} sample {k} is {float(values[k])!r}; expected a finite "
                                 f"value [{unit}]")
        check_time(self.name, t, "time")

    def check_bounds(self, *, made: bool = False) -> None:
        """Refuse what :func:`load_trial` refuses of a file: fewer than :data:`MIN_SAMPLES` samples, or a value
        beyond :data:`mudforce.io.tables.COLUMN_LIMITS`. ``made``: the trial was made here (synth), and the
        message says what to change."""
        where = f"trial {self.name}"
        if self.time.size < MIN_SAMPLES:
            raise InputError(f"{where}: only {_samples(self.time.size)}; the readers need at least {MIN_SAMPLES} "
                             "per trial" + (" (a higher rate or a longer motion)" if made else ""))
        for quantity, unit, values in (("time", "s", self.time), ("depth", "m", self.depth),
                                       ("force", "N", self.force)):
            limit = COLUMN_LIMITS[quantity]
            worst = float(np.max(np.abs(values)))
            if not worst <= limit:  # NaN too
                raise InputError(f"{where}: the {quantity} reaches {worst:.6g} {unit}, beyond the +-{limit:g} {unit} "
                                 "that the readers accept" + (" (lower the noise, bias, depth or size that made it)"
                                                              if made else ""))

    def __len__(self) -> int:
        return int(self.time.shape[0])


@dataclass(frozen=True, eq=False)
class Dataset:
    """A set of trials on one foot.

    Attributes
    ----------
    foot : Foot
        The intruder's geometry (contact area [m^2], width ``H`` [m]).
    trials : tuple of Trial
        In manifest order; at least one (a list is kept as a tuple).
    source : str
        Where it was loaded from.
    extra : dict or None
        The manifest's ``description`` and ``synthetic`` entries, if any (kept verbatim); no other key
        (:func:`save_dataset` writes them into ``dataset.json``, which keeps only these).
    inputs : tuple of str
        Every file and folder it was read from (folder, manifest, trial
        files), so that a command can refuse to write onto any of them.
    """

    foot: Foot
    trials: tuple[Trial, ...]
    source: str = ""
    extra: Mapping[str, Any] | None = None
    inputs: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        # checked when made, as a manifest is read: a str foot raised AttributeError in the fits and save_dataset, one
        # Trial TypeError (not iterable), no trials fitted to an empty result and saved a manifest load_dataset
        # refuses, as it refuses an extra key the manifest does not know (which save_dataset wrote)
        if not isinstance(self.foot, Foot):
            raise InputError(f"a Dataset's foot must be a Foot, got {type(self.foot).__name__}")
        trials = self.trials
        if isinstance(trials, Trial):
            raise InputError("a Dataset's trials must be a tuple of Trial, got one Trial: pass (trial,)")
        if not isinstance(trials, (tuple, list)) or not trials:
            got = f"an empty {type(trials).__name__}" if isinstance(trials, (tuple, list)) else type(trials).__name__
            raise InputError(f"a Dataset's trials must be a non-empty tuple of Trial, got {got}")
        for k, trial in enumerate(trials):
            if not isinstance(trial, Trial):
                raise InputError(f"a Dataset's trials[{k}] must be a Trial, got {type(trial).__name__}")
        object.__setattr__(self, "trials", tuple(trials))
        if self.extra is not None:
            if not isinstance(self.extra, Mapping):
                raise InputError(f"a Dataset's extra must be a mapping or None, got {type(self.extra).__name__}")
            unknown = sorted(map(str, set(self.extra) - set(_EXTRA_KEYS)))
            if unknown:
                raise InputError(f"a Dataset's extra holds {', '.join(unknown)}; expected only "
                                 f"{' and '.join(_EXTRA_KEYS)} (what dataset.json keeps)")

    @property
    def water_contents(self) -> list[float]:
        """The distinct water contents [-], ascending."""
        return sorted({t.water_content for t in self.trials})

    def conditions(self) -> dict[float, tuple[Trial, ...]]:
        """Trials grouped by water content [-], ascending; InputError if a trial's is unknown (NaN)."""
        unknown = [t.name for t in self.trials if math.isnan(t.water_content)]
        if unknown:  # NaN equals nothing: its group was empty, and the fits said "no trials to fit"
            raise InputError(f"trial {unknown[0]} has no water content (NaN), and a dataset's trials are grouped by "
                             "it; give each trial its water_content (e.g. 0.25), or fit them as one mud with "
                             "fit_condition")
        return {w: tuple(t for t in self.trials if t.water_content == w) for w in self.water_contents}


# ---------------------------------------------------------------------------- foot
def foot_from_json(data: Any, where: str) -> Foot:
    """Build a :class:`Foot` from the manifest's ``foot`` object.

    Accepted: ``{"shape": "cuboid", "length_m", "width_m"}``,
    ``{"shape": "disc", "diameter_m"}``, ``{"shape": "custom", "area_m2", "width_m"}``;
    lengths may be given in mm instead (``length_mm`` ...), but each quantity in one
    unit only (``length_m`` beside ``length_mm`` is refused).
    """
    example = '{"shape": "cuboid", "length_m": 0.051, "width_m": 0.038}'
    if not isinstance(data, Mapping):
        raise InputError(f"{where}: foot must be an object like {example}")
    shape = data.get("shape")
    needs = {"cuboid": ("length", "width"), "disc": ("diameter",), "custom": ("area", "width")}
    if shape not in needs:
        raise InputError(f'{where}: foot.shape is {shape!r}; expected "cuboid", "disc" or "custom", e.g. {example}')
    allowed = {"shape"}
    values: dict[str, float] = {}
    for quantity in needs[shape]:
        spellings = (("area_m2", 1.0), ("area_mm2", 1e-6)) if quantity == "area" else (
            (f"{quantity}_m", 1.0), (f"{quantity}_mm", 1e-3))
        allowed.update(s for s, _ in spellings)
        found = [(s, f) for s, f in spellings if s in data]
        if not found:
            raise InputError(f"{where}: foot needs {spellings[0][0]} (or {spellings[1][0]}) for shape {shape!r}")
        if len(found) > 1:  # as the CSV readers refuse depth_m beside depth_mm: which would count?
            raise InputError(f"{where}: foot gives both {found[0][0]} and {found[1][0]} for its {quantity}; "
                             "keep one of them")
        key, factor = found[0]
        value = data[key]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
            raise InputError(f"{where}: foot.{key} is {value!r}; expected a positive number")
        values[quantity] = float(value) * factor
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise InputError(f"{where}: unknown foot key(s) {', '.join(unknown)}; expected {', '.join(sorted(allowed))}")
    if shape == "cuboid":
        return Foot.cuboid(values["length"], values["width"])
    if shape == "disc":
        return Foot.disc(values["diameter"])
    return Foot(area=values["area"], width=values["width"], shape="custom")


def foot_to_json(foot: Foot) -> dict[str, Any]:
    """The manifest's ``foot`` object for a :class:`Foot` (a cuboid or disc if it is one, else custom)."""
    if foot.shape.startswith("cuboid"):
        return {"shape": "cuboid", "length_m": foot.area / foot.width, "width_m": foot.width}
    if foot.shape.startswith("disc"):
        return {"shape": "disc", "diameter_m": foot.width}
    return {"shape": "custom", "area_m2": foot.area, "width_m": foot.width}


# ---------------------------------------------------------------------------- loading
def _samples(count: int) -> str:
    """``"1 sample"``, ``"5 samples"``: a count of samples as a message says it."""
    return f"{count} sample" + ("" if count == 1 else "s")


def _check_trial_arrays(where: str, time: np.ndarray, column: str, lines: np.ndarray) -> None:
    if time.size < MIN_SAMPLES:
        raise InputError(f"{where}: only {_samples(time.size)}; a trial needs at least {MIN_SAMPLES}")
    check_time(where, time, column, lines=lines)


def load_trial(path: str | os.PathLike[str], water_content: float = math.nan, *,
               velocity: float | None = None, repeat: int | None = None) -> Trial:
    """Read one trial CSV with the columns ``time_s, depth_m, force_N`` (``depth_mm``, ``time_ms`` accepted).

    Parameters
    ----------
    path : path-like
        The CSV file.
    water_content : float
        Its water content [-] if known (NaN otherwise, e.g. for identification).
    velocity : float, optional
        Nominal speed [m/s].
    repeat : int, optional
        Repeat number.
    """
    matched: dict[str, str] = {}
    cols = read_columns(path, _TRIAL_COLUMNS, matched=matched)
    _check_trial_arrays(str(path), cols["time"], matched["time"], cols["line"])
    # water_content as given: Trial checks it (float() parsed "0.25" and b"0.25", and raised TypeError on a list)
    return Trial(Path(path).name, water_content, cols["time"], cols["depth"], cols["force"], velocity, repeat)


def _number(value: Any, where: str, what: str, lo: float, hi: float, example: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not lo < value < hi:
        raise InputError(f"{where}: {what} is {value!r}; expected a number in ({lo:g}, {hi:g}), e.g. {example}")
    return float(value)


def _load_manifest(path: Path) -> Dataset:
    where = str(path)
    data = load_json(path, "manifest", '{"foot": {...}, "trials": [...]}')
    if not isinstance(data, dict):
        raise InputError(f'{where}: expected a JSON object with "foot" and "trials", got {type(data).__name__}')
    unknown = sorted(set(data) - set(_TOP_KEYS))
    if unknown:
        raise InputError(f"{where}: unknown key(s) {', '.join(unknown)}; expected {', '.join(_TOP_KEYS)}")
    if "foot" not in data:
        raise InputError(f'{where}: missing "foot", e.g. {{"shape": "cuboid", "length_m": 0.051, "width_m": 0.038}}')
    foot = foot_from_json(data["foot"], where)
    entries = data.get("trials")
    if not isinstance(entries, list) or not entries:
        raise InputError(f'{where}: "trials" must be a non-empty list of {{"file": ..., "water_content": ...}}')
    trials: list[Trial] = []
    seen: set[str] = set()
    files: dict[tuple[int, int], str] = {}  # each trial file's (device, inode): its name in the manifest
    for i, entry in enumerate(entries):
        at = f"{where}: trials[{i}]"
        if not isinstance(entry, dict):
            raise InputError(f'{at} must be an object like {{"file": "w25_v10_r1.csv", "water_content": 0.25}}')
        bad = sorted(set(entry) - set(_TRIAL_KEYS))
        if bad:
            raise InputError(f"{at}: unknown key(s) {', '.join(bad)}; expected {', '.join(_TRIAL_KEYS)}")
        name = entry.get("file")
        if not isinstance(name, str) or not name.strip():
            raise InputError(f'{at}: "file" must be a CSV file name, got {name!r}')
        file = _inside_folder(path.parent, name, at)
        if str(file) in seen:
            raise InputError(f"{at}: file {name!r} is listed twice")
        seen.add(str(file))
        if "water_content" not in entry:
            raise InputError(f'{at}: missing "water_content" (a fraction, e.g. 0.25 for 25%)')
        w = _number(entry["water_content"], at, "water_content", 0.0, 1.0, "0.25 for 25%")
        velocity = None
        if entry.get("velocity_m_s") is not None:
            velocity = _number(entry["velocity_m_s"], at, "velocity_m_s", 0.0, math.inf, "0.01 for 10 mm/s")
        repeat = entry.get("repeat")
        if repeat is not None and (not is_integer(repeat) or not 0 <= repeat <= MAX_REPEATS):
            raise InputError(f"{at}: repeat is {shown(repeat)}; expected an integer in [0, {MAX_REPEATS}]")
        if not file.is_file():
            raise InputError(f"{at}: trial file {path.parent / name} not found")
        # one file under two names (a link, hard or symbolic) would count its trial twice in every fit
        stat = file.stat()
        same = files.get((stat.st_dev, stat.st_ino))
        if same is not None:
            raise InputError(f"{at}: file {name!r} is {same!r} under another name, listed twice; expected each trial "
                             "once")
        files[(stat.st_dev, stat.st_ino)] = name
        trials.append(load_trial(file, w, velocity=velocity, repeat=repeat))
    extra = {k: data[k] for k in _EXTRA_KEYS if k in data}
    inputs = (str(path.parent), where, *sorted(seen))
    return Dataset(foot=foot, trials=tuple(trials), source=where, extra=extra or None, inputs=inputs)


def _inside_folder(folder: Path, name: str, at: str) -> Path:
    """The trial file ``name`` of a manifest in ``folder``; refused unless it lies inside that folder.

    An absolute path, ``..`` or a link leading out of the folder is refused,
    so a manifest cannot make a command read (and echo in its messages)
    files elsewhere.
    """
    relative = Path(name)
    if relative.is_absolute() or name.startswith(("/", "\\")) or ".." in relative.parts or "\x00" in name:
        raise InputError(f'{at}: "file" must be a name relative to the dataset folder, without "..", '
                         f"got {name[:80]!r}")
    file = folder / relative
    root = Path(os.path.realpath(folder))
    real = Path(os.path.realpath(file))
    if root not in real.parents:
        raise InputError(f"{at}: trial file {name[:80]!r} leads outside the dataset folder; "
                         "expected a file inside it")
    return file


def _load_tidy(path: Path, foot: Foot) -> Dataset:
    where = str(path)
    matched: dict[str, str] = {}
    cols = read_columns(path, {**_TRIAL_COLUMNS, "water_content": (("water_content", 1.0),)}, keep_text=("trial",),
                        matched=matched)
    line = cols["line"]  # each data row's line number in the file
    if "trial" not in cols:
        raise InputError(f"{where}: missing column trial; expected trial,water_content,time_s,depth_m,force_N")
    ids = cols["trial"]
    order: list[str] = []
    rows: dict[str, list[int]] = {}
    for r, tid in enumerate(ids):
        if not tid:
            raise InputError(f"{where}: row {line[r]}, column trial: empty trial id")
        if tid not in rows:
            order.append(tid)
            rows[tid] = []
        elif rows[tid][-1] != r - 1:
            raise InputError(f"{where}: row {line[r]}, column trial: trial {tid!r} resumes after another trial; "
                             "expected each trial's rows together")
        rows[tid].append(r)
    trials = []
    for tid in order:
        idx = np.array(rows[tid])
        w_values = cols["water_content"][idx]
        if not np.all(w_values == w_values[0]):
            r = int(line[idx[np.flatnonzero(w_values != w_values[0])[0]]])
            raise InputError(f"{where}: row {r}, column water_content: trial {tid!r} changes water content")
        w = float(w_values[0])
        if not 0.0 < w < 1.0:
            raise InputError(f"{where}: row {line[idx[0]]}, column water_content: {w:g} is not a fraction "
                             "in (0, 1); expected e.g. 0.25 for 25%")
        t = cols["time"][idx]
        _check_trial_arrays(f"{where} (trial {tid!r})", t, matched["time"], line[idx])
        trials.append(Trial(tid, w, t, cols["depth"][idx], cols["force"][idx]))
    return Dataset(foot=foot, trials=tuple(trials), source=where, inputs=(where,))


def load_dataset(path: str | os.PathLike[str], *, foot: Foot | None = None) -> Dataset:
    """Load and validate a dataset.

    Parameters
    ----------
    path : path-like
        A dataset folder (holding ``dataset.json``), the ``dataset.json``
        itself, or a tidy CSV with the columns
        ``trial, water_content, time_s, depth_m, force_N``.
    foot : Foot, optional
        The foot for a tidy CSV (which cannot name one); the paper's
        51 x 38 mm cuboid by default. Refused with a manifest, which names its own.

    Raises
    ------
    InputError
        One line naming the file, row, column or key, the value, and what is expected.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"path must be a dataset folder or file name, got {type(path).__name__}")
    p = check_input_name(path, f"a dataset folder, its {MANIFEST_NAME}, or a tidy CSV")
    try:
        found, folder = p.exists(), p.is_dir()
    except OSError as exc:  # a name too long for the file system: is_dir() raised it, and mudforce fit exited 1
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    if folder:
        manifest = p / MANIFEST_NAME
        if not manifest.is_file():
            raise InputError(f"{p}: no {MANIFEST_NAME} in this folder; expected a dataset folder or a tidy CSV")
        p = manifest
    elif not found:
        raise InputError(f"{p}: not found; expected a dataset folder, its {MANIFEST_NAME}, or a tidy CSV")
    if p.suffix.lower() == ".json":
        if foot is not None:
            raise InputError(f"{p}: the manifest names its own foot; do not pass --foot with it")
        return _load_manifest(p)
    return _load_tidy(p, Foot.paper() if foot is None else foot)


# ---------------------------------------------------------------------------- writing
def _trial_csv(trial: Trial) -> str:
    lines = ["time_s,depth_m,force_N"]
    lines += [f"{t:.10g},{z:.9g},{f:.9g}" for t, z, f in zip(trial.time, trial.depth, trial.force, strict=True)]
    return "\n".join(lines) + "\n"


#: Significant digits of the time column that :func:`_trial_csv` writes (its ``.10g``).
_TIME_DIGITS = 10


def _check_readable(trial: Trial) -> None:
    """Refuse a trial that :func:`load_trial` would refuse once written: too few samples, a value beyond
    :data:`mudforce.io.tables.COLUMN_LIMITS`, time that does not increase as written (10 significant digits)."""
    trial.check_bounds(made=True)
    where = f"trial {trial.name}"
    time = np.asarray(trial.time, dtype=np.float64)
    # written with 10 significant digits, two times stay distinct if they differ by more than 1e-9 of either
    close = np.diff(time) <= 10.0 ** (1 - _TIME_DIGITS) * np.maximum(np.abs(time[:-1]), np.abs(time[1:]))
    if np.any(close):
        i = int(np.argmax(close))
        raise InputError(f"{where}: the times {time[i]:.17g} s and {time[i + 1]:.17g} s would not increase as "
                         f"written ({_TIME_DIGITS} digits); expected steps of more than 1e-9 of the time")


def save_dataset(dataset: Dataset, directory: str | os.PathLike[str]) -> Path:
    """Write ``dataset`` as a folder: one CSV per trial, then ``dataset.json`` (each atomically).

    Returns the manifest's path. Trial names must be distinct file names ending in ``.csv``.
    Nothing is written unless every trial can be read back by :func:`load_dataset`
    (at least :data:`MIN_SAMPLES` samples, values within :data:`mudforce.io.tables.COLUMN_LIMITS`,
    times that increase as written): no file that ``mudforce fit`` cannot read.
    """
    if not isinstance(dataset, Dataset):  # a dict raised AttributeError (no 'trials')
        raise InputError(f"save_dataset takes a Dataset, got {type(dataset).__name__}")
    out = Path(directory)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder")
    names = [trial.name for trial in dataset.trials]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise InputError(f"two trials are named {twice[0]!r}; each trial needs its own file "
                         "(repeated water contents or velocities?)")
    for name in names:
        if Path(name).name != name or name == MANIFEST_NAME or not name.endswith(".csv"):
            raise InputError(f"trial name {name!r} must be a plain file name ending in .csv")
    for trial in dataset.trials:
        _check_readable(trial)
        if math.isnan(trial.water_content):  # the manifest's writer said "a result is not finite", after the CSVs
            raise InputError(f"trial {trial.name} has no water content (NaN), and dataset.json needs each trial's; "
                             "give it its water_content (e.g. 0.25)")
    entries: list[dict[str, Any]] = []
    for trial in dataset.trials:
        entry: dict[str, Any] = {"file": trial.name, "water_content": trial.water_content}
        if trial.velocity is not None:
            entry["velocity_m_s"] = trial.velocity
        if trial.repeat is not None:
            entry["repeat"] = trial.repeat
        entries.append(entry)
    manifest: dict[str, Any] = {"foot": foot_to_json(dataset.foot), "trials": entries}
    if dataset.extra:
        manifest.update(dataset.extra)
    text = dumps_json(manifest, indent=2) + "\n"  # before any file: an extra it cannot write left the CSVs alone
    out.mkdir(parents=True, exist_ok=True)
    for trial in dataset.trials:
        atomic_write_text(out / trial.name, _trial_csv(trial))
    path = out / MANIFEST_NAME
    atomic_write_text(path, text)
    return path

