"""Plumbing shared by every package, and no physics: optional imports, deprecations, interrupts, progress,
failed writes (bad input or the system's failure: :mod:`mudforce._plumbing.writes`),
the results' common methods, and the map of modules that moved in 0.2.

Nothing here names an equation. The speed plumbing of the compiled steppers lives apart, in
:mod:`mudforce._kernel`.
"""
