"""Static mesh forces in ISO terms, and the planet load-sharing factor of a planetary stage.

A mesh spring carries the normal force F_bn along the line of action (:mod:`.reactions`,
``force_N``). With the base helix angle beta_b, the transverse working pressure angle
alpha_wt and the transverse reference pressure angle alpha_t of the mesh
(:mod:`.gear_table`), ISO 6336-1 / ISO 21771 split it into

* F_bt = F_bn cos(beta_b), the transverse force in the plane of action, and the axial
  force F_a = F_bn sin(beta_b) (= F_t tan(beta));
* the nominal tangential force at the reference circle F_t = F_bt cos(alpha_t) = T / r
  (T the torque the mesh puts on either gear, r = r_b / cos(alpha_t) its reference
  radius); without teeth the reference circle is not known and F_t is taken at the
  working pitch circle (alpha_wt: F_t = T / r_w);
* the radial force F_r = F_bt sin(alpha_wt), along the centre line.

Signs follow ``force_N``: > 0 the drive flank carries the load.

The planet load-sharing factor of a stage (ISO 6336-1 K_gamma, for each of its two mesh
kinds): K_gamma = max / mean of the magnitudes of its planets' static mesh forces; 1 for
a stage whose planets share the load equally.
"""
from __future__ import annotations

import math

import numpy as np


def iso_mesh_forces(force: float, row) -> dict:
    """F_t (reference circle, or working pitch circle without teeth), F_r, F_a (N) of a mesh
    carrying ``force`` (N, along the line of action), ``row`` its
    :class:`assembly.analysis.gear_table.GearRow`; ``circle``: which circle F_t is at."""
    f_bt = force * math.cos(row.base_helix_angle)
    a_t = row.transverse_pressure_angle
    return {"F_t_N": f_bt * math.cos(row.working_pressure_angle if a_t is None else a_t),
            "F_r_N": f_bt * math.sin(row.working_pressure_angle),
            "F_a_N": force * math.sin(row.base_helix_angle),
            "circle": "working pitch" if a_t is None else "reference"}


#: Planets whose mean mesh force is below this fraction of the case's largest force carry
#: nothing but round-off: their K_gamma (a ratio of round-off) is not given.
UNLOADED = 1e-9


def load_sharing(scene, forces: dict, scale: float = 0.0) -> list:
    """Per planetary stage of ``scene`` and mesh kind (``sun-planet``, ``planet-ring``): the
    planets' static mesh forces (N, by planet) and K_gamma = max / mean of their magnitudes
    (None, with a ``note``, when they carry nothing: a mean below :data:`UNLOADED` x the
    case's largest force, ``scale`` (N: of its meshes, bearings and applied loads) or the
    largest of ``forces``). ``forces``: expanded mesh name -> force (N)."""
    largest = max([abs(float(v)) for v in forces.values()] + [abs(float(scale))])
    out = []
    for st in scene.stages:
        for kind, name in (("sun-planet", "{}.sun-planet{}"), ("planet-ring", "{}.planet{}-ring")):
            got = [forces.get(name.format(st.name, i)) for i in range(st.planets.count)]
            if None in got:          # a model without the stage's meshes (a part of the scene)
                continue
            f = np.abs(got)
            mean = float(f.mean())
            loaded = mean > UNLOADED * largest and mean > 0.0
            row = {"stage": st.name, "mesh": kind, "forces_N": f.tolist(),
                   "K_gamma": float(f.max()) / mean if loaded else None}
            if not loaded:
                row["note"] = (f"the planets carry no load in this case (mean {mean:.3g} N, the case's largest "
                               f"force {largest:.3g} N): no load-sharing factor")
            out.append(row)
    return out
