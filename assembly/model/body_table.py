"""The mass properties every body of an assembled model has, and where each comes from.

A body's mass, polar and transverse inertia (about its centre of mass: the polar about its
axis, the transverse the mean of the two normal to it) and centre of mass are the model's
own numbers (:class:`assembly.model.bodies.RigidBodyModel`, a flexible body's superelement),
each with its source: ``typed`` (the scene's numbers), ``gear blank`` (from the teeth,
:func:`fe_components.gear_blank.blank_mass_properties`), ``polar/2`` (a transverse inertia
left out), ``FE mesh`` (a built-in component or a mesh file, integrated over its elements),
``STEP/CAD`` (a CAD part, meshed), ``beam shaft`` (a station's lumped share of its shaft)
and, for the centre of mass of a plain body, ``position``.

A component body may also type mass and inertias: the values the mesh replaces (a rigid
body made flexible keeps the numbers it had). They are never used; :func:`replaced` gives
them beside the mesh's with the relative difference, and :func:`replaced_note` says so in
one line, so that 60 kg typed becoming 30.9 kg of mesh is never silent.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene.paths import body_origins

#: Mass properties of a component that differ from the typed ones by more than this
#: (relative) are reported as replaced: a P2 mesh of curved surfaces holds its volume to
#: about 1e-3 (tests/fe_components/test_fe_validation.py), CAD-exact numbers agree to that.
AGREEMENT = 1e-3
QUANTITIES = ("mass", "polar_inertia", "transverse_inertia")


@dataclass(frozen=True)
class BodyMass:
    """One body's mass properties as the model uses them (kg, kg m^2, m; global centre of
    mass), the scene table that made it, the source of each (``sources``: quantity ->
    source, for mass, polar_inertia, transverse_inertia and center_of_mass) and, for a
    component body that typed them, the typed values the mesh replaced (``typed``)."""

    name: str
    path: str
    mass: float
    polar_inertia: float
    transverse_inertia: float
    center_of_mass: tuple
    sources: dict
    typed: dict

    @property
    def source(self) -> str:
        """The sources in one phrase: ``"FE mesh"``, or ``"gear blank (transverse: typed)"``
        where an inertia has another one (the centre of mass of a plain body is its position)."""
        main = self.sources["mass"]
        other = [f"{q.removesuffix('_inertia')}: {s}" for q, s in self.sources.items()
                 if s != main and q != "center_of_mass"]
        return main + (f" ({', '.join(other)})" if other else "")

    def differences(self) -> dict:
        """Quantity -> relative difference (model / typed - 1) of the typed values."""
        return {q: getattr(self, q) / v - 1.0 for q, v in self.typed.items()}

    def as_dict(self) -> dict:
        return {"body": self.name, "path": self.path, "mass_kg": self.mass, "polar_inertia_kgm2": self.polar_inertia,
                "transverse_inertia_kgm2": self.transverse_inertia, "center_of_mass_m": list(self.center_of_mass),
                "source": self.sources, "typed": self.typed, "relative_difference": self.differences()}


def _component_source(component) -> str:
    from fe_components.part.file import PartFile
    if isinstance(component, PartFile) and not component.is_mesh:
        return "STEP/CAD"
    return "FE mesh"


def _typed(b) -> dict:
    """The mass properties a body's table types: mass, polar and transverse inertia (from
    an inertia tensor: its axis entry and the mean of the other two)."""
    out = {}
    if b.mass is not None:
        out["mass"] = float(b.mass)
    if b.inertia_tensor is not None:
        J = np.asarray(b.inertia_tensor, float)
        out["polar_inertia"] = float(J[2, 2])
        out["transverse_inertia"] = 0.5 * float(J[0, 0] + J[1, 1])
    else:
        if b.polar_inertia is not None:
            out["polar_inertia"] = float(b.polar_inertia)
        if b.transverse_inertia is not None:
            out["transverse_inertia"] = float(b.transverse_inertia)
    return out


def _given(src, origin: dict) -> dict:
    """Body name -> the table as written that made it (a body, a stage member or planets
    table, None for a shaft's station)."""
    out = {b.name: b for b in src.as_given("bodies")}
    for name, path in origin.items():
        if path.startswith("stages["):
            i = int(path[len("stages["):path.index("]")])
            out[name] = getattr(src.as_given("stages")[i], path.rsplit(".", 1)[1])
    return out


def _plain_sources(b, given) -> dict:
    """Sources of a body without component: typed numbers, or its gear blank's."""
    if b.role == "station":
        return dict.fromkeys(QUANTITIES, "beam shaft") | {"center_of_mass": "beam shaft"}
    blank = given is not None and given.mass is None and getattr(given, "inertia_tensor", None) is None
    base = "gear blank" if blank else "typed"
    trans = "typed" if given is not None and given.transverse_inertia is not None else (
        base if blank or b.inertia_tensor is not None else "polar/2")
    return {"mass": base, "polar_inertia": base, "transverse_inertia": trans, "center_of_mass": "position"}


def body_properties(model) -> tuple[BodyMass, ...]:
    """A :class:`BodyMass` per body of ``model``, in the model's order."""
    src = model.source if model.source is not None else model.scene
    exp = src.expanded()
    origin = body_origins(src, exp)
    given = _given(src, origin)
    scene_bodies = {b.name: b for b in model.scene.bodies}
    out = []
    for name, bm in model.bodies.items():
        b = scene_bodies[name]
        a = np.asarray(bm.axes, float)[:, 2]
        J = np.asarray(bm.inertia, float)
        polar = float(a @ J @ a)
        if b.component is not None:
            s = _component_source(b.component)
            sources = dict.fromkeys(QUANTITIES, s) | {"center_of_mass": s}
            typed = _typed(b)
        else:
            sources, typed = _plain_sources(b, given.get(name)), {}
        out.append(BodyMass(name, origin.get(name, name), float(bm.mass), polar, 0.5 * (float(np.trace(J)) - polar),
                            tuple(float(x) for x in bm.position), sources, typed))
    return tuple(out)


def replaced(rows) -> list:
    """The rows whose typed mass properties differ from the model's (a component's mesh) by
    more than AGREEMENT."""
    return [r for r in rows if any(abs(d) > AGREEMENT for d in r.differences().values())]


def replaced_note(row: BodyMass) -> str:
    """One line: the typed values of a body and the ones its mesh gives instead."""
    parts = [f"{q} {v:.6g} -> {getattr(row, q):.6g} {'kg' if q == 'mass' else 'kg m^2'} "
             f"({100 * row.differences()[q]:+.1f} %)" for q, v in row.typed.items()]
    return (f"body {row.name!r} ({row.path}): its {row.sources['mass']} replaces the typed mass properties: "
            f"{', '.join(parts)}; the model uses the {row.sources['mass']}'s")
