"""The steppers: the model advanced along a prescribed motion, on the CPU (compiled).

- :mod:`~mudforce.steppers.simulation`: ``simulate``, a whole trajectory at once (batch);
- :mod:`~mudforce.steppers.contact`: ``MudContact``, one foot one sample at a time (streaming);
- :mod:`~mudforce.steppers.many`: ``MudContacts``, many feet stepped together;
- :mod:`~mudforce.steppers.contact3d`: ``MudContact3D``, ``MudContacts3D``, ``simulate_3d``, a foot of any shape.

The JAX stepper is :mod:`mudforce.jax`; the engines that move a foot by its mass are :mod:`mudforce.engines`.
"""

__all__: list[str] = []
