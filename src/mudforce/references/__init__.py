"""Independent solutions (oracles) the tests hold the steppers against: ``scipy.integrate.solve_ivp`` with
events, sharing only the equations (:mod:`mudforce.model`), never the steppers' control flow.

- :mod:`~mudforce.references.trajectory`: a prescribed depth trajectory (``reference_simulate``);
- :mod:`~mudforce.references.drop`: a foot of mass ``m`` dropped into mud (``exact_drop``);
- :mod:`~mudforce.references.contact3d`: the 3-D law along prescribed poses.
"""

__all__: list[str] = []
