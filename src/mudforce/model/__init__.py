"""The physics layer: every equation and every rule of the model, written once.

- :mod:`~mudforce.model.equations`: the paper's Eqs. (1)-(9) as small pure functions, and the rules built on
  them (which terms act on which branch, the drag gate, the necking test, the rest band of a state);
- :mod:`~mudforce.model.parameters`: Table I and the validated parameter set;
- :mod:`~mudforce.model.foot`: the paper's foot (area and width);
- :mod:`~mudforce.model.velocity`: the branch rule on sampled, possibly noisy, depth (Eq. (8));
- :mod:`~mudforce.model.shapes`, :mod:`~mudforce.model.law3d`: foot surfaces as elements and the law per element
  (mud in 3-D: ours, built on the paper's law);
- :mod:`~mudforce.model.granular`, :mod:`~mudforce.model.baselines`: the granular resistive-force laws the model
  is compared with.

The steppers (:mod:`mudforce.steppers`, :mod:`mudforce.jax`), the engines and the estimators call these; none of
them writes an equation of its own.
"""

__all__: list[str] = []
