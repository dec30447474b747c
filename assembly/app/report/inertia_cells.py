"""The referred-inertia table of a report: the drivetrain's inertia seen on each turning
body's shaft (:func:`assembly.analysis.referred.referred_inertias`)."""
from __future__ import annotations

from ...analysis.referred import referred_inertias
from ...errors import MechanismError

#: Title of the referred-inertia table.
REFERRED_TITLE = ("inertia referred to each shaft: twice the rigid-body mode's kinetic energy with that body "
                  "turning at 1 rad/s (sum J (omega / omega_shaft)^2, orbiting planets included)")


def _inertias(model, result):
    """:func:`referred_inertias` from ``result``'s rigid-body mode when it has exactly one
    (no second search for it), else from the model's springs."""
    if result is None:
        return referred_inertias(model)
    if result.n_rigid != 1:
        raise MechanismError(f"the model has {result.n_rigid} rigid-body modes, not one"
                             + (": bearings or shafts to the housing carry torsion" if result.n_rigid == 0 else ""),
                             result.n_rigid)
    return referred_inertias(model, result.abs_shapes[:, 0])


def referred_cells(model, result=None) -> dict:
    """Cells of the referred-inertia table (``rows`` empty and a ``notes`` line saying why
    when the model has not exactly one rigid-body mode); ``result``: the model's modal
    result, whose rigid-body mode is used when given."""
    header = ["shaft (body)", "J referred [kg m^2]"]
    try:
        J = _inertias(model, result)
    except MechanismError as exc:
        return dict(title=REFERRED_TITLE, header=header, rows=[], left=(0,), notes=[f"no referred inertia: {exc}"])
    return dict(title=REFERRED_TITLE, header=header, rows=[[b, f"{j:.6g}"] for b, j in J.items()], left=(0,),
                notes=[])


def referred_json(model, result=None) -> dict:
    """Body -> referred inertia (kg m^2); empty without a single rigid-body mode."""
    try:
        return _inertias(model, result)
    except MechanismError:
        return {}
