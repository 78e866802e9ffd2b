"""Force models the calibration can fit, behind one small interface.

A :class:`ForceModel` is a function ``force(time, depth, values, foot) -> force``
(time [s], depth [m], the parameter vector in SI in ``parameter_names``
order, a :class:`~mudforce.model.foot.Foot`; force [N] per sample) plus what the
fitter needs to know about its parameters: bounds, which are fixed by
default, starting points, and the fit stages. Every parameter must be
positive: the fitter works on their logarithms.

:data:`CHEN2024` is the paper's model (the compiled stepper of
:func:`mudforce.simulate`, exact branch rule). The baselines of
:mod:`mudforce.model.baselines` are :data:`GRANULAR_RFT`, :data:`DRFT` and
:data:`MAXWELL_ONLY`. :data:`MODELS` lists every built-in model, here, in
one place; another model (a variant of your own) is added with
:func:`register_model`, and any is chosen with ``mudforce fit --model NAME``.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np

from mudforce import _kernel as K
from mudforce.errors import InputError, is_real, shown, true_or_false
from mudforce.estimation.calibration._recording_model import _vector_force_and_band
from mudforce.estimation.calibration.preprocess import PreparedTrial
from mudforce.model.baselines import DEFAULT_K_RFT, drft_force, granular_rft_force, maxwell_only_force
from mudforce.model.equations import array_form, relaxation_time
from mudforce.model.foot import Foot
from mudforce.model.parameters import PARAMETER_NAMES, PARAMETER_UNITS, TABLE_I, TABLE_I_WATER_CONTENTS, MudParameters
from mudforce.steppers.simulation import CompactRun, run_compact, simulate

__all__ = [
    "CHEN2024",
    "DRFT",
    "GRANULAR_RFT",
    "MAXWELL_ONLY",
    "MODELS",
    "FitStage",
    "ForceFunction",
    "ForceModel",
    "get_model",
    "register_model",
]

#: ``force(time [s], depth [m], values [SI], foot) -> force [N]``, one value per sample.
ForceFunction = Callable[[np.ndarray, np.ndarray, np.ndarray, Foot], np.ndarray]

#: Which samples a stage fits: up to the reversal (approach, intrusion, hold), after it, or all.
Window = Literal["intrusion", "withdrawal", "all"]


@dataclass(frozen=True)
class FitStage:
    """One stage of a staged fit.

    Attributes
    ----------
    name : str
        For progress and logs.
    parameters : tuple of str
        The parameters this stage adjusts (the fixed ones are skipped).
    window : {"intrusion", "withdrawal", "all"}
        The samples whose residuals it minimises.
    search : {"local", "global"}
        ``"local"``: multi-start bounded least squares; ``"global"``:
        seeded differential evolution, then least squares from its best point.
    """

    name: str
    parameters: tuple[str, ...]
    window: Window
    search: Literal["local", "global"] = "local"
    #: True when the stage's parameters do not change the force before its window
    #: (so a model with ``resume`` simulates the samples before the reversal once).
    prefix_fixed: bool = False

    def __post_init__(self) -> None:
        # a misspelt window was fitted on all samples, a misspelt search ran the local one, a str's letters were
        # read as parameter names (none of them a parameter: the stage fitted nothing), each without a word
        if not isinstance(self.parameters, (tuple, list)) or not all(isinstance(n, str) for n in self.parameters):
            raise InputError(f"stage {self.name}: parameters must be a tuple of parameter names, e.g. ('k_m_i', "
                             f"'beta'), got {shown(self.parameters)}")
        if self.window not in get_args(Window):
            raise InputError(f"stage {self.name}: window must be one of {', '.join(get_args(Window))}, got "
                             f"{shown(self.window)}")
        if self.search not in ("local", "global"):
            raise InputError(f"stage {self.name}: search must be local or global, got {shown(self.search)}")
        true_or_false(self.prefix_fixed, f"stage {self.name}: prefix_fixed")


@dataclass(frozen=True)
class ForceModel:
    """A model the calibration can fit.

    Attributes
    ----------
    name : str
        Its registry name (``--model NAME``).
    parameter_names : tuple of str
        The parameter vector's entries.
    force : ForceFunction
        ``force(time, depth, values, foot) -> force [N]``.
    bounds : mapping
        Name -> (low, high) [SI], both > 0; the fit stays inside.
    search_bounds : mapping
        Name -> (low, high) for the global search (a narrower box; defaults to ``bounds``).
    fixed : tuple of str
        Parameters held at their default unless the user frees them.
    defaults : mapping
        Name -> value [SI]: the fixed values and a fallback start.
    starts : tuple of mappings
        Candidate starting points (name -> value [SI]) for local stages.
    stages : tuple of FitStage
        The staged fit; a final joint stage over every free parameter always follows.
    diagnose : callable, optional
        ``diagnose(values, prepared_trials, foot) -> list of warnings``: model-specific
        identifiability checks (e.g. "no trial necked").
    units : mapping
        Name -> unit string, for reports.
    resume : callable, optional
        ``resume(time, depth, values, foot, k) -> tail``: simulate samples
        ``[:k]`` once and return ``tail(values) -> force[k:]`` [N] for values
        that differ only in parameters that do not act before sample ``k``
        (a speed-up for stages with ``prefix_fixed``).
    force_scale : tuple of str
        The parameters the force is jointly proportional to (``F(c p) = c F(p)`` when each of them is
        multiplied by ``c``): a force sensor whose gain is off by ``1 + g`` reads as all of them off by
        ``1 + g``, so the fit widens their standard errors by the gain's uncertainty.
    rest_band : callable, optional
        ``rest_band(time, depth, foot) -> band``, with ``band(values) -> (force, low, high)`` [N] along that
        trajectory: the model's force and, at each sample, the band ``[low, high]`` a foot at rest may carry (a
        stuck foot carries its load anywhere in it). With one, the fit reads the samples of a recording of any
        motion at which the foot is at rest through the band, not on the branch (issue 23: rest is a band); without
        one it reads every sample on the model's force.
    """

    name: str
    parameter_names: tuple[str, ...]
    force: ForceFunction
    bounds: Mapping[str, tuple[float, float]]
    defaults: Mapping[str, float]
    fixed: tuple[str, ...] = ()
    search_bounds: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    starts: tuple[Mapping[str, float], ...] = ()
    stages: tuple[FitStage, ...] = ()
    diagnose: Callable[[np.ndarray, Sequence[PreparedTrial], Foot], list[str]] | None = None
    units: Mapping[str, str] = field(default_factory=dict)
    resume: Callable[[np.ndarray, np.ndarray, np.ndarray, Foot, int], Callable[[np.ndarray], np.ndarray]] | None = None
    force_scale: tuple[str, ...] = ()
    rest_band: Callable[[np.ndarray, np.ndarray, Foot], Callable[[np.ndarray], tuple[np.ndarray, np.ndarray,
                                                                                    np.ndarray]]] | None = None

    def __post_init__(self) -> None:
        # a list raised TypeError (unhashable) at register_model, 3 was registered and then refused by get_model
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"a ForceModel's name must be a non-empty str (its --model NAME), got {shown(self.name)}")
        names = set(self.parameter_names)
        # a name twice was taken, and the fit's vector had two entries for one parameter
        repeated = sorted({n for n in self.parameter_names if self.parameter_names.count(n) > 1})
        if repeated:
            raise InputError(f"model {self.name}: parameter_names repeats {', '.join(repeated)}; expected each "
                             "name once")
        for what, keys in (("bounds", self.bounds), ("defaults", self.defaults)):
            missing = names - set(keys)
            if missing:
                raise InputError(f"model {self.name}: {what} lacks {', '.join(sorted(missing))}")
        for n in self.parameter_names:
            # a NaN default was taken: chen2024's lambda = NaN stopped the fit at scipy's ValueError (residuals not
            # finite), drft's rho_m = NaN at its force's check, each after the trials' preparation
            value = self.defaults[n]
            if not (is_real(value) and 0.0 < value <= sys.float_info.max):
                raise InputError(f"model {self.name}: default of {n} must be a number with 0 < value < inf (the fit "
                                 f"works on logarithms), got {shown(value)}")
        unknown_fixed = set(self.fixed) - names  # an unknown name (a typo) was ignored: the parameter was fitted
        if unknown_fixed:
            raise InputError(f"model {self.name}: fixed names {', '.join(sorted(unknown_fixed))}, not among its "
                             f"parameters {', '.join(self.parameter_names)}")
        for n, (lo, hi) in self.bounds.items():
            # finite: the global search refused inf (scipy's ValueError), 10**5000 overflowed the force to inf
            if not (is_real(lo) and is_real(hi) and 0.0 < lo < hi <= sys.float_info.max):
                raise InputError(f"model {self.name}: bounds of {n} must be numbers with 0 < low < high < inf, "
                                 f"got {shown(lo)}, {shown(hi)}")
        # an unknown name was ignored (the search ran over the whole bounds); a reversed box, or one beside the
        # bounds, was searched without a word, from points outside the bounds
        strays = [n for n in self.search_bounds if n not in names]
        if strays:
            raise InputError(f"model {self.name}: search_bounds names {', '.join(map(str, strays))}, not among its "
                             f"parameters {', '.join(self.parameter_names)}")
        for n, (lo, hi) in self.search_bounds.items():
            a, b = self.bounds[n]
            if not (is_real(lo) and is_real(hi) and lo < hi and lo < b and hi > a):
                raise InputError(f"model {self.name}: search_bounds of {n} must be numbers with low < high that "
                                 f"overlap its bounds ({a:g}, {b:g}), got {shown(lo)}, {shown(hi)}")
        # a start naming no parameter was ignored (the defaults started instead); a NaN value stopped the fit after
        # the trials' preparation (maxwell_only's force: k_m_i must be finite), a dict raised AttributeError there
        if not isinstance(self.starts, (tuple, list)) or not all(isinstance(x, Mapping) for x in self.starts):
            raise InputError(f"model {self.name}: starts must be a tuple of mappings of parameter names to values "
                             f"[SI], got {type(self.starts).__name__}")
        for k, start in enumerate(self.starts):
            for n, value in start.items():
                if n not in names:
                    raise InputError(f"model {self.name}: starts[{k}] names {shown(n)}, not among its parameters "
                                     f"{', '.join(self.parameter_names)}")
                if not (is_real(value) and 0.0 < value <= sys.float_info.max):
                    raise InputError(f"model {self.name}: starts[{k}] {n} must be a number with 0 < value < inf (the "
                                     f"fit works on logarithms), got {shown(value)}")
        for stage in self.stages:  # a name not among them (a typo) was skipped: the stage left it where it was
            strays = [n for n in stage.parameters if n not in names]
            if strays:
                raise InputError(f"model {self.name}: stage {stage.name} names {', '.join(strays)}, not among its "
                                 f"parameters {', '.join(self.parameter_names)}")
        unknown = set(self.force_scale) - names
        if unknown:
            raise InputError(f"model {self.name}: force_scale names {', '.join(sorted(unknown))}, "
                             f"not among its parameters {', '.join(self.parameter_names)}")

    def vector(self, values: Mapping[str, float]) -> np.ndarray:
        """The parameter vector [SI] from a name -> value mapping (missing names from ``defaults``)."""
        return np.array([float(values.get(n, self.defaults[n])) for n in self.parameter_names])


# ---------------------------------------------------------------------------- the paper's model
_CHEN_BOUNDS: dict[str, tuple[float, float]] = {
    "k_m_i": (1e3, 1e9),
    "b_m_i": (1e2, 1e9),
    "k_m_w": (1e3, 1e9),
    "b_m_w": (1e2, 1e9),
    "alpha": (1e0, 1e8),
    "beta": (1e-2, 1.0),
    "sigma_y": (1e0, 1e7),
    "zeta": (1e-3, 1e2),
    "omega_0": (1e-2, 1e3),
    "rho_m": (1e2, 2e4),
    "lambda": (1e-6, 1e2),
}
# a box around Table I's range, for the seeded global search of the withdrawal stage
_CHEN_SEARCH: dict[str, tuple[float, float]] = {
    "k_m_w": (1e5, 2e7),
    "b_m_w": (1e5, 2e7),
    "sigma_y": (1e2, 1e5),
    "zeta": (0.05, 5.0),
    "omega_0": (0.2, 30.0),
}


#: the last parameter vector's stepper constants: ``(values' bytes, foot, row)`` (see :func:`_chen_row`)
_LAST_ROW: tuple[bytes, Foot | None, np.ndarray] = (b"", None, np.empty((1, K.N_PARAMS)))


def _chen_row(values: np.ndarray, foot: Foot) -> np.ndarray:
    """The stepper's constants for ``values`` [SI] on ``foot`` with the exact rule, shape ``(1, N_PARAMS)``.

    Speed plumbing: a fit evaluates every trial of a condition with one
    parameter vector, and its standard errors the same vector many times;
    the row of the last vector is kept (``make_params`` of the same numbers
    gives the same row) and handed out again, never written. The memo is
    one tuple, swapped whole, so that threads can share it.
    """
    global _LAST_ROW
    key = np.ascontiguousarray(values, dtype=np.float64).tobytes()
    last = _LAST_ROW
    if last[1] is foot and last[0] == key:
        return last[2]
    row = K.make_params(values, foot.area, foot.width, 1, 0.0)[None, :]
    _LAST_ROW = (key, foot, row)
    return row


def _chen_force(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    """The paper's force [N] with the exact branch rule.

    What :func:`mudforce.simulate` computes, calling the compiled stepper
    directly: the fit evaluates this tens of thousands of times on inputs
    already validated, and only needs the force.
    """
    bad, force, *_ = run_compact(time, depth, _chen_row(values, foot), 1)
    if bad >= 0:  # numerically impossible parameters: a huge, finite residual
        force[bad:] = 1e6
    return force


def _chen_on(time: np.ndarray, depth: np.ndarray, foot: Foot) -> Callable[[np.ndarray], np.ndarray]:
    """``values -> _chen_force(time, depth, values, foot)`` [N], on work arrays made once (:func:`trajectory_force`).

    Speed plumbing: the array returned is the work's own, overwritten by the next call.
    """
    work = CompactRun(time, depth, 1)

    def force(values: np.ndarray) -> np.ndarray:
        bad = work.run(_chen_row(values, foot))
        if bad >= 0:  # as _chen_force
            work.force[bad:] = 1e6
        return work.force

    return force


def _chen_resume(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot,
                 first: int) -> Callable[[np.ndarray], np.ndarray]:
    """Simulate samples ``[:first]`` once; the tail after it for withdrawal-only parameter changes."""
    row = K.make_params(values, foot.area, foot.width, 1, 0.0)[None, :]
    head = K.new_out(first)
    snapshot = K.new_states(1)
    ring = K.new_ring(1, 1)  # the exact velocity rule keeps no history
    K.run_batch(time[:first], depth[:first], snapshot, ring, row, head)
    K.forget_cache(snapshot)  # cached decays belong to the old parameters
    out = K.new_out(time.size - first)

    def tail(new_values: np.ndarray) -> np.ndarray:
        states = snapshot.copy()
        prow = _chen_row(new_values, foot)
        bad = K.run_batch(time, depth, states, ring, prow, out, first)
        force: np.ndarray = K.outputs(out).force.copy()
        # from the first sample refused or with a NaN force on: a huge, finite residual
        end = bad - first if bad >= 0 else force.size
        nan = np.flatnonzero(np.isnan(force[:end]))
        force[int(nan[0]) if nan.size else end:] = 1e6
        return force

    return tail


def _chen_rest_band(time: np.ndarray, depth: np.ndarray,
                    foot: Foot) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``values -> (force, low, high)`` [N] along one trajectory: the paper's force (exact rule, the same bits as
    :func:`_chen_force`) and the rest band about it at each sample, as identify reads a foot at rest
    (Eqs. (2)-(3)'s edges at the stepper's own Maxwell strain, widened to hold the force)."""
    t = np.ascontiguousarray(time, dtype=np.float64)
    z = np.ascontiguousarray(depth, dtype=np.float64)

    def band(values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return _vector_force_and_band(t, z, values, foot, 0.0)

    return band


def _chen_diagnose(values: np.ndarray, trials: Sequence[PreparedTrial], foot: Foot) -> list[str]:
    params = MudParameters.from_dict(dict(zip(PARAMETER_NAMES, map(float, values), strict=True)))
    necks: list[float] = []
    suction = 0.0
    for tr in trials:
        res = simulate(tr.time, tr.depth, params, foot, velocity_filter="exact")
        suction = min(suction, res.min_force)
        if res.necking_times.size:
            necks.append(float(res.necking_times[0]) - tr.reversal_time)
    warnings = []
    if not necks:
        warnings.append(
            "no trial necked (the suction never reached sigma_y): sigma_y is only known to exceed "
            f"{-suction / foot.area:.4g} Pa, and zeta, omega_0 are not determined by this data")
    else:
        tau_w = array_form(relaxation_time)(params.k_m_w, params.b_m_w)
        if max(necks) < 0.3 * tau_w:
            warnings.append(
                f"necking comes {max(necks):.3g} s after the reversal, before the withdrawal relaxation time "
                f"b_m_w/k_m_w = {tau_w:.3g} s: the suction curve has not bent, so b_m_w is weakly determined")
    return warnings


_TABLE_STARTS = tuple(p.to_dict() for p in TABLE_I.values())

#: The paper's model, Eqs. (1)-(9), fitted in three stages as its Section III-A suggests.
CHEN2024 = ForceModel(
    name="chen2024",
    parameter_names=PARAMETER_NAMES,
    force=_chen_force,
    bounds=_CHEN_BOUNDS,
    search_bounds=_CHEN_SEARCH,
    defaults=TABLE_I[0.25].to_dict(),
    fixed=("rho_m", "lambda"),
    starts=_TABLE_STARTS,
    stages=(
        FitStage("intrusion and hold", ("k_m_i", "b_m_i", "alpha", "beta"), "intrusion", "local"),
        # k_m_w ... omega_0 act only in the withdrawal branch and after necking
        FitStage("withdrawal", ("k_m_w", "b_m_w", "sigma_y", "zeta", "omega_0"), "withdrawal", "global",
                 prefix_fixed=True),
    ),
    diagnose=_chen_diagnose,
    resume=_chen_resume,
    units=PARAMETER_UNITS,
    # every stress of Eqs. (1)-(9) is linear in these jointly (the necking test compares two of them)
    force_scale=("k_m_i", "b_m_i", "k_m_w", "b_m_w", "alpha", "sigma_y", "rho_m"),
    rest_band=_chen_rest_band,
)

# ---------------------------------------------------------------------------- the baselines
_RHO_M = TABLE_I[0.25].rho_m  # [kg/m^3]
_LAMBDA = TABLE_I[0.25].lambda_  # [-]
_K_STARTS = (1e5, 1e6, 1e7)


def _rft_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    return granular_rft_force(time, depth, float(values[0]), foot)


def _drft_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    return drft_force(time, depth, float(values[0]), float(values[1]), float(values[2]), foot)


def _maxwell_fit(time: np.ndarray, depth: np.ndarray, values: np.ndarray, foot: Foot) -> np.ndarray:
    k_i, b_i, k_w, b_w, rho, lam = (float(x) for x in values)
    return maxwell_only_force(time, depth, k_i, b_i, k_w, b_w, rho, lam, foot)


#: Granular RFT (Li, Zhang & Goldman 2013) as a fittable model; parameter ``k_rft`` [Pa/m].
GRANULAR_RFT = ForceModel(
    name="granular_rft",
    parameter_names=("k_rft",),
    force=_rft_fit,
    bounds={"k_rft": (1e2, 1e10)},
    defaults={"k_rft": DEFAULT_K_RFT},
    starts=tuple({"k_rft": k} for k in _K_STARTS),
    units={"k_rft": "Pa/m"},
)

#: Dynamic RFT as a fittable model; parameters ``k_rft`` [Pa/m], ``lambda`` [-], ``rho_m`` [kg/m^3] (fixed).
DRFT = ForceModel(
    name="drft",
    parameter_names=("k_rft", "lambda", "rho_m"),
    force=_drft_fit,
    bounds={"k_rft": (1e2, 1e10), "lambda": (1e-6, 1e4), "rho_m": (1e2, 2e4)},
    defaults={"k_rft": DEFAULT_K_RFT, "lambda": _LAMBDA, "rho_m": _RHO_M},
    fixed=("rho_m",),
    starts=tuple({"k_rft": k, "lambda": lam} for k in _K_STARTS for lam in (_LAMBDA, 10.0)),
    units={"k_rft": "Pa/m", "lambda": "-", "rho_m": "kg/m^3"},
)

_MAXWELL_ROWS: tuple[Mapping[str, float], ...] = tuple(
    {n: TABLE_I[w].to_dict()[n] for n in ("k_m_i", "b_m_i", "k_m_w", "b_m_w")} for w in TABLE_I_WATER_CONTENTS
)

#: The Maxwell-only ablation as a fittable model; ``k_m_i, b_m_i, k_m_w, b_m_w`` (+ fixed ``rho_m``, ``lambda``).
MAXWELL_ONLY = ForceModel(
    name="maxwell_only",
    parameter_names=("k_m_i", "b_m_i", "k_m_w", "b_m_w", "rho_m", "lambda"),
    force=_maxwell_fit,
    bounds={"k_m_i": (1e3, 1e9), "b_m_i": (1e2, 1e9), "k_m_w": (1e3, 1e9), "b_m_w": (1e2, 1e9),
            "rho_m": (1e2, 2e4), "lambda": (1e-6, 1e2)},
    defaults={**_MAXWELL_ROWS[2], "rho_m": _RHO_M, "lambda": _LAMBDA},
    fixed=("rho_m", "lambda"),
    starts=_MAXWELL_ROWS,
    stages=(
        FitStage("intrusion and hold", ("k_m_i", "b_m_i"), "intrusion", "local"),
        FitStage("withdrawal", ("k_m_w", "b_m_w"), "withdrawal", "local"),
    ),
    units={"k_m_i": "Pa/m", "b_m_i": "Pa s/m", "k_m_w": "Pa/m", "b_m_w": "Pa s/m", "rho_m": "kg/m^3",
           "lambda": "-"},
)

#: Every built-in model by name: the paper's, then the baselines; :func:`register_model` adds more.
MODELS: dict[str, ForceModel] = {m.name: m for m in (CHEN2024, GRANULAR_RFT, DRFT, MAXWELL_ONLY)}


_BUILT_IN = dict(MODELS)  # what register_model may not replace


def register_model(model: ForceModel) -> None:
    """Make ``model`` available to :func:`get_model` and ``--model NAME``.

    A built-in model's name (``chen2024``, ``granular_rft``, ``drft``,
    ``maxwell_only``) is refused: replacing it would change what every
    later fit, report and reproduction of that name means, without a word
    (give the variant a name of its own). A name you registered may be
    registered again, and the new model replaces yours: that is how a
    variant is revised in a running session (a notebook's cell run twice),
    and the name was yours to give.
    """
    if not isinstance(model, ForceModel):  # a name or None raised AttributeError ('str' object has no attribute)
        raise InputError(f"register_model takes a ForceModel, got {type(model).__name__}")
    if model.name in _BUILT_IN and model is not _BUILT_IN[model.name]:  # it silently replaced the built-in
        raise InputError(f"register_model: {model.name!r} is a built-in model's name; give your model another name "
                         f"(not {', '.join(sorted(_BUILT_IN))})")
    MODELS[model.name] = model


def get_model(model: str | ForceModel) -> ForceModel:
    """A model by name (one of :data:`MODELS`), or the model itself."""
    if isinstance(model, ForceModel):
        return model
    if not isinstance(model, str):  # a list or dict raised TypeError (unhashable type)
        raise InputError(f"model must be a model name or a ForceModel, got {type(model).__name__}; known models: "
                         f"{', '.join(sorted(MODELS))}")
    try:
        return MODELS[model]
    except KeyError:
        raise InputError(f"unknown model {model!r}; known models: {', '.join(sorted(MODELS))}") from None


def trajectory_force(model: ForceModel, foot: Foot, time: np.ndarray,
                     depth: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """``values -> model.force(time, depth, values, foot)`` [N] along one trajectory, for a fit's many evaluations.

    Speed plumbing: the paper's model runs on work arrays made once per
    trajectory (:func:`_chen_on`), the same numbers bit for bit; the
    array it returns is overwritten by the next call, so the caller uses
    it before calling again. Any other model's force is called as it is.
    """
    if model.force is _chen_force:
        return _chen_on(time, depth, foot)
    return lambda values: model.force(time, depth, values, foot)
