"""Positions checked against the assembly's size: a unit slip the field ranges cannot see.

The field rules hold every length to the sizes parts are built in
(:mod:`fe_components.sizes`); a position has no such range of its own, but a drivetrain is
a few times longer than its largest gear (the NREL 5 MW: 7 m of shaft line beside a 2.4 m
ring gear; a ship's line 100 m beside a 4 m gear). So every position the scene gives
(bodies, stage centres, bearings, shaft ends, mesh centres, load and stress points) lies
within :data:`POSITION_FACTOR` times the assembly's largest part (gear diameters, stage
envelopes, components, shaft diameters) of the middle of the assembly's other bodies; a
position typed in millimetres where metres belong lies far outside. A position 1000 x too
small is a plausible place and cannot be told from one.
"""
from __future__ import annotations

import numpy as np

from fe_components.params import CarrierParams, CylinderParams, PinionParams, WheelParams

from ..errors import SceneError

#: Positions lie within this many times the largest part of the assembly from its middle.
POSITION_FACTOR = 100.0


def part_size(body) -> float:
    """The largest dimension (m) of a body's gear or component, 0 if it gives none."""
    sizes = []
    if body.teeth is not None:
        sizes.append(2 * body.teeth.pitch_radius)
    c = body.component
    if isinstance(c, (PinionParams, WheelParams)):
        sizes.append(2 * c.teeth.tip_radius)
    if isinstance(c, PinionParams):
        sizes.append(c.length)
    if isinstance(c, CarrierParams):
        sizes.append(c.cheek_diameter)
    if isinstance(c, CylinderParams):
        sizes += [c.length, c.diameter]
    return max(sizes, default=0.0)


def assembly_size(scene) -> float:
    """The largest part of the scene (m): gear diameters (base radii typed or derived,
    teeth), stage envelopes and carriers, components, beam shaft diameters; 0 for a scene of
    springs and masses alone."""
    sizes = [part_size(b) for b in scene.bodies]
    sizes += [2 * abs(r) for m in scene.meshes for r in (m.base_radius1, m.base_radius2) if r is not None]
    for st in scene.stages:
        if None not in (st.sun.base_radius, st.planets.base_radius, st.pressure_angle_sun):
            sizes.append(2 * (st.carrier_radius() + st.planets.base_radius))
        if isinstance(st.carrier.component, CarrierParams):
            sizes.append(st.carrier.component.cheek_diameter)
    sizes += [s.diameter for s in scene.shafts if s.diameter is not None]
    return max(sizes, default=0.0)


def typed_positions(scene):
    """(path, position as written, the body it places or None) of every point the
    scene's tables give."""
    given = {"bodies": scene.as_given("bodies"), "stages": scene.as_given("stages"), "meshes": scene.as_given("meshes")}
    for key, attrs in (("bodies", ("position",)), ("stages", ("center",)), ("bearings", ("position",)),
                       ("shafts", ("position", "position1", "position2")), ("meshes", ("center1", "center2"))):
        for i, item in enumerate(given.get(key, getattr(scene, key))):
            for a in attrs:
                if getattr(item, a, None) is not None:
                    yield f"{key}[{i}].{a}", getattr(item, a), (key, i) if key in ("bodies", "stages") else None
    for path, lc in scene.load_cases():
        for j, pl in enumerate(lc.forces):
            if pl.point is not None:
                yield f"{path}.forces[{j}].point", pl.point, None
    if scene.simulation is not None:
        for j, p in enumerate(scene.simulation.points):
            yield f"simulation.points[{j}].point", p.point, None


def column_median(a: np.ndarray) -> np.ndarray:
    """Median of each column of ``a`` (rows >= 1), the very numbers of ``np.median(a,
    axis=0)`` (the middle row of the sorted columns, or the mean of the middle two): NumPy's
    median imports numpy.ma on its first call, 25 ms of a 0.3 s ``flexgear modes``."""
    s = np.sort(a, axis=0)
    n = len(s)
    return s[n // 2] if n % 2 else (s[n // 2 - 1] + s[n // 2]) / 2.0


def positions_plausible(scene) -> None:
    """Every position the scene gives lies within POSITION_FACTOR x the assembly's largest
    part of the median of the bodies' positions (the scene's bodies and its stages'
    centres, without the body the position places); skipped for a scene without part
    sizes. Of the positions out of reach, the one whose millimetre reading fits is refused
    (with that reading), else the farthest."""
    size = assembly_size(scene)
    if size <= 0:
        return
    limit = POSITION_FACTOR * size
    places = {("bodies", i): b.position for i, b in enumerate(scene.bodies)}
    places.update({("stages", i): st.center or (0.0, 0.0, 0.0) for i, st in enumerate(scene.stages)})
    out = []
    for path, p, owner in typed_positions(scene):
        others = [q for k, q in places.items() if k != owner]
        if not others:
            continue
        middle = column_median(np.array(others, float))
        d = float(np.linalg.norm(np.asarray(p, float) - middle))
        if d > limit:
            mm = np.asarray(p, float) * 1e-3
            out.append((bool(np.linalg.norm(mm - middle) <= limit), d, path, p, middle))
    if not out:
        return
    fits, d, path, p, middle = max(out, key=lambda t: t[:2])
    hint = f"; did you mean mm ({[float(f'{v * 1e-3:.9g}') for v in p]} m)?" if fits else ""
    raise SceneError(path, list(p), f"{d:.4g} m from the middle of the assembly's other bodies "
                                    f"({[float(f'{v:.6g}') for v in middle]} m), more than {POSITION_FACTOR:g} x "
                                    f"its largest part ({size:.4g} m across): a length in the wrong unit{hint}")
