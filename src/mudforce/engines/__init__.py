"""Coupling the model to engines that move a foot by its mass.

- :mod:`~mudforce.engines.dynamics`: the built-in event-located engine (a foot dropped into mud), the naive
  explicit coupling for comparison;
- :mod:`~mudforce.engines.mujoco`: MuJoCo (``MudAdapter``, ``MudPatch``, ``add_mud``);
- :mod:`~mudforce.engines.mjx`: MJX (the same concepts as pytrees, under ``jit``).
"""

__all__: list[str] = []
