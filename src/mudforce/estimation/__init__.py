"""Learning the mud from data.

- :mod:`~mudforce.estimation.calibration`: fit the parameters from trials of any motion, identify the water
  content of one trial, synthesize trials, fit the drag;
- :mod:`~mudforce.estimation.tracker`: the water content online (``MudTracker``, ``MudTrackers``, ``track``).
"""

__all__: list[str] = []
