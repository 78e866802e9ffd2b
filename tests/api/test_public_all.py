"""Every public module's ``__all__`` is pinned: a change to the API (a name added, removed or renamed, a new
public module) must be deliberate, made here with it.

A public module is one under ``src/mudforce`` whose dotted name has no part starting with ``_`` (found on
disk with :mod:`pkgutil`, without importing anything). The command line's modules (``mudforce.cli.*``)
are pinned too: their interface is the command line itself (tested through a subprocess in ``tests/cli/``),
but their ``__all__`` names what :mod:`mudforce.cli` (``NAME``, ``HELP``, ``add_arguments``, ``run``) and
other modules take from them. Modules that need an optional package are checked only where it is installed.

The lists were generated once from the code and written out literally; review them as the API. This is the
one pin of every ``__all__`` (``mudforce``'s included); the table of the public API is ``docs/api.md``, and
deprecated names (never in ``__all__``) are tested in ``test_deprecated.py``.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType

import pytest

import mudforce

# module -> the optional packages it needs (skipped where one is missing)
OPTIONAL: dict[str, tuple[str, ...]] = {
    "mudforce.jax": ("jax",),
    "mudforce.jax.contact3d": ("jax",),
    "mudforce.jax.domain": ("jax",),
    "mudforce.engines.mjx": ("jax", "mujoco", "mujoco.mjx"),
    "mudforce.engines.mjx3d": ("jax", "mujoco", "mujoco.mjx"),
    "mudforce.engines.mujoco": ("mujoco",),
    "mudforce.engines.mujoco.adapter3d": ("mujoco",),
}

PINNED: dict[str, list[str]] = {
    "mudforce": [
        "CITATION", "PARAMETER_NAMES", "STATE_NAMES", "TABLE_I", "ContactSample", "ContactState", "Foot", "Hold",
        "InputError", "Intrude", "MudContact", "MudContact3D", "MudContacts", "MudContacts3D", "MudParameters",
        "MudTracker", "MudTrackers", "Protocol", "SimulationResult", "TrackEstimate", "TrackEstimates",
        "VelocityFilter", "Withdraw", "Wrench", "__version__", "estimate_depth_noise", "simulate", "simulate_3d",
    ],
    "mudforce.model.baselines": [
        "BASELINE_NAMES", "DEFAULT_K_RFT", "branch_velocity", "drft_force", "granular_rft_force", "maxwell_only_force",
    ],
    "mudforce.estimation.calibration": [
        "CHEN2024", "MODELS", "ConditionFit", "Dataset", "DragFit", "Fit3D", "FitOptions", "FitResult", "FitStage",
        "ForceModel", "Identification", "Motion", "PreparedTrial", "Trial", "TrialFit", "fit_3d", "fit_by_velocity",
        "fit_condition", "fit_dataset", "fit_drag", "fit_motion", "get_model", "identify_water_content",
        "load_dataset", "load_fit", "load_fit_parameters", "load_trial", "parse_foot", "prepare_trial", "read_sliding",
        "register_model", "save_dataset", "synthesize", "synthesize_gait", "tare",
    ],
    "mudforce.estimation.calibration.branches": [
        "CREEP_SAMPLES", "CREEP_SIGMAS", "CUT", "JUMP_REWARD_CAP", "QUIET_FINE_MIN_SAMPLES", "QUIET_FINE_ORDER",
        "QUIET_FINE_RATIO", "QUIET_FINE_SCALE", "QUIET_FINE_WINDOW", "QUIET_MIN_WINDOWS", "QUIET_ORDER",
        "QUIET_QUANTILE", "QUIET_RATIO", "QUIET_SCALE", "QUIET_WINDOW", "SWITCH_COST", "corner_preserving_smooth",
        "creep_withdrawals", "denoise_depth", "estimate_force_noise",
        "estimate_quiet_noise", "label_branches", "rest_steps",
    ],
    "mudforce.estimation.calibration.dataset": [
        "MANIFEST_NAME", "MIN_SAMPLES", "Dataset", "Trial", "foot_from_json", "foot_to_json", "load_dataset",
        "load_trial", "parse_foot", "save_dataset",
    ],
    "mudforce.estimation.calibration.drag": ["DragFit", "fit_drag", "read_sliding"],
    "mudforce.estimation.calibration.fit": [
        "DEPTH_NOISE_SHARE_WARNING", "MISFIT_WARNING_RATIO", "POOR_RELATIVE_STDERR", "ConditionFit", "FitOptions",
        "FitResult", "TrialFit",
        "correlation_inflation", "fit_by_velocity", "fit_condition", "fit_dataset", "load_fit", "load_fit_parameters",
        "misfit_ratio", "speed_key",
    ],
    "mudforce.estimation.calibration.fit3d": ["FIT3D_PARAMETERS", "Fit3D", "fit_3d"],
    "mudforce.estimation.calibration.identify": [
        "DEFAULT_FORCE_GAIN_UNCERTAINTY",
        "MAX_DEPTH_OFFSET",
        "MAX_FORCE_LAG",
        "MIN_HALF_WIDTH",
        "NEAR_LIMITS_WARNING",
        "OTHER_MUD_WARNING",
        "REST_SPEED",
        "TAIL_SHARE_WARNING",
        "Identification",
        "identify_water_content",
    ],
    "mudforce.estimation.calibration.models": [
        "CHEN2024", "DRFT", "GRANULAR_RFT", "MAXWELL_ONLY", "MODELS", "FitStage", "ForceFunction", "ForceModel",
        "get_model", "register_model",
    ],
    "mudforce.estimation.calibration.preprocess": [
        "CLEAN_DEPTH_M", "MAX_DEPTH_NOISE_M", "MIN_PRECONTACT_SAMPLES", "Motion", "PreparedTrial", "fit_motion",
        "is_protocol", "motion_covariance", "noise_floor", "noise_floor_parts", "prepare_trial", "snap_reversal",
        "tare", "tare_correction",
    ],
    "mudforce.estimation.calibration.report": ["ERROR_PROFILE_POINTS", "error_profile", "write_report"],
    "mudforce.estimation.calibration.results": [
        "MISFIT_WARNING_RATIO", "POOR_RELATIVE_STDERR", "ConditionFit", "FitResult", "TrialFit", "load_fit",
        "load_fit_parameters", "misfit_ratio", "speed_key",
    ],
    "mudforce.estimation.calibration.synth": [
        "DEFAULT_VELOCITIES", "DEFAULT_WATER_CONTENTS", "FINE_RATE", "MAX_FINE_SAMPLES", "MAX_REPEATS", "START_BELOW",
        "repeat_count", "synthesize", "synthesize_gait", "trial_name",
    ],
    "mudforce.estimation.calibration.uncertainty": [
        "correlation_inflation", "covariance", "jackknife_variance", "jacobian", "motion_sensitivity", "profiled",
        "profiled_in_place",
    ],
    "mudforce.cli": ["COMMANDS", "main"],
    "mudforce.engines": [],  # a package of modules by concept
    "mudforce.estimation": [],  # a package of modules by concept
    "mudforce.model": [],  # a package of modules by concept
    "mudforce.motions": [],  # a package of modules by concept
    "mudforce.references": [],  # a package of modules by concept
    "mudforce.steppers": [],  # a package of modules by concept
    "mudforce.cli.drop": ["HELP", "NAME", "add_arguments", "run"],
    "mudforce.cli.fit": ["HELP", "NAME", "add_arguments", "run"],
    "mudforce.cli.fit_drag": ["HELP", "NAME", "add_arguments", "run"],
    "mudforce.cli.identify": ["HELP", "NAME", "add_arguments", "run"],
    "mudforce.cli.params": [
        "HELP", "NAME", "add_arguments", "format_table_i", "parse_water_content", "run", "table_i_json",
    ],
    "mudforce.cli.reproduce": ["HELP", "NAME", "add_arguments", "run"],
    "mudforce.cli.simulate": [
        "FOOT_EXAMPLES", "HELP", "MAX_SAMPLES", "NAME", "add_arguments", "check_output_path", "parse_foot", "run",
    ],
    "mudforce.cli.synth": [
        "DEPTH_NOISE_SIGMAS", "HELP", "MAX_BIAS", "MAX_FORCE_NOISE", "MAX_SAMPLES", "MAX_TRIALS", "NAME",
        "add_arguments", "run",
    ],
    "mudforce.cli.track": ["COLUMNS", "HELP", "NAME", "add_arguments", "run"],
    "mudforce.steppers.contact": ["ContactSample", "ContactState", "MudContact", "check_states"],
    "mudforce.steppers.contact3d": [
        "ContactState3D", "ContactStates3D", "MudContact3D", "MudContacts3D", "Result3D", "Wrench", "simulate_3d",
    ],
    "mudforce.engines.dynamics": [
        "GRAVITY", "PHASE_NAMES", "REST_SPEED", "ExactDrop", "FootResult", "NaiveDrop", "Phase", "branch_forces",
        "exact_drop", "naive_drop", "rest_band", "simulate_foot",
    ],
    "mudforce.engines.dynamics.engine": ["simulate_foot"],
    "mudforce.engines.dynamics.naive": ["NaiveDrop", "naive_drop"],
    "mudforce.engines.dynamics.rest_band": ["band_middle", "branch_forces", "branch_forces_row", "necked_force",
                                          "rest_band", "rest_band_spread"],
    "mudforce.engines.dynamics.result": ["GRAVITY", "PHASE_NAMES", "REST_SPEED", "FootResult", "Phase", "check_path"],
    "mudforce.model.equations": [
        "NECK_FILTER_SERIES_BELOW", "NECK_FILTER_SLOW_MODE_FROM",
        "array_form", "drag_acts", "drag_stress", "intrusion_stress", "maxwell_strain_increment", "maxwell_strain_rate",
        "maxwell_strain_step", "neck_breaks", "neck_filter_closed_form",
        "neck_filter_response", "neck_filter_response_increment", "neck_filter_sine_series",
        "neck_filter_sinh_series", "neck_filter_slow_mode", "neck_filter_transition",
        "neck_filter_transition_increment", "neck_filter_update", "neck_filter_update_increment", "necked_mud_motion",
        "necked_stress", "necking_fraction", "necking_time", "necking_velocity", "nonlinear_spring_stress",
        "piece_midpoint_depth", "post_necking_force", "relaxation_time", "rest_band_blend", "rest_band_depth_spread",
        "rest_band_forces",
        "submerged_drag_stress", "total_stress", "viscoelastic_stress", "withdrawal_stress", "yield_strain"
    ],
    "mudforce.errors": [
        "MAX_FEET", "MAX_SEED", "InputError", "feet_count", "finite_number", "holds_boolean", "is_integer", "is_real",
        "number_within", "positive_int", "positive_number", "real_array", "real_number", "seed_int", "shown",
        "true_or_false",
    ],
    "mudforce.model.foot": ["AREA_RANGE", "FOOT_EXAMPLES", "SIZE_RANGE", "Foot", "parse_foot"],
    "mudforce.motions.gait": ["Gait", "Walk", "gait", "walk"],
    "mudforce.model.bounds": [
        "MAX_DEPTH", "MAX_DT", "MAX_GRAVITY", "MAX_HORIZONTAL", "MAX_OUTPUT_SAMPLES", "MAX_TIME", "MIN_DT",
        "bounded_depth", "check_depths", "check_finite", "check_gravity", "check_step", "check_times", "max_samples"],
    "mudforce.model.law3d": [
        "FLAT_PLATE_ALPHA", "MAX_BEARING_SCALE", "MAX_LATERAL_STIFFNESS", "QUATERNION_TOLERANCE", "ROUNDING_DEPTH",
        "bearing_factor", "bearing_stress", "check_bearing_scale", "check_lateral_stiffness", "element_depth",
        "element_force", "horizontal_drag", "lateral_capacity", "lateral_return_map", "moment",
        "root", "rotate", "rotation", "rotation_matrix", "select", "settle_depth", "shear_fraction", "spring_stress",
        "vertical_element_force", "vertical_force", "vertical_lean", "vertical_weight",
    ],
    "mudforce.model.granular": [
        "LAWS", "LEADING_TOLERANCE", "LI2013_GENERIC", "RFT3D_C1", "RFT3D_C2", "RFT3D_C3", "LiCoefficients",
        "medium_scale", "rft3d_alpha", "rft3d_alpha_unchecked", "rft3d_angles",
        "rft3d_basis", "rft_alpha", "rft_element_alpha",
        "rft_element_forces", "rft_wrench",
    ],
    "mudforce.io": [
        "MAX_JSON_BYTES", "StagedOutputs", "atomic_open", "atomic_write_text", "check_input_name", "check_output_dir",
        "check_output_path", "check_replaceable_dir", "clean_stale", "dumps_json", "load_json",
        "refuse_overwriting_inputs", "write_outputs", "write_target",
    ],
    "mudforce.jax": [
        "CONTACT", "FREE", "NECKED", "UNSTARTED", "Necking", "Params", "State", "StepConstants", "branch_forces",
        "drag_stress", "init", "intrusion_step", "leave_necked", "make_params", "maxwell_strain_increment", "mud_depth",
        "neck_filter_response", "neck_filter_transition", "neck_flush_age", "necked_step", "necking_time",
        "nonlinear_spring_stress", "params_from_water_content", "reset", "rest_band", "step", "step_constants",
        "stick_force", "touchdown", "withdrawal_step",
    ],
    "mudforce.jax.contact3d": ["Params3D", "State3D", "init3d", "make_params3d", "reset3d", "step3d"],
    "mudforce.jax.domain": ["params_from_water_content"],
    "mudforce.engines.mjx": ["MudPatch", "MudState", "add_mud", "drop_model", "init", "simulate_drop", "step"],
    "mudforce.engines.mjx3d": ["Mud3D", "MudState3D", "add_mud", "init", "set_mud", "simulate_drop", "step"],
    "mudforce.engines.mujoco": [
        "ANCHOR_HEIGHT", "STICK_VELOCITY", "MudAdapter", "MudAdapter3D", "MudPatch", "add_mud", "add_mud_3d",
        "drop_model", "foot_of", "simulate_drop", "simulate_drop_3d",
    ],
    "mudforce.engines.mujoco.adapter3d": [
        "DROP_SHAPES", "SUPPORTED_GEOMS", "AdapterState3D", "Drop3D", "MudAdapter3D", "add_mud_3d", "drop_model_3d",
        "foot_geom", "simulate_drop_3d",
    ],
    "mudforce.model.parameters": [
        "CITATION", "PAPER_UNITS", "PARAMETER_NAMES", "PARAMETER_RANGES", "RHO_M", "TABLE_I", "TABLE_I_RMSE_N",
        "TABLE_I_WATER_CONTENTS", "WATER_CONTENT_RANGE", "MudParameters"
    ],
    "mudforce.io.plotting": ["check_title", "figure_to_png", "new_figure", "save_png"],
    "mudforce.io.results": ["to_pandas", "write_text"],
    "mudforce.steppers.plots": ["STATE_COLOURS", "plot_result"],
    "mudforce.engines.dynamics.plots": ["PHASE_COLOURS", "plot_foot_result"],
    "mudforce.motions.protocol": [
        "MAX_RATE", "MAX_SAMPLES", "MIN_RATE", "Hold", "Intrude", "Protocol", "Step", "Withdraw",
    ],
    "mudforce.motions.quadruped": [
        "FEET", "GAITS", "QUADRUPED_XML", "ROBOT_FOOT", "QuadrupedGait", "RobotWalk", "robot_walk",
    ],
    "mudforce.references.contact3d": ["Reference3DResult", "place", "reference_simulate_3d", "vertical_leans",
                                     "vertical_weights"],
    "mudforce.references.trajectory": ["CONTACT", "FREE", "NECKED", "ReferenceResult", "reference_simulate"],
    "mudforce.references.drop": ["GRAVITY", "ExactDrop", "exact_drop", "exact_drop_3d"],
    "mudforce.reproduce": [
        "MAX_SEED", "POORLY_DETERMINED", "SCATTERED", "VELOCITY_FREE", "ReproduceConfig", "ReproduceResult",
        "Terminated", "check_output_dir", "check_seed", "determined", "make_experiments", "reproduce",
    ],
    "mudforce.reproduce.experiments": ["SCATTERED", "ReproduceConfig", "make_experiments"],
    "mudforce.reproduce.figures": ["N_FIGURES", "Spec", "figure_specs", "warm_up_matplotlib", "write_figures"],
    "mudforce.reproduce.html": ["TEMPLATE", "render_html"],
    "mudforce.reproduce.jobs": ["GAIN_UNCERTAINTY", "THREADED_RUNTIMES", "VELOCITY_FREE", "Job", "count_fits",
                                "executor", "run_fits", "sort_fits", "start_method", "terminate"],
    "mudforce.reproduce.output": ["REPORT_FILES", "StagedFolder", "check_report_dir", "clean_stale"],
    "mudforce.reproduce.report": ["ReproduceResult", "Terminated", "reproduce"],
    "mudforce.reproduce.summary": [
        "MODEL_LABELS", "NINE", "PAPER_UNITS", "POORLY_DETERMINED", "determined", "in_paper_units", "make_summary",
        "summary_json",
    ],
    "mudforce.motions.sensor_chain": ["LIMITS", "SensorChain", "apply", "drift_path"],
    "mudforce.model.shapes": [
        "DEFAULT_ELEMENTS", "MAX_ELEMENTS", "Shape", "box", "capsule", "cylinder", "disc", "ellipsoid",
        "from_mujoco_geom", "mesh", "sole", "sphere",
    ],
    "mudforce.steppers.simulation": [
        "MAX_DEPTH", "MAX_DT", "MAX_TIME", "MIN_DT", "STATE_NAMES", "SimulationResult", "simulate",
    ],
    "mudforce.io.tables": [
        "COLUMN_LIMITS", "COLUMN_UNITS", "NUMBER", "POSE_COLUMNS", "WRITE_BLOCK", "is_pose_trajectory",
        "read_columns", "read_poses", "read_trajectory", "write_csv",
    ],
    "mudforce.estimation.family_check": [
        "DEFAULT_FAMILY_EVERY", "DEFAULT_FAMILY_WINDOW", "SWING_CLEARANCE", "FamilyCheck", "FamilyVerdict",
        "check_family",
    ],
    "mudforce.estimation.nuisances": ["DEFAULT_FORCE_GAIN_UNCERTAINTY", "REST_SPEED", "check_force_gain_uncertainty"],
    "mudforce.estimation.tracker": [
        "DEFAULT_DEPTH_OFFSETS", "DEFAULT_DEPTH_OFFSET_PRIOR", "DEFAULT_FORCE_LAG_ALLOWANCE", "DEFAULT_GRID",
        "DEFAULT_MAX_STEP", "MISFIT_THRESHOLD", "MudTracker", "MudTrackers", "TrackEstimate",
        "TrackEstimates",
        "TrackResult", "TrackerState",
        "default_velocity_filter", "track",
    ],
    "mudforce.estimation.tracking_plots": ["plot_track", "tracking_figure"],
    "mudforce.io.units": ["KINDS", "LIMITS", "format_quantity", "parse_list", "parse_quantity"],
    "mudforce.steppers.many": ["MudContacts"],
    "mudforce.model.velocity": [
        "MAX_NOISE_ORDER", "MAX_WINDOW", "MIN_NOISE_SAMPLES", "NOISE_FLOOR_M", "SLOWEST_MOTION", "DepthNoise",
        "VelocityFilter", "analyse_depth_noise", "auto_velocity_filter", "choose_velocity_filter",
        "describe_velocity_rule", "estimate_depth_noise", "resolve_velocity_filter",
    ],
}


def _walk(path: Path, prefix: str) -> Iterator[str]:
    for info in sorted(pkgutil.iter_modules([str(path)]), key=lambda m: m.name):
        yield prefix + info.name
        if info.ispkg:
            yield from _walk(path / info.name, f"{prefix}{info.name}.")


def public_modules() -> list[str]:
    """Every public module's dotted name, found on disk (nothing is imported)."""
    names = ["mudforce", *_walk(Path(mudforce.__file__).parent, "mudforce.")]
    return sorted(n for n in names
                  if not any(part.startswith("_") for part in n.split(".")))


def _import(name: str) -> ModuleType:
    for package in OPTIONAL.get(name, ()):
        pytest.importorskip(package)
    return importlib.import_module(name)


def test_every_public_module_is_pinned() -> None:
    """A new public module must be pinned deliberately; a module gone must leave the list."""
    found = public_modules()
    assert sorted(set(found) - set(PINNED)) == [], "public modules not pinned"
    assert sorted(set(PINNED) - set(found)) == [], "pinned modules that no longer exist"


def test_optional_modules_are_pinned_modules() -> None:
    assert set(OPTIONAL) <= set(PINNED)


@pytest.mark.parametrize("name", sorted(PINNED))
def test_all_is_pinned(name: str) -> None:
    """The module's ``__all__`` is exactly its pinned list (same names, same order, no repeats)."""
    module = _import(name)
    assert hasattr(module, "__all__"), f"{name} has no __all__"
    declared = list(module.__all__)
    assert len(declared) == len(set(declared)), f"{name}.__all__ repeats a name"
    assert declared == PINNED[name]


@pytest.mark.parametrize("name", sorted(PINNED))
def test_every_name_in_all_resolves(name: str) -> None:
    module = _import(name)
    missing = [n for n in module.__all__ if not hasattr(module, n)]
    assert missing == [], f"{name}: {missing}"
