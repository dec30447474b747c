"""Coupled against one-way (assembly.dynamics.coupling) on a drivetrain that is its own two-mass
equivalent.

Theory. When the detailed drivetrain is a two-mass chain (rotor, shaft, generator), its two-mass
equivalent is itself, so the coupled run and the two-mass run are one run; and the one-way run
applies that run's recorded aerodynamic torque and generator torque at the very steps they acted
(the torque a controller sample held over a step is recorded at the step's end, where the one-way
table is read; the aerodynamic torque at t_{k+1} is the one the step solved for), so it repeats
the coupled run to Newton's tolerance (1e-10 of the forces) -- when both start alike: the
coupled run starts in equilibrium with the generator torque that balances the rotor's, the
one-way run with the torque the controller's first sample set, so the pitch is trimmed here to
make the two one (the simple law's region 3 asks the rated torque). The spectra then agree to
that order, and the comparison finds no peak differing by its 3 dB.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from assembly.app.report.coupling import coupling_files
from assembly.app.report.links import folder_problems
from assembly.dynamics.coupling import DIFFER_DB, compare_coupling
from assembly.dynamics.rosco_data import NREL5MW_SURFACE, rosco_file
from assembly.dynamics.rotor_surface import read_surface, rotor_loads
from assembly.errors import SceneError
from assembly.scene.schema import scene_from_dict

pytest.importorskip("rosco", reason="the rosco package (its NREL 5 MW surface) is not installed")

pytestmark = pytest.mark.usefixtures("step_path")

RPM = math.pi / 30.0
# NREL 5 MW (Jonkman et al., NREL/TP-500-38060, 2009): rotor, generator x ratio^2, DTTorSpr, DTTorDmp
J_ROTOR, J_GEN_LSS, K, C = 38_759_236.0, 534.116 * 97.0 ** 2, 867_637_000.0, 6_215_000.0
TQ = 43_093.55 * 97.0                     # rated generator torque on the low-speed side


def _trim() -> float:
    """The pitch (rad) at which the surface gives the rated torque at 16 m/s and 12.1 rpm."""
    s = read_surface(rosco_file(NREL5MW_SURFACE))
    lo, hi = 0.0, math.radians(25.0)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if rotor_loads(s, 63.0, 1.225, 16.0, 12.1 * RPM, mid).torque > TQ else (lo, mid)
    return 0.5 * (lo + hi)


def _chain(**turbine):
    tb = {"surface": "rosco", "radius": 63.0, "pitch": _trim(),
          "wind": {"steps": [[0.0, 16.0], [4.0, 17.0], [8.0, 15.5], [12.0, 16.5]]},
          "controller": {"kind": "simple", "period": 0.01, "rated_speed": 1161.963 * RPM / 97.0,
                         "rated_torque": TQ, "region2_k": 2.332287 * 97.0 ** 3, "slip": 0.1}}
    tb.update(turbine)
    return scene_from_dict({
        "name": "two-mass chain", "fidelity": "torsional", "band_hz": 10.0,
        "bodies": [{"name": "rotor", "role": "rotor", "mass": 1.0, "polar_inertia": J_ROTOR,
                    "position": [0.0, 0.0, 0.0]},
                   {"name": "generator", "role": "generator", "mass": 1.0, "polar_inertia": J_GEN_LSS,
                    "position": [0.0, 0.0, 5.0]}],
        "shafts": [{"name": "shaft", "body1": "rotor", "body2": "generator", "k_torsion": K, "c_torsion": C}],
        "bearings": [{"body": "rotor", "position": [0.0, 0.0, 0.0], "k_radial": 1e9, "k_axial": 1e9,
                      "k_tilt": 1e9}],
        "simulation": {"speed": 12.1 * RPM}, "turbine": tb})


def test_a_two_mass_drivetrain_gives_the_same_spectra_coupled_and_one_way(tmp_path, step_path):
    c = compare_coupling(_chain(), 16.0, 0.01, tooth_force="torque:shaft", bearing_axial="torque:shaft",
                         t_skip=2.0, segment=4.0)
    if step_path == "python":                  # flexgear coupling's files of it, once (the step does not matter)
        coupling_files(c, tmp_path, "two-mass chain", 10.0)
        assert folder_problems(tmp_path) == []    # index.html: the shared style, the navigation, every link
    # the two-mass equivalent is the chain itself (its shaft, its inertias)
    assert c.two_mass.stiffness == pytest.approx(K, rel=1e-12)
    assert c.two_mass.damping == pytest.approx(C, rel=1e-9)
    for s in c.spectra:
        top = float(s.coupled.max())
        # Newton's tolerance of the forces, through the spectrum's linear operations
        assert np.max(np.abs(s.coupled - s.one_way)) <= 1e-7 * top, s.label
    assert all(abs(p["ratio_db"]) < DIFFER_DB for p in c.peaks if p["coupled"] > 1e-6 * max(
        float(s.coupled.max()) for s in c.spectra if s.output == p["output"]))
    assert not any("differs" in v for v in c.verdicts)


def test_the_comparison_needs_a_turbine_rotor_and_a_long_enough_run():
    with pytest.raises(SceneError) as exc:
        compare_coupling(_chain(wind=None), 16.0, 0.01, "torque:shaft", "torque:shaft")
    assert exc.value.path == "turbine"
    with pytest.raises(SceneError) as exc:
        compare_coupling(_chain(), 10.0, 0.01, "torque:shaft", "torque:shaft", t_skip=2.0, segment=5.0)
    assert exc.value.path == "t_skip"
