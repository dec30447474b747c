"""A design-study file (TOML): the scene, the analysis per variant, what to keep, the design.

::

    name = "Helix angle"                # optional title
    scene = "kahraman_beta20.toml"      # relative to this file, or a shipped scene
    analysis = "modes"                  # modes | compare | frf | simulate

    [keep]
    modes = 12                          # modes, compare: the first N elastic frequencies (Hz)
    stats = ["peak", "mean"]            # simulate: per output, of mean rms min max peak peak_time_s
    life = true                         # simulate: the life tables' DELs, L10, damage (default: when
                                        #   the scene has [simulation.life])
    passages = true                     # simulate: a run-up's largest amplification per output
                                        #   (the scene's [simulation.drive]; default false)

    [frf]                               # analysis = "frf": as `flexgear frf`
    input = "torque:rotor"
    outputs = ["mesh_force:stage1_sun_p0"]
    fmin = 1.0                          # Hz
    fmax = 500.0                        # Hz
    points = 400
    log = true

    [simulate]                          # analysis = "simulate": as `flexgear simulate`
    t_end = 0.5                         # s
    dt = 1e-4                           # s
    outputs = ["force:stage3"]          # default: every nonlinear mesh's force and stress point

    [design]                            # default: grid
    kind = "lhs"                        # grid | lhs | random
    samples = 50
    seed = 1

    [[parameters]]                      # see assembly.app.study.spec
    path = "meshes[0].helix_angle_deg"
    range = [0.0, 30.0, 31]

Shipped studies are in ``assembly/studies`` and may be named without a folder. Every problem
raises :class:`assembly.errors.SceneError` naming the study field (``frf.fmax``,
``parameters[0].path``) and the value, before any variant runs: every key of every table is
checked by name and TOML type (:mod:`assembly.app.study.keys`); the ``[frf]`` input and
outputs and the ``[simulate]`` outputs are looked up once on the base scene's assembled model
(a name the base scene has but a variant lacks, say a planet's mesh when the planet count
drops, makes that variant an error row); a run of more than :data:`MAX_STEPS` steps
(``t_end / dt``) is refused.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import SceneError
from .keys import check_study
from .spec import Variant, variants

STUDY_DIR = Path(__file__).resolve().parents[2] / "studies"
ANALYSES = ("modes", "compare", "frf", "simulate")
STATS = ("mean", "rms", "min", "max", "peak", "peak_time_s")
#: Most time steps (t_end / dt) of one variant's run. A step of the reduced 5 MW drivetrain
#: costs some 25-50 us compiled and 150-180 us in Python (docs/benchmarks.md), so 1e8 steps are
#: about 1-5 hours per variant; more is a typo (t_end = 1e6 for 1e0) or a run no study can
#: wait for. A 600 s load case at dt = 1e-4 s is 6e6 steps.
MAX_STEPS = 10 ** 8


@dataclass
class Study:
    """A read and checked study: the scene file, the analysis and its settings (SI: Hz, s),
    what to keep, and the variants."""

    name: str
    scene: str                      # the scene file (absolute path)
    analysis: str
    settings: dict
    keep: dict
    variants: list[Variant]
    source: str = ""                # the study file
    parameters: list[str] = field(default_factory=list)   # the parameters' column names


def resolve_study_path(path) -> Path:
    """``path`` if it exists, else a shipped study of that bare name (``.toml`` optional)."""
    p = Path(path)
    if p.exists() or Path(p.name) != p:
        return p
    for cand in (STUDY_DIR / p.name, (STUDY_DIR / p.name).with_suffix(".toml")):
        if cand.exists():
            return cand
    return p


def read_study(path) -> Study:
    """Read, check and expand the study file at ``path`` (module notes)."""
    from ...scene.schema import load_scene, resolve_scene_path
    p = resolve_study_path(path)
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SceneError("study", str(p), f"cannot read: {exc.strerror or exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise SceneError("study", str(p), f"not a valid TOML file: {exc}") from None
    check_study(data)
    title = data.get("name", p.stem)
    scene_name = data.get("scene")
    if not isinstance(scene_name, str) or not scene_name:
        raise SceneError("scene", scene_name, "the scene file to vary (relative to the study file, or a shipped one)")
    local = p.parent / scene_name
    scene_path = local if local.exists() else resolve_scene_path(scene_name)
    scene = load_scene(scene_path)
    analysis = data.get("analysis", "modes")
    if analysis not in ANALYSES:
        raise SceneError("analysis", analysis, f"must be one of {list(ANALYSES)}")
    for other in ("frf", "simulate"):
        if other in data and other != analysis:
            raise SceneError(other, data[other], f"a [{other}] table needs analysis = {other!r}")
    settings = _settings(analysis, data.get(analysis, {}))
    keep = _keep(analysis, data.get("keep", {}), scene)
    vs = variants(scene, {k: data[k] for k in ("parameters", "design") if k in data})
    names = list(vs[0].params)
    check_names(scene, analysis, settings)
    return Study(title, str(Path(scene_path).resolve()), analysis, settings, keep, vs, str(p), names)


def first_reference(study, cache_dir: str | None = None):
    """:func:`tracked_reference` of the first variant the scene takes (a variant it refuses is an
    error row of the study, not a refusal of it); None when it takes none. Solved as a variant is
    (:func:`assembly.app.study.run.run_variant`: one BLAS thread, the study's cache), so that the
    reduced parts it leaves in the cache are bit for bit those a variant would build."""
    import contextlib

    from threadpoolctl import threadpool_limits

    from cms.linsolve import default_backend
    from fe_components.meshing import cache_root

    from ...scene.schema import load_scene
    from ..errors import user_errors
    scene = load_scene(study.scene)
    default_backend()
    for v in study.variants:
        try:
            with threadpool_limits(1), (cache_root(cache_dir) if cache_dir else contextlib.nullcontext()):
                return tracked_reference(scene.with_values(v.values), study.keep)
        except SceneError as exc:
            if exc.path.startswith("keep."):
                raise
        except user_errors():
            pass
    return None


def tracked_reference(scene, keep: dict):
    """The modes a ``modes`` study follows in every variant, those of ``scene`` -- its first
    variant, whose reduced parts the variant then finds in the cache
    (:func:`assembly.analysis.tracking.reference_modes`): the first ``keep["modes"]``, or those of
    ``keep["classes"]`` within ``keep["band_hz"]``; SceneError at ``keep.classes`` when none is."""
    from ...analysis.classify import classify_modes
    from ...analysis.modal import solve_modes
    from ...analysis.tracking import reference_modes
    from ...model.assemble import assemble
    res = solve_modes(assemble(scene))
    labels = [m.mode_class for m in classify_modes(res)[res.n_rigid:]]
    classes = keep.get("classes")
    ref = reference_modes(res, labels, keep["modes"], None if classes is None else set(classes), keep.get("band_hz"))
    if not ref.numbers:
        raise SceneError("keep.classes" if classes is not None else "keep.band_hz",
                         classes if classes is not None else keep.get("band_hz"),
                         f"no mode of the base scene is of these classes in this band (classes: {sorted(set(labels))})")
    return ref


def check_names(scene, analysis: str, settings: dict) -> None:
    """The ``[frf]`` input and outputs, or the ``[simulate]`` outputs, looked up on ``scene``'s
    assembled model once, before any variant runs (SceneError at ``frf.outputs[j]`` ...)."""
    if analysis not in ("frf", "simulate") or (analysis == "simulate" and settings["outputs"] is None):
        return
    from ...model.assemble import assemble
    model = assemble(scene, full_fe=settings.get("unreduced", False))
    if analysis == "frf":
        from ...dynamics.frf_channels import input_channel, output_channels
        input_channel(model, settings["input"], "frf.input")
        for j, name in enumerate(settings["outputs"]):
            output_channels(model, name, f"frf.outputs[{j}]")
        return
    from ...dynamics.run_outputs import recorded_channels
    points = scene.simulation.points if scene.simulation is not None else ()
    for j, name in enumerate(settings["outputs"]):
        recorded_channels(model, points, [name], f"simulate.outputs[{j}]")


def _keep(analysis: str, keep, scene) -> dict:
    allowed = {"modes": {"modes", "track", "classes", "band_hz"}, "compare": {"modes"}, "frf": set(),
               "simulate": {"stats", "life", "passages"}}[analysis]
    for k in keep:
        if k not in allowed:
            raise SceneError(f"keep.{k}", keep[k], f"not kept by analysis {analysis!r}"
                             + (f" (it keeps: {sorted(allowed)})" if allowed else " (it keeps each output's peak)"))
    sim = scene.simulation
    out = {"modes": 10, "stats": ["peak", "mean"], "life": sim is not None and sim.life is not None, "passages": False,
           **keep}
    if out["life"] and (sim is None or sim.life is None):
        raise SceneError("keep.life", True, "the scene has no [simulation.life] table: nothing rates the run")
    if out["passages"] and (sim is None or sim.drive is None):
        raise SceneError("keep.passages", True, "the scene has no [simulation.drive]: a run-up's passages need one")
    if out["modes"] < 1:
        raise SceneError("keep.modes", out["modes"], "must be an integer >= 1")
    out.setdefault("track", analysis == "modes")
    band = out.get("band_hz")
    if band is not None and not (len(band) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                         and math.isfinite(v) and v >= 0 for v in band)
                                 and band[0] < band[1]):
        raise SceneError("keep.band_hz", band, "must be two frequencies [lo, hi] in Hz, 0 <= lo < hi")
    if "classes" in out:
        from ...analysis.classify import MODE_CLASSES
        cl = out["classes"]
        if not isinstance(cl, list) or not cl:
            raise SceneError("keep.classes", cl, f"must be a non-empty list of mode classes {list(MODE_CLASSES)}")
        for j, c in enumerate(cl):
            if c not in MODE_CLASSES:
                raise SceneError(f"keep.classes[{j}]", c, f"not a mode class (classes: {list(MODE_CLASSES)})")
    if ("classes" in out or band is not None) and not out["track"]:
        raise SceneError("keep.track", False, "modes kept by class or band are followed by shape: track = true")
    if any(s not in STATS for s in out["stats"]):
        raise SceneError("keep.stats", out["stats"], f"must be a non-empty list of {list(STATS)}")
    return out


def _number(t: dict, key: str, where: str, default=None, positive=True) -> float:
    v = t.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
        raise SceneError(f"{where}.{key}", v, "must be a finite number" + (" > 0" if positive else ""))
    return float(v)


def _names(t: dict, key: str, where: str, required: bool) -> list | None:
    v = t.get(key)
    if v is None and not required:
        return None
    if not isinstance(v, list) or not v or not all(isinstance(x, str) and x for x in v):
        raise SceneError(f"{where}.{key}", v, "must be a non-empty list of output names")
    return v


def _bands(bands, fmin, fmax) -> list:
    """``[frf] bands``: a list of [lo, hi] (Hz) inside [fmin, fmax], each kept its own peak;
    SceneError at ``frf.bands[i]`` naming the band."""
    if bands is None:
        return []
    out = []
    for i, b in enumerate(bands):
        ok = (isinstance(b, list) and len(b) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                         and math.isfinite(v) for v in b) and b[0] < b[1])
        if not ok:
            raise SceneError(f"frf.bands[{i}]", b, "must be [lo, hi] in Hz, lo < hi")
        if isinstance(fmin, (int, float)) and isinstance(fmax, (int, float)) and not (fmin <= b[0] and b[1] <= fmax):
            raise SceneError(f"frf.bands[{i}]", b, f"must lie in fmin .. fmax = {fmin} .. {fmax} Hz")
        out.append((float(b[0]), float(b[1])))
    return out


def band_label(lo: float, hi: float) -> str:
    """An ``[frf] bands`` entry as its result columns name it: ``peak[OUT][LO-HI Hz]``."""
    return f"{lo:g}-{hi:g} Hz"


def _bands_sampled(s: dict) -> None:
    """Each ``[frf] bands`` entry holds a sample of the frequency grid (a band between two
    samples would have no peak: no column), and no two bands share a column name (their
    ``lo-hi`` as printed); SceneError at ``frf.bands[i]``."""
    if not s["bands"] or s["log"] and s["fmin"] <= 0:
        return
    from ..report.frf import frequencies
    f = frequencies(s["fmin"], s["fmax"], s["points"], s["log"])
    names = {}
    for i, (lo, hi) in enumerate(s["bands"]):
        if not np.any((f >= lo) & (f <= hi)):
            raise SceneError(f"frf.bands[{i}]", [lo, hi], f"holds no frequency of the grid ({s['points']} points "
                             f"from {s['fmin']:g} to {s['fmax']:g} Hz): widen it or add points")
        key = band_label(lo, hi)
        if key in names:
            raise SceneError(f"frf.bands[{i}]", [lo, hi], f"its column name [{key}] is frf.bands[{names[key]}]'s")
        names[key] = i


def _settings(analysis: str, t: dict) -> dict:
    """The analysis's own settings, checked (Hz, s; keys and types by :func:`check_keys`)."""
    if analysis == "frf":
        from ...dynamics.frf import MAX_FREQUENCY_HZ, METHODS, cutoff_check
        if "input" not in t:
            raise SceneError("frf.input", None, "missing: the input, e.g. 'torque:rotor'")
        s = {"input": t["input"], "outputs": _names(t, "outputs", "frf", True),
             "fmin": _number(t, "fmin", "frf", 1.0), "fmax": _number(t, "fmax", "frf"),
             "points": t.get("points", 400), "log": t.get("log", False), "method": t.get("method", "modal"),
             "modes_hz": None if t.get("modes_hz") is None else _number(t, "modes_hz", "frf"),
             "bands": _bands(t.get("bands"), t.get("fmin", 1.0), t.get("fmax"))}
        if s["points"] < 2:
            raise SceneError("frf.points", s["points"], "must be an integer >= 2")
        if not s["fmin"] < s["fmax"]:
            raise SceneError("frf.fmax", s["fmax"], f"must be above fmin = {s['fmin']} Hz")
        _bands_sampled(s)
        if not s["fmax"] < MAX_FREQUENCY_HZ:
            raise SceneError("frf.fmax", s["fmax"], "its angular frequency squared overflows a double")
        if s["method"] not in METHODS:
            raise SceneError("frf.method", s["method"], f"must be one of {list(METHODS)}")
        if s["modes_hz"] is not None and s["method"] != "modal":
            raise SceneError("frf.modes_hz", s["modes_hz"], "the modal cutoff is read by method = 'modal' only")
        if s["modes_hz"] is not None:
            try:                                          # a cutoff that cannot be accurate, before any variant
                cutoff_check(s["modes_hz"], s["fmax"])
            except SceneError as exc:
                raise SceneError("frf.modes_hz", exc.value, exc.reason) from None
        return s
    if analysis == "simulate":
        s = {"t_end": _number(t, "t_end", "simulate"), "dt": _number(t, "dt", "simulate"),
             "outputs": _names(t, "outputs", "simulate", False), "unreduced": t.get("unreduced", False),
             "speed": None if t.get("speed") is None else _number(t, "speed", "simulate", positive=False)}
        if s["dt"] >= s["t_end"]:
            raise SceneError("simulate.dt", s["dt"], f"must be below t_end = {s['t_end']} s")
        steps = s["t_end"] / s["dt"]
        if steps > MAX_STEPS:
            raise SceneError("simulate.dt", s["dt"], f"t_end / dt = {steps:.3g} steps per variant; at most "
                                                     f"{MAX_STEPS:.0e} (a larger dt or a shorter t_end)")
        return s
    return {}
