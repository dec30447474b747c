"""The NREL 5 MW drivetrain at rated operation, every mesh angle-driven with backlash: the scene
the time-domain benchmarks run (tables 1, 2, 4 and 5 of ``flexgear bench transient``)."""
from __future__ import annotations

RATED_SPEED = 1.2671              # rad/s: 12.1 rpm rated rotor speed [Jonkman 2009]
GENERATOR_TORQUE = 43093.55       # N m: rated generator torque [Jonkman 2009]
RATIO = 96.354                    # the scenes' overall ratio from the teeth (nrel5mw.toml header)
STEP, BACKLASH = 0.3, 4.0e-4      # dk/k0 of every mesh; normal backlash m [Nejad et al. 2016]
DT_5MW = 1e-4                     # s


def rated_5mw(name: str):
    """The NREL 5 MW scene ``name`` at rated operation, every mesh angle-driven with backlash."""
    from ...scene.schema import load_scene
    scene = load_scene(name)
    ch = {"simulation": {"speed": RATED_SPEED, "generator": {"torque": GENERATOR_TORQUE},
                         "loads": [{"body": "rotor", "value": GENERATOR_TORQUE * RATIO}]}}
    for i, _ in enumerate(scene.stages):
        ch.update({f"stages[{i}].variation_sun": {"step": STEP}, f"stages[{i}].variation_ring": {"step": STEP},
                   f"stages[{i}].backlash": BACKLASH})
    for i, _ in enumerate(scene.meshes):
        ch.update({f"meshes[{i}].variation": {"step": STEP}, f"meshes[{i}].backlash": BACKLASH})
    return scene.with_values(ch)
