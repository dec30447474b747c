"""The referred-inertia table of a report: the drivetrain's inertia seen on each turning
body's shaft (:func:`assembly.analysis.drivetrain.referred_inertias`)."""
from __future__ import annotations

from ...analysis.drivetrain import referred_inertias
from ...errors import MechanismError

#: Title of the referred-inertia table.
REFERRED_TITLE = ("inertia referred to each shaft: twice the rigid-body mode's kinetic energy with that body "
                  "turning at 1 rad/s (sum J (omega / omega_shaft)^2, orbiting planets included)")


def referred_cells(model) -> dict:
    """Cells of the referred-inertia table (``rows`` empty and a ``notes`` line saying why
    when the model has not exactly one rigid-body mode)."""
    header = ["shaft (body)", "J referred [kg m^2]"]
    try:
        J = referred_inertias(model)
    except MechanismError as exc:
        return dict(title=REFERRED_TITLE, header=header, rows=[], left=(0,), notes=[f"no referred inertia: {exc}"])
    return dict(title=REFERRED_TITLE, header=header, rows=[[b, f"{j:.6g}"] for b, j in J.items()], left=(0,),
                notes=[])


def referred_json(model) -> dict:
    """Body -> referred inertia (kg m^2); empty without a single rigid-body mode."""
    try:
        return referred_inertias(model)
    except MechanismError:
        return {}
