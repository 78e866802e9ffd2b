"""The MuJoCo 3-D adapter's band paths give the general path's bits.

* :func:`mudforce.engines.mujoco._step3d.foot_band` (the band only for the elements that face down, and
  without the band at the step's start, which weight 1 multiplies by 0) equals the sum over every element
  of :func:`mudforce.engines.dynamics.rest_band.branch_forces` times its downward-facing area, bit for bit,
  through touchdown, contact and necking.
* A foot whose band :func:`~mudforce.engines.mujoco._step3d.feet_bands` computes (its patch is not the first
  to hold a foot) moves as it does when :func:`~mudforce.engines.mujoco._step3d.prepare` computes it: two
  feet in two patches, listed in either order, give the same bits.
"""

from __future__ import annotations

import mujoco
import numpy as np

import mudforce as mf
from mudforce.engines.dynamics.rest_band import branch_forces
from mudforce.engines.mujoco import MudAdapter3D, MudPatch, add_mud_3d
from mudforce.engines.mujoco._step3d import foot_band
from mudforce.model import law3d, shapes
from mudforce.steppers.contact3d import MudContacts3D

MUD = mf.MudParameters.from_water_content(0.25)
SPHERE = shapes.sphere(0.04, resolution=0.012)
DT = 2e-3


def test_foot_band_is_branch_forces_summed() -> None:
    """Two tilted spheres pushed in and pulled out fast (touchdowns, contact, necking): the sums agree bit for bit."""
    steps = 120
    t = np.arange(steps) * DT
    z = 0.025 - 0.04 * np.sin(np.pi * t / t[-1]) ** 2  # origin 25 mm up, to 15 mm down, back up
    feet = MudContacts3D(MUD, SPHERE, 2)
    tilt = 0.4
    quats = np.array([[1.0, 0.0, 0.0, 0.0], [np.cos(tilt / 2), np.sin(tilt / 2), 0.0, 0.0]])
    mats = np.array([law3d.rotation_matrix(q).ravel() for q in quats])
    states, rows = feet._live_rows()  # the writable rows MudAdapter3D passes (one compiled signature)
    nb = np.vstack([SPHERE.normals] * 2)
    area = np.concatenate([SPHERE.areas] * 2)
    up, down, drag = (np.zeros(len(area)) for _ in range(3))
    modes = set()
    for k in range(steps):
        feet.step(np.array([[0.0, 0.0, z[k]], [0.1, 0.0, z[k] + 0.003]]), quats, DT if k else 0.0)
        feet._export_rows()  # the rows as the step left them (as MudAdapter3D asks for them)
        branch_forces(states, rows, DT, 1.0, up, down, drag)
        for f in range(2):
            lo, hi = f * SPHERE.n, (f + 1) * SPHERE.n
            r = mats[f]
            expected = [0.0, 0.0, 0.0]
            sideways = np.zeros(6)
            for i in range(lo, hi):  # the adapter's sums before (every element, in order)
                nz = r[6] * nb[i, 0] + r[7] * nb[i, 1] + r[8] * nb[i, 2]
                w = area[i] * float(law3d.vertical_weight(nz))
                expected = [expected[0] + w * up[i], expected[1] + w * down[i], expected[2] + w * drag[i]]
                if w:  # the ends' sideways parts: law3d.vertical_element_force's lean on each element's share
                    lean = w * float(law3d.vertical_lean(nz))
                    lx = lean * (r[0] * nb[i, 0] + r[1] * nb[i, 1] + r[2] * nb[i, 2])
                    ly = lean * (r[3] * nb[i, 0] + r[4] * nb[i, 1] + r[5] * nb[i, 2])
                    sideways += [lx * up[i], ly * up[i], lx * down[i], ly * down[i], lx * drag[i], ly * drag[i]]
            side = np.full(6, np.nan)
            got = foot_band(states, rows, DT, lo, hi, r, nb, area, *feet._live_lanes(), side)
            np.testing.assert_array_equal(np.array(got), np.array(expected))
            np.testing.assert_array_equal(side, sideways)
        modes |= set(feet.modes)
    assert modes == {"FREE", "CONTACT", "NECKED"}


def _two_feet() -> tuple[mujoco.MjModel, mujoco.MjData]:
    spec = mujoco.MjSpec()
    spec.option.timestep = DT
    for name, x in (("a", -0.5), ("b", 0.5)):
        body = spec.worldbody.add_body(name=f"body_{name}", pos=[x, 0.0, 0.025])
        body.add_freejoint()
        body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.02, 0, 0], mass=0.5, contype=0,
                      conaffinity=0)
    add_mud_3d(spec, ["a", "b"])
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qvel[0] = 0.1  # foot a slides along x; foot b falls straight in
    return model, data


def test_a_band_from_feet_bands_is_the_one_prepare_computes() -> None:
    """Two feet in two patches: whichever patch is listed first, the run is the same, bit for bit."""
    west = MudPatch(mf.MudParameters.from_water_content(0.20), extent=(-10.0, 0.0, -10.0, 10.0))
    east = MudPatch(mf.MudParameters.from_water_content(0.30), extent=(0.0, 10.0, -10.0, 10.0))
    runs = []
    for patches in ([west, east], [east, west]):
        model, data = _two_feet()
        mud = MudAdapter3D(model, data, ["a", "b"], patches, resolution=0.012)
        rec = []
        for _ in range(80):
            mud.step()
            rec.append(np.concatenate([data.qpos, data.qvel, mud.contact_forces.ravel(), mud.band[0], mud.band[1],
                                       mud.capacity.ravel(), model.tendon_frictionloss]))
        runs.append(np.array(rec))
    assert (runs[0][-1, -12:] > 0.0).sum() >= 4  # both feet loaded
    np.testing.assert_array_equal(runs[0], runs[1])
