"""Every number and name of a scene is checked against the rule declared on its field
before anything uses it: one SceneError naming the exact field path, fast, and with no
meshing -- for every numeric field of every scene table and of every component kind, for
TOML tables and for dataclasses built in Python alike.

The sweeps enumerate the fields from the dataclasses themselves, and a coverage test
checks that the enumeration reaches every numeric field, so a field added later without a
rule, or out of reach of the sweep, fails here.
"""
import copy
import dataclasses
import math
import time
import tomllib
import types
import typing

import pytest

from assembly.errors import SceneError
from assembly.scene.schema import SCENE_DIR, component_from_table, scene_from_dict
from assembly.scene.tables import (
    MAX_MODES,
    MAX_NAME_LENGTH,
    Bearing,
    BearingSpec,
    Body,
    FlexOptions,
    GearMesh,
    LoadCase,
    Member,
    PlanetaryStage,
    Planets,
    Scene,
    Shaft,
)
from fe_components.errors import GeometryError
from fe_components.material import Material
from fe_components.params import COMPONENT_KINDS, CarrierParams, GearTeeth, ShaftSegment

#: Values tried on every numeric field. The first six are never admissible anywhere
#: (not a real number, NaN, -inf, beyond the largest physical magnitude 1e100 of
#: fe_components.fields); +inf only where a field admits a rigid direction; 0 and -1
#: wherever the field's declared range excludes them.
NEVER = [math.nan, -math.inf, 1e300, -1e300, "1.0", True]
BAD = NEVER + [math.inf, 0.0, -1.0]
#: A scene validates in about 1-2 ms; a bad value must not take longer than this to refuse
#: (no meshing, no solve: a NaN used to hang in gmsh for minutes).
FAST_S = 2.0

SCENE_CLASSES = (Scene, Body, Bearing, GearMesh, Shaft, Member, Planets, BearingSpec, PlanetaryStage,
                 LoadCase, FlexOptions, Material)
PARAM_CLASSES = tuple(COMPONENT_KINDS.values()) + (GearTeeth, ShaftSegment)


def _toml(name):
    return tomllib.loads((SCENE_DIR / name).read_text())


#: A flexible cylinder on two bearings: the one component kind no shipped scene uses.
CYLINDER_SCENE = {
    "band_hz": 3000.0,
    "bodies": [{"name": "rod", "fidelity": "flexible",
                "component": {"kind": "cylinder", "length": 0.5, "diameter": 0.05}}],
    "bearings": [{"body": "rod", "interface": end, "k_radial": 1e9, "k_axial": 1e9, "k_tilt": 1e5}
                 for end in ("end_a", "end_b")],
}


def _bases():
    hs = _toml("hs_parallel_stage.toml")
    hs["bodies"][0]["flex"]["material"] = {"E": 2.1e11, "nu": 0.3, "rho": 7850.0}  # reach Material too
    comp = hs["bodies"][0]["component"]  # shaft steps as tables, so a field can be set by name
    comp["shaft"] = [{"length": a, "diameter": d} for a, d in comp["shaft"]]
    step = _toml("planetary_step_carrier.toml")   # its part file by absolute path (no scene folder here)
    comp = step["stages"][0]["carrier"]["component"]
    comp["file"] = str(SCENE_DIR / comp["file"])
    return {"kahraman_beta0.toml": _toml("kahraman_beta0.toml"), "hs_parallel_stage.toml": hs,
            "planetary_step_carrier.toml": step,
            "planetary_flexible_carrier.toml": _toml("planetary_flexible_carrier.toml"),
            "lin_parker_n3.toml": _toml("lin_parker_n3.toml"), "cylinder": CYLINDER_SCENE}


BASES = _bases()


@pytest.fixture(autouse=True)
def no_gmsh(monkeypatch):
    """Validation must never mesh."""
    import fe_components.meshing

    def fail(*a, **k):
        raise AssertionError("gmsh called during validation")
    monkeypatch.setattr(fe_components.meshing, "generate_mesh", fail)


def _bare(tp):
    """The type inside Optional[...]."""
    if typing.get_origin(tp) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(tp) if a is not type(None)]
        return args[0] if len(args) == 1 else tp
    return tp


def _path(keys) -> str:
    out = ""
    for k in keys:
        out += f"[{k}]" if isinstance(k, int) else (f".{k}" if out else k)
    return out


def _get(tree, keys):
    for k in keys:
        tree = tree[k]
    return tree


# ---------------------------------------------------------------- enumeration
def _sites(cls, data, keys=()):
    """(keys, class, field, type) of every ruled field of ``cls`` reachable in the table
    ``data`` (absent optional fields included: they are set to the bad value)."""
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(cls):
        tp = _bare(hints[f.name])
        if "quantity" in f.metadata:
            yield keys + (f.name,), cls, f, tp
        elif dataclasses.is_dataclass(tp) and isinstance(data.get(f.name), dict):
            yield from _sites(tp, data[f.name], keys + (f.name,))
        elif typing.get_origin(tp) is tuple and dataclasses.is_dataclass(typing.get_args(tp)[0]):
            for i, item in enumerate(data.get(f.name) or []):
                if isinstance(item, dict):
                    yield from _sites(typing.get_args(tp)[0], item, keys + (f.name, i))


def _scene_sites():
    """One site per (class, field) of the scene tables, over the base scenes."""
    seen, out = set(), []
    for name, tree in BASES.items():
        for keys, cls, f, tp in _sites(Scene, tree):
            if (cls, f.name) not in seen:
                seen.add((cls, f.name))
                out.append((name, keys, cls, f, tp))
    return out


SCENE_SITES = _scene_sites()

#: kind -> (base scene, keys of its component table)
COMPONENT_TABLES = {"pinion": ("hs_parallel_stage.toml", ("bodies", 0, "component")),
                    "wheel": ("hs_parallel_stage.toml", ("bodies", 1, "component")),
                    "carrier": ("planetary_flexible_carrier.toml", ("stages", 0, "carrier", "component")),
                    "cylinder": ("cylinder", ("bodies", 0, "component")),
                    "file": ("planetary_step_carrier.toml", ("stages", 0, "carrier", "component"))}
#: set by the planetary stage from its planets (giving them is an error of its own)
STAGE_SET = {"planet_angles", "pin_pitch_radius"}
#: what the stage adds to the carrier table (lin_parker_n3: R_c = (0.0387 + 0.0502) / cos 24.6 deg)
_STAGE_PLACED = {"carrier": {"n_planets": 3, "pin_pitch_radius": 0.0889 / math.cos(math.radians(24.6))}}


def _component_sites():
    out = []
    for kind, (base, keys) in COMPONENT_TABLES.items():
        table = _get(BASES[base], keys)
        data = {"teeth": table.get("teeth", {}), "shaft": [{}] * len(table.get("shaft", []))}
        for sub, cls, f, tp in _sites(COMPONENT_KINDS[kind], data):
            if sub[-1] not in STAGE_SET and (not sub[:1] == ("shaft",) or sub[1] == 1):  # one shaft step
                out.append((kind, base, keys, sub, cls, f))
    return out


COMPONENT_SITES = _component_sites()


def _has_float(tp) -> bool:
    return tp is float or any(_has_float(a) for a in typing.get_args(tp))


def test_every_numeric_field_has_a_rule_and_is_swept():
    # a float field without a declared unit and range would be checked by nothing
    for cls in SCENE_CLASSES + PARAM_CLASSES:
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            if _has_float(hints[f.name]):
                assert "quantity" in f.metadata, f"{cls.__name__}.{f.name} has no rule"
    ruled = {(c, f.name) for c in SCENE_CLASSES for f in dataclasses.fields(c) if "quantity" in f.metadata}
    assert {(c, f.name) for _, _, c, f, _ in SCENE_SITES} == ruled
    comp = {(c, f.name) for c in PARAM_CLASSES for f in dataclasses.fields(c) if "quantity" in f.metadata}
    swept = {(c, f.name) for *_, c, f in COMPONENT_SITES} | {(CarrierParams, n) for n in STAGE_SET}
    assert swept == comp


# ---------------------------------------------------------------- outcome check
def _refusable(rule, value) -> bool:
    """Whether ``value`` must be refused: never a real number of physical magnitude
    (a string, a bool, NaN, -inf, |x| > 1e100); +inf unless the field admits a rigid
    direction; otherwise as the field's declared range says."""
    if isinstance(value, (str, bool)) or math.isnan(value) or value == -math.inf or 1e100 < abs(value) < math.inf:
        return True
    if value == math.inf:
        return not rule.inf_ok
    return rule.problem(value) is not None


def _check(build, path, value, rule, errors=(SceneError,)):
    t0 = time.perf_counter()
    try:
        build()
        err = None
    except errors as exc:
        err = exc
    dt = time.perf_counter() - t0
    assert dt < FAST_S, (path, value, dt)
    if _refusable(rule, value):
        assert err is not None, f"{path} = {value!r} accepted"
        if isinstance(err, SceneError):
            assert err.path == path, (path, value, str(err))
        else:  # a self-checking type built in Python (Material) names its own field
            assert err.parameter == path.rsplit(".", 1)[-1], (path, value, str(err))
        assert "\n" not in str(err)
    return err


# ---------------------------------------------------------------- component tables
def _set_value(node, key, value):
    node[key] = value
    node.pop(f"{key}_deg", None)


@pytest.mark.parametrize("kind,base,keys,sub,cls,f", COMPONENT_SITES,
                         ids=[f"{s[0]}.{_path(s[3])}" for s in COMPONENT_SITES])
def test_component_field_refused_before_meshing(kind, base, keys, sub, cls, f):
    rule = f.metadata["quantity"]
    prefix = _path(keys)
    for value in BAD:
        tree = copy.deepcopy(BASES[base])
        node = _get(tree, keys + sub[:-1])
        _set_value(node, sub[-1], value)
        err = _check(lambda: scene_from_dict(tree), f"{prefix}.{_path(sub)}", value, rule)
        if err is not None:  # an admissible value may still break a relation of this part,
            # or of its teeth with the teeth of the gear it meshes with (the message names both)
            assert err.path.startswith(prefix) or f"{prefix}." in err.reason, str(err)
        if err is not None and len(sub) == 1 and _refusable(rule, value):
            # one rule: the part built in Python (fe_components alone) gives the same reason
            valid = component_from_table(_get(BASES[base], keys) | _STAGE_PLACED.get(kind, {}), "c")
            with pytest.raises(GeometryError) as direct:
                dataclasses.replace(valid, **{sub[0]: value})
            if typing.get_origin(_bare(typing.get_type_hints(cls)[sub[0]])) is tuple:
                # a point (a part file's axis) given one number: refused on the same field, by
                # its shape or by the number's rule, whichever the path checks first
                assert direct.value.parameter == sub[0]
            else:
                assert (direct.value.parameter, direct.value.reason) == (sub[0], err.reason)


# ---------------------------------------------------------------- scene tables
def _array_with(value, tp, old):
    """An array of the field's shape with ``value`` first (the old array if given)."""
    if old is not None:
        arr = copy.deepcopy(list(old))
    elif typing.get_args(tp)[-1] is Ellipsis:
        arr = [0.0, 0.0, 0.0]
    else:
        arr = [[1.0 * (i == j) for j in range(3)] for i in range(3)] if "tuple[float" in str(typing.get_args(tp)[0]) \
            else [0.0, 0.0, 1.0]
    if isinstance(arr[0], list):
        arr[0] = [value] + list(arr[0][1:])
        return arr, "[0][0]"
    arr[0] = value
    return arr, "[0]"


def _toml_mutation(base, keys, tp, value):
    tree = copy.deepcopy(BASES[base])
    node = _get(tree, keys[:-1])
    suffix = ""
    if typing.get_origin(tp) is tuple:
        value, suffix = _array_with(value, tp, node.get(keys[-1]))
    _set_value(node, keys[-1], value)
    return tree, suffix


def _replace_at(obj, keys, value):
    if not keys:
        return value
    k = keys[0]
    if isinstance(k, int):
        items = list(obj)
        items[k] = _replace_at(items[k], keys[1:], value)
        return tuple(items)
    return dataclasses.replace(obj, **{k: _replace_at(getattr(obj, k), keys[1:], value)})


@pytest.mark.parametrize("base,keys,cls,f,tp", SCENE_SITES, ids=[f"{s[2].__name__}.{s[3].name}" for s in SCENE_SITES])
def test_scene_field_refused_in_toml_and_python(base, keys, cls, f, tp):
    rule = f.metadata["quantity"]
    valid = scene_from_dict(copy.deepcopy(BASES[base]))
    for value in BAD:
        tree, suffix = _toml_mutation(base, keys, tp, value)
        from_toml = _check(lambda: scene_from_dict(tree), _path(keys) + suffix, value, rule)
        # the same value through the constructors (a Material checks itself when built)
        new = _get(tree, keys) if suffix else value
        new = tuple(tuple(x) if isinstance(x, list) else x for x in new) if suffix else new
        from_python = _check(lambda: _replace_at(valid, keys, new), _path(keys) + suffix, value, rule,
                             errors=(SceneError, GeometryError))
        if _refusable(rule, value):  # one rule, one message
            assert from_toml.reason == from_python.reason, (str(from_toml), str(from_python))


@pytest.mark.parametrize("base,keys,cls,f,tp", [s for s in SCENE_SITES if s[3].metadata.get("angle")],
                         ids=[f"{s[2].__name__}.{s[3].name}" for s in SCENE_SITES if s[3].metadata.get("angle")])
def test_angle_in_degrees_refused_under_its_own_key(base, keys, cls, f, tp):
    # a value given in degrees is reported under the key and in the unit it was written in
    rule = f.metadata["quantity"]
    for value in NEVER:
        tree = copy.deepcopy(BASES[base])
        node = _get(tree, keys[:-1])
        node.pop(keys[-1], None)
        if typing.get_origin(tp) is tuple:
            node[f"{keys[-1]}_deg"] = [value, 120.0, 240.0]
            path = _path(keys) + "_deg[0]"
        else:
            node[f"{keys[-1]}_deg"] = value
            path = _path(keys) + "_deg"
        _check(lambda: scene_from_dict(tree), path, value, rule)


# ---------------------------------------------------------------- names
NAME_SITES = [("kahraman_beta0.toml", ("name",)), ("kahraman_beta0.toml", ("bodies", 0, "name")),
              ("kahraman_beta0.toml", ("bearings", 0, "name")), ("kahraman_beta0.toml", ("meshes", 0, "name")),
              ("hs_parallel_stage.toml", ("shafts", 0, "name")), ("hs_parallel_stage.toml", ("load", "name")),
              ("lin_parker_n3.toml", ("stages", 0, "name"))]
#: NUL, a newline, an escape, a zero-width format character, path separators, too long, empty
BAD_NAMES = ["a\x00b", "a\nb", "\x1b[31mred", "a\u200bb", "a/b", "a\\b", "x" * (MAX_NAME_LENGTH + 1), "x" * 300, ""]


@pytest.mark.parametrize("base,keys", NAME_SITES, ids=[_path(k) for _, k in NAME_SITES])
def test_bad_names_refused(base, keys):
    valid = scene_from_dict(copy.deepcopy(BASES[base]))
    for name in BAD_NAMES:
        tree = copy.deepcopy(BASES[base])
        _get(tree, keys[:-1])[keys[-1]] = name
        for build in (lambda: scene_from_dict(tree), lambda: _replace_at(valid, keys, name)):
            with pytest.raises(SceneError) as e:
                build()
            assert e.value.path == _path(keys) and e.value.value == name
    if keys[0] != "bodies":  # (renaming a body breaks the references to it)
        tree = copy.deepcopy(BASES[base])
        _get(tree, keys[:-1])[keys[-1]] = "low-speed stage 2, \u00e9t\u00e9"  # spaces, non-ASCII: fine
        scene_from_dict(tree)


# ---------------------------------------------------------------- Craig-Bampton bounds
def _flex_tree(base, keys, **flex):
    tree = copy.deepcopy(BASES[base])
    node = _get(tree, keys)
    node["flex"] = {**node.get("flex", {}), **flex}
    return tree


@pytest.mark.parametrize("base,keys,who", [("hs_parallel_stage.toml", ("bodies", 0), "pinion"),
                                           ("hs_parallel_stage.toml", ("bodies", 1), "wheel"),
                                           ("planetary_flexible_carrier.toml", ("stages", 0, "carrier"),
                                            "stage.carrier")])
def test_unbounded_cutoff_refused_naming_the_body(base, keys, who):
    # A 1 GHz cutoff would keep every interior mode of the mesh (about 2.4 GB on the HS
    # pinion): refused at once, by Weyl's count on the part's volume, before meshing.
    t0 = time.perf_counter()
    with pytest.raises(SceneError) as e:
        scene_from_dict(_flex_tree(base, keys, cutoff_hz=1e9))
    assert e.value.path == _path(keys) + ".flex.cutoff_hz" and who in str(e.value)
    tree = copy.deepcopy(BASES[base])
    tree["band_hz"] = 1e9  # the default cutoff is CB_CUTOFF_FACTOR x band
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    first = "stage.carrier" if "planetary" in base else "pinion"  # the first flexible body
    assert e.value.path == "band_hz" and first in str(e.value)
    with pytest.raises(SceneError) as e:
        scene_from_dict(_flex_tree(base, keys, n_modes=MAX_MODES + 1))
    assert e.value.path == _path(keys) + ".flex.n_modes"
    scene_from_dict(_flex_tree(base, keys, n_modes=MAX_MODES))  # the bound itself is allowed
    assert time.perf_counter() - t0 < 10.0


def test_couplings_must_name_interfaces():
    tree = _flex_tree("hs_parallel_stage.toml", ("bodies", 0), couplings={"bearing_c": "rbe2"})
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "bodies[0].flex.couplings" and e.value.value == "bearing_c"


# ---------------------------------------------------------------- planets and the Python API
def test_planet_outer_radius_keeps_the_overlap_check():
    # outer_radius <= 0 used to switch the overlap check off (40 planets solved)
    tree = copy.deepcopy(BASES["lin_parker_n3.toml"])
    pl = tree["stages"][0]["planets"]
    pl.update(count=40, outer_radius=-1.0)
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "stages[0].planets.outer_radius"
    pl["outer_radius"] = pl["base_radius"]  # a tip radius at the base circle cannot be
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "stages[0].planets.outer_radius"
    pl.pop("outer_radius")
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "stages[0].planets.count" and "overlap" in str(e.value)


@pytest.mark.parametrize("build,path", [
    (lambda: Scene(bodies=(Body(name=3),)), "bodies[0].name"),
    (lambda: Scene(bodies=(Body("a", 1.0, polar_inertia=1e-3),),
                   bearings=(Bearing(body="a", k_radial="1e8", k_axial=1e8, k_tilt=1e5),)), "bearings[0].k_radial"),
    (lambda: Scene(bodies=[[1, 2]]), "bodies[0]"),
    (lambda: Scene(bodies=({"name": "a"},)), "bodies[0]"),
    (lambda: Scene(bodies=(Body("a", 1.0, polar_inertia=1e-3, fidelity="bogus"),)), "bodies[0].fidelity"),
    (lambda: Scene(bodies=(Body("a", 1.0, polar_inertia=1e-3, flex=FlexOptions(order=True)),)), "bodies[0].flex.order"),
    (lambda: Scene(band_hz="3000"), "band_hz"),
])
def test_python_api_wrong_types_name_the_field(build, path):
    with pytest.raises(SceneError) as e:
        build()
    assert e.value.path == path


def test_python_api_lists_are_accepted():
    b = Body("a", 1.0, polar_inertia=1e-3, position=[0.0, 0.0, 0.1])
    sc = Scene(bodies=[b], bearings=[Bearing("a", 1e8, 1e8, 1e5)])
    assert isinstance(sc.bodies, tuple) and isinstance(sc.bearings, tuple)
    assert sc.expanded() is sc


def test_huge_axis_refused_and_unit_vector_safe():
    import numpy as np

    from assembly.mechanics.kinematics import unit
    # 1e200 squared overflows: the norm of the raw vector would be inf
    np.testing.assert_allclose(unit([1e200, 0.0, 1e200]), [2 ** -0.5, 0.0, 2 ** -0.5], rtol=1e-15)
    np.testing.assert_allclose(unit([1e-200, 0.0, 0.0]), [1.0, 0.0, 0.0], rtol=1e-15)
    tree = copy.deepcopy(BASES["kahraman_beta0.toml"])
    tree["bodies"][0]["axis"] = [1e200, 0.0, 1e200]
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "bodies[0].axis[0]"


# ---------------------------------------------------------------- API entry points
def test_with_fidelity_refuses_unknown_fidelity_and_bodies():
    from assembly.scene.tables import with_fidelity
    sc = scene_from_dict(copy.deepcopy(BASES["kahraman_beta0.toml"]))
    for bad in ("bogus", "Rigid", None, 1):
        with pytest.raises(SceneError) as e:
            with_fidelity(sc, bad)
        assert e.value.path == "fidelity" and "torsional" in str(e.value)
    with pytest.raises(SceneError) as e:
        with_fidelity(sc, "torsional", bodies=["pinion", "gearbox"])
    assert e.value.path == "bodies" and e.value.value == "gearbox"
    # one name is one body (not the substrings of a string)
    one = with_fidelity(sc, "torsional", bodies="pinion")
    assert [b.fidelity for b in one.bodies] == ["torsional", "rigid"]


def test_solve_modes_n_modes_checked():
    from assembly.analysis.modal import solve_modes
    from assembly.model.assemble import assemble
    model = assemble(scene_from_dict(copy.deepcopy(BASES["kahraman_beta0.toml"])))
    n = model.K.shape[0]  # 12: two rigid bodies of six DOFs
    for bad in (0, -1, 1.5, True, "3"):
        with pytest.raises(SceneError) as e:
            solve_modes(model, n_modes=bad)
        assert e.value.path == "n_modes"
    assert len(solve_modes(model, n_modes=3).frequencies_hz) == 3
    assert len(solve_modes(model, n_modes=10 * n).frequencies_hz) == n  # more than there are: all


def test_derived_scenes_keep_stage_paths():
    # with_fidelity and scale_bearings keep planetary stages as stages, so an error of the
    # derived scene names the user's table (it used to name bodies[2] of an expanded copy)
    from assembly.scene.tables import scale_bearings, with_fidelity
    tree = _flex_tree("planetary_flexible_carrier.toml", ("stages", 0, "carrier"), cutoff_hz=1e9)
    tree["stages"][0]["carrier"]["fidelity"] = "rigid"  # (a rigid carrier is not reduced: valid)
    sc = scene_from_dict(tree)
    with pytest.raises(SceneError) as e:
        with_fidelity(sc, "flexible", bodies=["stage.carrier"])
    assert e.value.path == "stages[0].carrier.flex.cutoff_hz"
    lp = scene_from_dict(copy.deepcopy(BASES["lin_parker_n3.toml"]))
    tors = with_fidelity(lp, "torsional")
    assert tors.stages and {b.fidelity for b in tors.expanded().bodies} == {"torsional"}
    some = with_fidelity(lp, "torsional", bodies=["stage.planet0"])  # splits the planets: expanded
    assert not some.stages and [b.fidelity for b in some.bodies if b.role == "planet"] == \
        ["torsional", "rigid", "rigid"]
    stiff = scale_bearings(lp, 10.0, ("k_radial",))
    assert stiff.stages[0].planets.bearing.k_radial == 10 * lp.stages[0].planets.bearing.k_radial
    for bad in (0.0, -1.0, math.nan, math.inf, "2", True):
        with pytest.raises(SceneError) as e:
            scale_bearings(lp, bad)
        assert e.value.path == "factor"
    with pytest.raises(SceneError) as e:
        scale_bearings(lp, 2.0, ("k_radial", "mass"))
    assert e.value.path == "directions" and e.value.value == "mass"


def test_stage_member_bearing_interface_named_as_written():
    tree = copy.deepcopy(BASES["planetary_flexible_carrier.toml"])
    tree["stages"][0]["carrier"]["bearing_interface"] = "bearing_c"
    with pytest.raises(SceneError) as e:
        scene_from_dict(tree)
    assert e.value.path == "stages[0].carrier.bearing_interface" and e.value.value == "bearing_c"


def test_numpy_values_accepted_from_python():
    # numpy numbers and arrays are numbers and arrays (a NaN inside one is still refused)
    import numpy as np
    b = Body("a", np.float64(1.0), polar_inertia=1e-3, position=np.array([0.0, 0.0, 0.1]))
    sc = Scene(bodies=(b,), bearings=(Bearing("a", 1e8, 1e8, np.int64(100000)),))
    assert sc.bodies[0].mass == 1.0
    with pytest.raises(SceneError) as e:
        Scene(bodies=(dataclasses.replace(b, position=np.array([0.0, np.nan, 0.1])),), bearings=sc.bearings)
    assert e.value.path == "bodies[0].position[1]"
