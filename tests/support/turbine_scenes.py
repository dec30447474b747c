"""Small drivetrains in their turbine (a ``[turbine]`` table with ROSCO's NREL 5 MW surface and
ServoDyn's simple torque law), as scenes for :func:`assembly.dynamics.simulate.simulate`.

NREL 5 MW (Jonkman, Butterfield, Musial & Scott, NREL/TP-500-38060, 2009): rotor inertia, the
generator's on the high-speed side, gear ratio, ElastoDyn's drivetrain spring, rated torque and
speed of the generator, tip radius; the rotor's mass (blades and hub, 110 t) for its axial
motion.
"""
from __future__ import annotations

import math

from assembly.scene.schema import scene_from_dict

RPM = math.pi / 30.0
J_ROTOR, J_GEN, RATIO, K_SHAFT = 38_759_236.0, 534.116, 97.0, 867_637_000.0
RATED_TQ, RATED_GEN_RPM, RADIUS = 43_093.55, 1161.963, 63.0
M_ROTOR = 110_000.0


def simple_controller(period: float, tq: float) -> dict:
    """ServoDyn's simple law referred to the low-speed side: above rated speed the rated torque
    ``tq`` (N m), whatever the speed; called every ``period`` s."""
    return {"kind": "simple", "period": period, "rated_speed": RATED_GEN_RPM * RPM / RATIO, "rated_torque": tq,
            "region2_k": 2.332287 * RATIO ** 3, "slip": 0.1}


def two_mass(speed, pitch, wind, pulse, t_pulse, dt, tq, period=None):
    """The two-mass torsional drivetrain (rotor J_r, generator J_g N^2 on the low-speed side,
    ElastoDyn's shaft) at ``speed`` rad/s, the blades at ``pitch`` rad, in ``wind`` (m/s, or a
    ``[turbine.wind]`` table), a torque doublet ``pulse`` (N m) on the generator at ``t_pulse``
    (two times, ramps of ``dt``), the controller every ``period`` s (default ``dt``) holding
    ``tq``."""
    return scene_from_dict({
        "name": "two-mass drivetrain", "fidelity": "torsional",
        "bodies": [{"name": "rotor", "role": "rotor", "mass": 1.0, "polar_inertia": J_ROTOR,
                    "position": [0.0, 0.0, 0.0]},
                   {"name": "generator", "role": "generator", "mass": 1.0, "polar_inertia": J_GEN * RATIO ** 2,
                    "position": [0.0, 0.0, 5.0]}],
        "shafts": [{"name": "shaft", "body1": "rotor", "body2": "generator", "k_torsion": K_SHAFT}],
        "simulation": {"speed": speed, "loads": [
            {"body": "generator", "value": 0.0, "end_value": pulse, "t_start": t_pulse[0], "t_end": t_pulse[0] + dt},
            {"body": "generator", "value": 0.0, "end_value": -pulse, "t_start": t_pulse[1],
             "t_end": t_pulse[1] + dt}]},
        "turbine": {"surface": "rosco", "radius": RADIUS, "pitch": pitch,
                    "wind": wind if isinstance(wind, dict) else {"speed": wind},
                    "controller": simple_controller(dt if period is None else period, tq)}})


def rigid_rotor(speed, pitch, wind: dict, period, tq, k_axial=5.0e8, c_axial=1.0e6):
    """The rotor and generator as rigid bodies on their bearings (the rotor's axial mount ``k_axial``
    N/m with a damper ``c_axial`` N s/m), the shaft between them in torsion only, so the rotor's
    thrust acts on its own axial row: ``speed`` rad/s, ``pitch`` rad, ``wind`` a
    ``[turbine.wind]`` table, the controller every ``period`` s holding ``tq`` N m."""
    return scene_from_dict({
        "name": "rigid rotor on its mount", "fidelity": "rigid",
        "bodies": [{"name": "rotor", "role": "rotor", "mass": M_ROTOR, "polar_inertia": J_ROTOR,
                    "position": [0.0, 0.0, 0.0]},
                   {"name": "generator", "role": "generator", "mass": 1000.0, "polar_inertia": J_GEN * RATIO ** 2,
                    "position": [0.0, 0.0, 5.0]}],
        "shafts": [{"name": "shaft", "body1": "rotor", "body2": "generator", "k_torsion": K_SHAFT}],
        "bearings": [{"body": b, "position": [0.0, 0.0, z], "k_radial": 1.0e9, "k_axial": k_axial, "k_tilt": 1.0e10,
                      "c_axial": c_axial} for b, z in (("rotor", 0.0), ("generator", 5.0))],
        "simulation": {"speed": speed},
        "turbine": {"surface": "rosco", "radius": RADIUS, "pitch": pitch, "thrust": True, "wind": wind,
                    "controller": simple_controller(period, tq)}})
