"""The 3-D kernel's fast paths give the general paths' bits.

* Each element's paper state in :class:`MudContacts3D` (FREE elements that stay FREE store only the columns
  their quiet step changes; Eq. (4) is computed once per submerged element for the paper's stress and the
  lateral law) equals the 1-D stepper's (:class:`mudforce.MudContacts`) on the same element depths, bit for bit,
  and so does each element's stress.
  So it does when the step length changes (every element through the whole state machine).
* :class:`MudAdapter3D`'s one-patch-everywhere path equals its general path (a patch with a finite extent that
  holds every foot), bit for bit.
"""

from __future__ import annotations

import mujoco
import numpy as np

import mudforce as mf
from mudforce import _kernel as K
from mudforce.engines.mujoco import MudAdapter3D, MudPatch
from mudforce.engines.mujoco.adapter3d import drop_model_3d
from mudforce.model import law3d, shapes
from mudforce.steppers.contact3d import MudContacts3D

MUD = mf.MudParameters.from_water_content(0.25)
SPHERE = shapes.sphere(0.04, resolution=0.012)
DT = 2e-3


def test_element_states_are_the_1d_steppers() -> None:
    """A sphere that falls in from above (FREE elements staying FREE, touchdowns), sinks, rises and leaves."""
    steps = 160
    t = np.arange(steps) * DT
    z = 0.03 - 0.045 * np.sin(np.pi * t / t[-1])  # origin 30 mm up, to 15 mm down, back up
    feet = MudContacts3D(MUD, SPHERE, 2)
    quats = np.tile([1.0, 0.0, 0.0, 0.0], (2, 1))
    assert SPHERE.width is not None
    element = mf.Foot(area=1.0, width=SPHERE.width, shape="element")
    one_d = mf.MudContacts(MUD, 2 * SPHERE.n, element, threads=1, velocity_filter="exact")
    oz = law3d.rotate(tuple(np.eye(3).ravel().tolist()), *SPHERE.centroids.T)[2]
    modes = set()
    for k in range(steps):
        pos = np.array([[0.0, 0.0, z[k]], [0.01, 0.0, z[k] + 0.002]])
        feet.step(pos, quats, DT if k else 0.0)
        depths = np.concatenate([law3d.element_depth(0.0, pos[f, 2], oz) for f in range(2)])
        force = one_d.step(depths, DT if k else 0.0)
        np.testing.assert_array_equal(feet.state.elements[:, :K.N_STATE], one_d.state[:, :K.N_STATE])
        np.testing.assert_array_equal(feet._stress, force)  # the elements' stresses [Pa] (unit areas)
        modes |= set(feet.modes)
    assert {"FREE", "CONTACT"} <= modes


def test_a_change_of_step_length_is_the_1d_steppers() -> None:
    """Steps whose length changes (every element leaves its quiet step for the whole state machine, which
    ``_step_foot`` calls out of line) while the sphere sinks and rises: each element's state and stress are still
    the 1-D stepper's, bit for bit."""
    lengths = np.array([DT] * 20 + [DT / 2] * 20 + [DT] * 20 + [1.5 * DT] * 20)
    t = np.concatenate([[0.0], np.cumsum(lengths[1:])])
    z = 0.01 - 0.03 * np.sin(np.pi * t / t[-1])  # origin 10 mm up, to 20 mm down, back up
    feet = MudContacts3D(MUD, SPHERE, 1)
    quats = np.array([[1.0, 0.0, 0.0, 0.0]])
    assert SPHERE.width is not None
    element = mf.Foot(area=1.0, width=SPHERE.width, shape="element")
    one_d = mf.MudContacts(MUD, SPHERE.n, element, threads=1, velocity_filter="exact")
    oz = law3d.rotate(tuple(np.eye(3).ravel().tolist()), *SPHERE.centroids.T)[2]
    modes = set()
    for k in range(lengths.size):
        pos = np.array([[0.0, 0.0, z[k]]])
        dt = lengths[k] if k else 0.0
        feet.step(pos, quats, dt)
        force = one_d.step(law3d.element_depth(0.0, pos[0, 2], oz), dt)
        np.testing.assert_array_equal(feet.state.elements[:, :K.N_STATE], one_d.state[:, :K.N_STATE])
        np.testing.assert_array_equal(feet._stress, force)
        modes |= set(feet.modes)
    assert {"FREE", "CONTACT", "NECKED"} <= modes


def test_one_patch_everywhere_is_the_general_path() -> None:
    """A tilted sphere dropped sideways into mud: the adapter's fast path and its general path agree bit for bit."""
    runs = []
    for patch in (MudPatch(MUD), MudPatch(MUD, extent=(-10.0, 10.0, -10.0, 10.0))):
        model = drop_model_3d(0.5, "sphere", [0.04], height=0.01, tilt=0.3)
        data = mujoco.MjData(model)
        data.qvel[0] = 0.2
        mud = MudAdapter3D(model, data, ["foot"], patch, resolution=0.012)
        rec = []
        for k in range(120):
            mud.step()
            if k == 60:
                mud.reset()
            rec.append(np.concatenate([data.qpos, data.qvel, mud.contact_forces.ravel(), mud.law_forces.ravel(),
                                       mud.law_torques.ravel(), mud.capacity.ravel()]))
        runs.append(np.array(rec))
    assert np.abs(runs[0][:, 2]).max() > 0.0
    np.testing.assert_array_equal(runs[0], runs[1])
