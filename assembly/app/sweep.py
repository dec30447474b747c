"""``flexgear sweep SCENE.toml --param helix|bearing-factor --values ... --out DIR``.

Natural frequencies against one scene parameter (as Peeters et al., Wind Energy 9 (2006),
Figs. 7 and 11a):

* ``helix``: helix angle (values in deg; stored in rad) of every helical gear (spur gears
  stay spur), set by path (:meth:`assembly.scene.Scene.with_values`) where the scene gives
  it: a mesh's typed helix angle, a gear body's teeth, a stage's ``helix_angle``; each keeps
  its hand (sign); a scene without a helical mesh is refused;
* ``bearing-factor``: common factor on all bearing stiffnesses (radial, axial, tilt) via
  :func:`assembly.scale_bearings`; plotted on log axes (bearing modes grow as sqrt(factor)
  while the gear modes level off).

Writes ``sweep.csv`` (one row per value: the value, the number of rigid-body modes and
every frequency in Hz), ``sweep.png`` and ``flexgear_run.json`` into DIR, atomically and with
the same folder rules as ``flexgear run`` (:mod:`assembly.app.output`).
"""
from __future__ import annotations

import csv
import dataclasses
import logging
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SceneError

log = logging.getLogger(__name__)

PARAMS = ("helix", "bearing-factor")
DEFAULT_VALUES = {"helix": np.linspace(0.0, 30.0, 31), "bearing-factor": np.geomspace(1.0, 1e6, 25)}


def check_helical(scene) -> None:
    """Refuse (SceneError) a scene without a helical gear mesh or stage: a helix sweep
    changes only gears that are helical already."""
    if not any(m.helix_angle for m in scene.meshes) and not any(st.helix_angle for st in scene.stages):
        raise SceneError("meshes.helix_angle", 0.0, "no helical gear mesh or stage in this scene: the helix "
                                                    "sweep changes only meshes that are helical already")


def with_helix_angle(scene, beta: float):
    """Copy of ``scene`` with its helical gears at helix angle ``beta`` (rad).

    Only gears that are helical already (non-zero helix angle) change, each keeping its
    hand (sign); spur gears stay spur. Changed are the values the scene gives: a mesh's
    typed ``helix_angle``, the teeth of a gear body (its meshes then derive their line of
    action from them) and a stage's ``helix_angle``. A scene without a helical mesh is
    refused."""
    from ..gear_data import body_teeth
    check_helical(scene)
    changes = {}
    for i, m in enumerate(scene.as_given("meshes")):
        if m.helix_angle:
            changes[f"meshes[{i}].helix_angle"] = math.copysign(beta, m.helix_angle)
    for i, b in enumerate(scene.as_given("bodies")):
        # the body's own teeth and its component's (equal when both are given)
        for teeth in ((f"bodies[{i}].teeth", b.teeth), body_teeth(dataclasses.replace(b, teeth=None), f"bodies[{i}]")):
            if teeth is not None and teeth[1] is not None and teeth[1].helix_angle:
                changes[f"{teeth[0]}.helix_angle"] = math.copysign(beta, teeth[1].helix_angle)
    for i, st in enumerate(scene.as_given("stages")):
        if st.helix_angle:
            changes[f"stages[{i}].helix_angle"] = math.copysign(beta, st.helix_angle)
    return scene.with_values(changes)


def parse_values(tokens, param: str) -> np.ndarray:
    """Parameter values from CLI tokens: numbers (``0 5 10`` or ``0,5,10``) or ranges
    ``start:stop:count`` (linear for helix, geometric for bearing-factor). Default when
    empty: 0..30 deg (31 values) or 1..1e6 (25 values)."""
    if not tokens:
        return DEFAULT_VALUES[param].copy()
    out = []
    for tok in tokens:
        for part in str(tok).replace(",", " ").split():
            if ":" in part:
                try:
                    a, b, n = part.split(":")
                    a, b, n = float(a), float(b), int(n)
                except ValueError:
                    raise ValueError(f"--values {part!r}: a range is start:stop:count") from None
                if n < 1:
                    raise ValueError(f"--values {part!r}: count must be >= 1")
                if param == "bearing-factor":
                    if not (a > 0 and b > 0):
                        raise ValueError(f"--values {part!r}: factors must be > 0")
                    out.extend(np.geomspace(a, b, n))
                else:
                    out.extend(np.linspace(a, b, n))
            else:
                try:
                    out.append(float(part))
                except ValueError:
                    raise ValueError(f"--values {part!r}: not a number") from None
    v = np.asarray(out, float)
    if not np.all(np.isfinite(v)):
        raise ValueError("--values must be finite numbers")
    if param == "bearing-factor" and np.any(v <= 0):
        raise ValueError(f"--values {v[v <= 0][0]:g}: bearing factors must be > 0")
    if param == "helix" and np.any(np.abs(v) >= 90):
        raise ValueError(f"--values {v[np.abs(v) >= 90][0]:g}: |helix angle| must be < 90 deg")
    return v


@dataclass
class SweepResult:
    param: str
    values: np.ndarray            # as given (deg for helix, factor for bearing-factor)
    frequencies_hz: np.ndarray    # (n_values, n_modes)
    n_rigid: np.ndarray           # (n_values,)
    scene_name: str


def run_sweep(scene, param: str, values, progress=None) -> SweepResult:
    """Frequencies of ``scene`` (a Scene) for each parameter value."""
    from ..modal import solve_modes
    from ..model import assemble
    from .progress import Progress
    from ..scene import scale_bearings

    if param not in PARAMS:
        raise ValueError(f"--param {param!r}: must be one of {list(PARAMS)}")
    progress = progress or Progress(enabled=False)
    values = np.asarray(values, float)
    F, nr = [], []
    with progress.step(f"sweep {param}", total=len(values), unit="model") as bar:
        for v in values:
            sc = with_helix_angle(scene, math.radians(v)) if param == "helix" else scale_bearings(scene, float(v))
            r = solve_modes(assemble(sc))
            F.append(np.sort(r.frequencies_hz))
            nr.append(r.n_rigid)
            bar.update(1)
    n = min(len(f) for f in F)
    if any(len(f) != n for f in F):  # cannot happen: the DOF count does not depend on the value
        log.warning("mode count changes along the sweep; keeping the lowest %d", n)
    return SweepResult(param, values, np.array([f[:n] for f in F]), np.array(nr), scene.name)


def write_csv(sr: SweepResult, path) -> Path:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        head = ["helix_angle_deg", "helix_angle_rad"] if sr.param == "helix" else ["bearing_factor"]
        w.writerow(head + ["n_rigid_body_modes"] + [f"f{j + 1}_hz" for j in range(sr.frequencies_hz.shape[1])])
        for v, nr, f in zip(sr.values, sr.n_rigid, sr.frequencies_hz):
            first = [f"{v:.9g}", f"{math.radians(v):.9g}"] if sr.param == "helix" else [f"{v:.9g}"]
            w.writerow(first + [int(nr)] + [f"{x:.9g}" for x in f])
    return Path(path)


def write_plot(sr: SweepResult, path, max_modes: int | None = None) -> Path:
    from .plots import plot_sweep

    if sr.param == "helix":
        xlabel, logx, what = "helix angle [deg]", False, "helix angle"
    else:
        xlabel, logx, what = "bearing stiffness factor (radial, axial, tilt) [-]", True, "bearing stiffness factor"
    return plot_sweep(sr.values, sr.frequencies_hz, path, xlabel,
                      title=f"{sr.scene_name}: natural frequencies vs {what}", logx=logx,
                      n_rigid=sr.n_rigid, max_modes=max_modes, logy=logx)


def sweep_to_dir(scene_source, param: str, values, out_dir, progress=None, max_modes: int | None = None) -> dict:
    """Load the scene, sweep, and write CSV + PNG + manifest into ``out_dir`` atomically."""
    from ..schema import load_scene
    from .output import check_output_dir, staged_output, write_manifest, writing

    out_dir = Path(out_dir).absolute()
    t0 = time.perf_counter()
    check_output_dir(out_dir)  # refuse a foreign folder before the (possibly long) sweep
    scene = load_scene(scene_source)
    if param == "helix":
        check_helical(scene)  # before any output folder is made
    with staged_output(out_dir) as work:
        sr = run_sweep(scene, param, values, progress)
        with writing(out_dir, work, "sweep results"):
            write_csv(sr, work / "sweep.csv")
            write_plot(sr, work / "sweep.png", max_modes=max_modes)
            info = dict(tool="flexgear sweep", scene=scene.name, scene_source=str(scene_source), param=param,
                        values=[float(v) for v in sr.values], files=["sweep.csv", "sweep.png"],
                        n_modes=int(sr.frequencies_hz.shape[1]), time_s=round(time.perf_counter() - t0, 4),
                        python=sys.version.split()[0])
            write_manifest(work, info)
    return info
