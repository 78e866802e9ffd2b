"""Synthetic intrusion datasets from the model, with realistic sensor imperfections.

Each trial is the paper's protocol (intrude to a depth, hold, withdraw at
the same speed until clear of the mud, Section II-A of [1]) preceded by an
approach from above the surface, simulated exactly, then measured with:
white force noise [N], white depth noise [m] (motion capture), and a
constant force-sensor bias [N]. The true parameters travel in the
manifest's ``synthetic`` entry so that a fit can be checked against them.

.. [1] X. Chen, J. Yi, J. Shan, arXiv:2403.02617 (2024).
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from mudforce.errors import InputError, finite_number, is_integer, positive_int, seed_int, shown
from mudforce.estimation.calibration.dataset import MAX_REPEATS, Dataset, Trial, save_dataset
from mudforce.model.foot import Foot
from mudforce.model.parameters import MudParameters
from mudforce.motions.protocol import Protocol
from mudforce.motions.sensor_chain import SensorChain
from mudforce.motions.sensor_chain import apply as apply_chain
from mudforce.steppers.simulation import simulate

__all__ = ["DEFAULT_VELOCITIES", "DEFAULT_WATER_CONTENTS", "FINE_RATE", "MAX_FINE_SAMPLES", "MAX_REPEATS",
           "START_BELOW", "repeat_count", "synthesize", "synthesize_gait", "trial_name"]

#: How ``synthesize_gait`` chooses where each walk starts: above the surface, in the mud, or every other one.
START_BELOW = ("never", "always", "alternate")

#: Water contents [-] that ``mudforce synth`` makes by default.
DEFAULT_WATER_CONTENTS: tuple[float, ...] = (0.25,)
#: Speeds [m/s] that ``mudforce synth`` makes by default.
DEFAULT_VELOCITIES: tuple[float, ...] = (0.01, 0.02, 0.04)
#: With a sensor chain, the rate [Hz] at which the model is simulated along the true path before the
#: chain samples it (or the sample rate, if higher).
FINE_RATE = 2000.0
#: Most samples of the fine simulations of one dataset with a sensor chain, all trials together [-].
MAX_FINE_SAMPLES = 20_000_000


def _check_chain(chain: SensorChain | None, rate: float, seconds: float) -> None:
    """Refuse a chain that sets what the synthesizer's own arguments set, or fine simulations too long."""
    if chain is None:
        return
    if not isinstance(chain, SensorChain):
        raise InputError(f"chain must be a SensorChain or None, got {type(chain).__name__}")
    if chain.depth_noise or chain.force_noise or chain.force_bias or chain.rate is not None:
        raise InputError("chain: give its depth_noise, force_noise, force_bias and rate as 0 and None; the "
                         "synthesizer's depth_noise, force_noise, bias and rate arguments set them")
    fine = max(FINE_RATE, rate)
    if seconds * fine > MAX_FINE_SAMPLES:
        raise InputError(f"with a sensor chain the model is simulated at {fine:g} Hz: {seconds * fine:.3g} samples "
                         f"in all, more than {MAX_FINE_SAMPLES:,}; shorten the trials or make fewer")


def _through_chain(chain: SensorChain, time: np.ndarray, depth: np.ndarray, force: np.ndarray, *, rate: float,
                   force_noise: float, depth_noise: float, bias: float,
                   seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The clean fine recording through ``chain`` with the synthesizer's noise, bias and rate."""
    full = replace(chain, force_noise=force_noise, depth_noise=depth_noise, force_bias=bias,
                   rate=None if rate >= FINE_RATE else rate)
    return apply_chain(time, depth, force, full, seed)


def _chain_entry(chain: SensorChain) -> dict[str, Any]:
    """The manifest's record of a chain (the corruptions beyond noise and bias, and the fine rate)."""
    entry = {k: v for k, v in chain.to_dict().items()
             if k not in ("depth_noise_m", "force_noise_N", "force_bias_N", "rate_Hz")}
    entry["fine_rate_Hz"] = FINE_RATE
    return entry


def repeat_count(repeats: Any) -> int:
    """``repeats`` as an int in [1, :data:`MAX_REPEATS`], else InputError (the synthetic datasets' and the report's
    count of trials per water content and speed)."""
    if positive_int(repeats, "repeats") > MAX_REPEATS:
        raise InputError(f"repeats must be at most {MAX_REPEATS} (trials per water content and speed), got "
                         f"{shown(repeats)}")
    return int(repeats)


def trial_name(water_content: float, velocity: float, repeat: int) -> str:
    """The file name of a synthetic trial, e.g. ``w25_v10_r1.csv`` (W in %, v in mm/s)."""
    stem = f"w{water_content * 100:g}_v{velocity * 1e3:g}_r{repeat}"
    return stem.replace(".", "p") + ".csv"


def synthesize(
    out: str | os.PathLike[str] | None = None,
    *,
    water_contents: Sequence[float] = DEFAULT_WATER_CONTENTS,
    velocities: Sequence[float] = DEFAULT_VELOCITIES,
    repeats: int = 3,
    force_noise: float = 0.2,
    depth_noise: float = 3e-5,
    bias: float = 0.5,
    seed: int = 0,
    foot: Foot | None = None,
    depth: float = 0.02,
    hold: float = 6.0,
    approach: float = 0.005,
    rise: float = 0.02,
    rate: float = 100.0,
    parameters: dict[float, MudParameters] | None = None,
    chain: SensorChain | None = None,
) -> Dataset:
    """Make (and optionally write) a synthetic dataset.

    Parameters
    ----------
    out : path-like, optional
        Folder to write ``dataset.json`` and the trial CSVs into.
    water_contents : sequence of float
        Volume fractions [-]; parameters from :meth:`MudParameters.from_water_content`
        (Table I, interpolated) unless ``parameters`` gives them.
    velocities : sequence of float
        Intrusion and withdrawal speeds [m/s].
    repeats : int
        Trials per (water content, speed).
    force_noise : float
        Standard deviation of white force noise [N].
    depth_noise : float
        Standard deviation of white depth noise [m].
    bias : float
        Constant force-sensor offset added to every sample [N].
    seed : int
        Seed of the noise, within [0, 2**32 - 1]; the same seed gives the same files.
    foot : Foot, optional
        The intruder; the paper's 51 x 38 mm cuboid by default.
    depth, hold, approach, rise : float
        Protocol: hold depth [m], hold time [s], start height above the
        surface [m], final height above the surface [m].
    rate : float
        Sampling rate [Hz].
    parameters : dict, optional
        Water content [-] -> :class:`MudParameters`, overriding Table I.
    chain : SensorChain, optional
        A robot's sensor corruptions (:mod:`mudforce.motions.sensor_chain`: depth
        offset, drift, force delay and low-pass, gain) with its noise, bias
        and rate left at 0 and None (the arguments above set them). The
        model is then simulated along the true path at :data:`FINE_RATE`
        and the chain samples it at ``rate``; each trial's chain is seeded
        from ``seed``. Recorded under ``"sensor_chain"`` in the manifest.

    Returns
    -------
    Dataset
        With the true parameters under ``extra["synthetic"]``.
    """
    repeats = repeat_count(repeats)
    seed = seed_int(seed, "seed")
    for name, values in (("water_contents", water_contents), ("velocities", velocities)):
        if len(set(values)) != len(list(values)):
            raise InputError(f"{name} repeats a value; give each once (each makes its own trials)")
    # checked, not converted (the manifest records them as given): np.isfinite raised TypeError on a string or an
    # int beyond float64, and a bool was taken as 0 or 1
    finite_number(force_noise, "force noise", "N", nonnegative=True)
    finite_number(depth_noise, "depth noise", "m", nonnegative=True)
    finite_number(bias, "bias", "N")
    if not water_contents or not velocities:
        raise InputError("synthesize needs at least one water content and one velocity")
    foot = Foot.paper() if foot is None else foot
    fine_rate = rate if chain is None else max(FINE_RATE, rate)
    if chain is not None:
        _check_chain(chain, rate, repeats * len(water_contents) * sum(
            Protocol.paper(depth=depth, velocity=v, hold=hold, rise=rise, rate=rate, approach=approach).duration
            for v in velocities))
    rng = np.random.default_rng(seed)
    truths: dict[str, Any] = {}
    trials: list[Trial] = []
    for w in water_contents:
        params = (parameters or {}).get(w) or MudParameters.from_water_content(w)
        truths[f"{w:g}"] = params.to_dict()
        for v in velocities:
            protocol = Protocol.paper(depth=depth, velocity=v, hold=hold, rise=rise, rate=fine_rate,
                                      approach=approach)
            time, z = protocol.sample()
            clean = simulate(time, z, params, foot, velocity_filter="exact").force
            for r in range(1, repeats + 1):
                if chain is None:
                    t, force = time, clean + bias + force_noise * rng.standard_normal(time.size)
                    measured = z + depth_noise * rng.standard_normal(time.size)
                else:
                    t, measured, force = _through_chain(chain, time, z, clean, rate=rate, force_noise=force_noise,
                                                        depth_noise=depth_noise, bias=bias,
                                                        seed=int(rng.integers(0, 2**32 - 1)))
                trials.append(Trial(trial_name(w, v, r), float(w), t, measured, force, float(v), r))
    synthetic = {
        "seed": seed,
        "force_noise_N": force_noise,
        "depth_noise_m": depth_noise,
        "bias_N": bias,
        "protocol": {"depth_m": depth, "hold_s": hold, "approach_m": approach, "rise_m": rise, "rate_Hz": rate},
        "parameters": truths,
    }
    if chain is not None:
        synthetic["sensor_chain"] = _chain_entry(chain)
    dataset = Dataset(foot=foot, trials=tuple(trials), source="synthesize()", extra={"synthetic": synthetic})
    if out is not None:
        path = save_dataset(dataset, out)
        dataset = Dataset(foot=foot, trials=dataset.trials, source=str(path), extra=dataset.extra)
    return dataset


def synthesize_gait(
    out: str | os.PathLike[str] | None = None,
    *,
    water_contents: Sequence[float] = DEFAULT_WATER_CONTENTS,
    repeats: int = 3,
    duration: float = 25.0,
    rate: float = 100.0,
    jitter: float = 0.0,
    start_below: str = "never",
    force_noise: float = 0.2,
    depth_noise: float = 3e-5,
    bias: float = 0.5,
    seed: int = 0,
    foot: Foot | None = None,
    chain: SensorChain | None = None,
) -> Dataset:
    """Make (and optionally write) a dataset of robot-like foot motions: one walk per trial.

    Each trial is :func:`mudforce.motions.gait.walk` with its own seed (drawn from
    ``seed``): several steps, each a touchdown at some speed to some depth,
    a stance with sway, sometimes a partial withdrawal and a re-push, and a
    lift-off. The manifest has no ``velocity_m_s`` (there is no one speed).

    Parameters
    ----------
    out : path-like, optional
        Folder to write ``dataset.json`` and the trial CSVs into.
    water_contents : sequence of float
        Volume fractions [-] (Table I, interpolated), within 15% to 35%.
    repeats : int
        Walks per water content.
    duration : float
        Length of each walk [s].
    rate : float
        Mean sampling rate [Hz].
    jitter : float
        Time-stamp jitter as a fraction of the sample period [-], within [0, 0.4].
    start_below : {"never", "always", "alternate"}
        Which walks start in stance, below the surface (their bias cannot be tared).
    force_noise, depth_noise, bias : float
        White force noise [N], white depth noise [m], constant force offset [N].
    seed : int
        Seed of the gaits and the noise; the same seed gives the same files.
    foot : Foot, optional
        The foot; the paper's 51 x 38 mm cuboid by default.
    chain : SensorChain, optional
        As for :func:`synthesize`: each walk's gait is simulated at
        :data:`FINE_RATE` and the chain (seeded with the walk's seed)
        samples it at ``rate``; not with ``jitter`` (the chain samples on a
        regular clock).

    Returns
    -------
    Dataset
        With the true parameters under ``extra["synthetic"]``.
    """
    from mudforce.motions.gait import gait, walk

    repeats = repeat_count(repeats)
    if start_below not in START_BELOW:
        raise InputError(f"start_below must be one of {', '.join(START_BELOW)}, got {start_below!r}")
    if not water_contents:
        raise InputError("synthesize_gait needs at least one water content")
    if not is_integer(seed) or seed < 0:
        raise InputError(f"seed must be an integer >= 0, got {shown(seed)}")
    foot = Foot.paper() if foot is None else foot
    if chain is not None:
        if jitter:
            raise InputError("jitter cannot go with a sensor chain (the chain samples on a regular clock); "
                             "expected jitter 0")
        _check_chain(chain, rate, repeats * len(water_contents) * duration)
    truths: dict[str, Any] = {}
    trials: list[Trial] = []
    seeds = np.random.default_rng(seed).integers(0, 2**31 - 1, size=(len(water_contents), repeats))
    for i, w in enumerate(water_contents):
        truths[f"{w:g}"] = MudParameters.from_water_content(w).to_dict()
        for r in range(1, repeats + 1):
            below = start_below == "always" or (start_below == "alternate" and r % 2 == 0)
            name = (f"w{w * 100:g}_gait_r{r}").replace(".", "p") + ".csv"
            if chain is None:
                path = walk(float(w), seed=int(seeds[i, r - 1]), duration=duration, rate=rate, jitter=jitter,
                            start_below=below, foot=foot, force_noise=force_noise, depth_noise=depth_noise,
                            bias=bias)
                trials.append(Trial(name, float(w), path.time, path.depth, path.force, None, r))
                continue
            fine = gait(int(seeds[i, r - 1]), duration=duration, rate=max(FINE_RATE, rate), start_below=below)
            clean = simulate(fine.time, fine.depth, MudParameters.from_water_content(float(w)), foot,
                             velocity_filter="exact").force
            t, z, f = _through_chain(chain, fine.time, fine.depth, clean, rate=rate, force_noise=force_noise,
                                     depth_noise=depth_noise, bias=bias, seed=int(seeds[i, r - 1]))
            trials.append(Trial(name, float(w), t, z, f, None, r))
    synthetic = {
        "seed": seed,
        "force_noise_N": force_noise,
        "depth_noise_m": depth_noise,
        "bias_N": bias,
        "gait": {"duration_s": duration, "rate_Hz": rate, "jitter": jitter, "start_below": start_below},
        "parameters": truths,
    }
    if chain is not None:
        synthetic["sensor_chain"] = _chain_entry(chain)
    dataset = Dataset(foot=foot, trials=tuple(trials), source="synthesize_gait()", extra={"synthetic": synthetic})
    if out is not None:
        written = save_dataset(dataset, out)
        dataset = Dataset(foot=foot, trials=dataset.trials, source=str(written), extra=dataset.extra)
    return dataset
