"""Motions and recordings that drive the model and test the estimators.

- :mod:`~mudforce.motions.protocol`: the paper's prescribed intrude-hold-withdraw motions;
- :mod:`~mudforce.motions.gait`: robot-like walks on (changing) mud;
- :mod:`~mudforce.motions.quadruped`: foot trajectories from a quadruped simulated in MuJoCo;
- :mod:`~mudforce.motions.sensor_chain`: a robot's sensor chain applied to a recording (offset, drift, lag,
  gain, noise, rate).
"""

__all__: list[str] = []
