"""Coupled against one-way: Kucher & Hauptmann's comparison of a drivetrain run inside its
turbine with the same drivetrain driven by load series from a simpler turbine model.

Three runs of the same wind and controller (the scene's ``[turbine]``):

(a) coupled: the detailed drivetrain in the loop (:mod:`assembly.dynamics.turbine_run`);
(b) two-mass: the turbine with the drivetrain's ElastoDyn-like two-mass equivalent
    (:func:`assembly.analysis.two_mass.two_mass`: rotor inertia, the rest referred to the
    generator, DTTorSpr and DTTorDmp; the generator on the low-speed side with ``generator_ratio``
    = GBRatio), as an aeroelastic code without the gearbox would run it;
(c) one-way: the detailed drivetrain alone, its rotor driven by (b)'s aerodynamic torque and
    thrust series and its generator by (b)'s generator torque series (``[[simulation.loads]]``
    and a generator of law "table"): the usual chain of an aeroelastic run then a drivetrain run.

The report compares (a) and (c): the amplitude spectral densities (Welch, Hann windows of
``segment`` s, half overlap, mean removed, over ``t_skip`` .. t_end so the start stays out) of the
rotor torque, a tooth force and a bearing's axial load, their peaks with the detailed model's
nearest mode (frequency, class, the elements holding most of its strain energy), and where the
two differ: peaks whose spectral densities differ by more than ``DIFFER_DB``.
"""
from __future__ import annotations

import dataclasses
import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import arguments as check
from ..analysis.classify import classify_modes
from ..analysis.energy import strain_by_element
from ..analysis.modal import solve_modes
from ..analysis.two_mass import two_mass
from ..errors import SceneError
from ..model.assemble import assemble
from ..scene.schema import scene_from_dict, to_dict
from ..scene.tables import Scene, with_fidelity, with_tables
from ..scene.time_domain import Generator, TimeLoad
from ..scene.turbine import Turbine
from .run_outputs import recorded_channels
from .simulate import simulate

#: Spectral densities further apart than this (dB) at a peak: the runs differ there.
DIFFER_DB = 3.0
#: Peaks kept per channel and run.
PEAKS = 5


@dataclass(frozen=True)
class Spectrum:
    """Amplitude spectral densities (units / sqrt(Hz)) of one channel: ``coupled`` and
    ``one_way`` over ``frequency_hz``; ``output``: the run's output name; ``rms`` {run: RMS of
    the channel's fluctuation in the window}."""

    label: str
    output: str
    unit: str
    frequency_hz: np.ndarray
    coupled: np.ndarray
    one_way: np.ndarray
    rms: dict


@dataclass(frozen=True)
class Comparison:
    """The three runs (module notes), the ``spectra``, their ``peaks`` (dicts: channel, Hz, the
    two densities, their ratio in dB, the nearest mode and its strain shares), ``verdicts``
    (sentences, where the runs differ) and the two-mass model used (``two_mass``)."""

    coupled: object
    two_mass_run: object
    one_way: object
    spectra: list
    peaks: list
    verdicts: list
    two_mass: object
    window_s: tuple
    modes: list = field(default_factory=list)


def compare_coupling(scene: Scene, t_end: float, dt: float, tooth_force: str | None = None,
                     bearing_axial: str | None = None, base_dir=None, t_skip: float | None = None,
                     segment: float = 10.0, progress=None, fidelity: str | None = None) -> Comparison:
    """The comparison of the module notes for ``scene`` (with a ``[turbine]`` rotor) over
    ``t_end`` s at step ``dt``; ``tooth_force`` (default the first mesh's ``force:MESH``) and
    ``bearing_axial`` (default ``force:BEARING:z`` of the first bearing with an axial spring) name the outputs;
    ``t_skip`` (default 10 % of the run) the start left out of the spectra; ``fidelity``: the
    detailed drivetrain's ("torsional", "rigid", "flexible"; default the scene's)."""
    if fidelity is not None:
        scene = with_fidelity(scene, fidelity)
    tb = scene.turbine
    if tb is None or tb.wind is None:
        raise SceneError("turbine", None, "missing: the comparison runs the scene's [turbine] rotor in its wind")
    exp = scene.expanded()
    if tooth_force is None:
        if not exp.meshes:
            raise SceneError("tooth_force", None, "missing: the scene has no gear mesh")
        tooth_force = f"force:{exp.meshes[0].name}"
    if bearing_axial is None:
        axial = [b.name for b in exp.bearings if (b.k_axial or 0.0) > 0.0]
        if not axial:
            raise SceneError("bearing_axial", None, "missing: no bearing of the scene has an axial spring")
        bearing_axial = f"force:{axial[0]}:z"
    t_end, dt = check.number("t_end", t_end, "s", gt=0.0), check.number("dt", dt, "s", gt=0.0)
    segment = check.number("segment", segment, "s", gt=0.0)
    t_skip = 0.1 * t_end if t_skip is None else check.number("t_skip", t_skip, "s", ge=0.0)
    model = assemble(scene)
    for arg, name in (("tooth_force", tooth_force), ("bearing_axial", bearing_axial)):
        check.text(arg, name)
        recorded_channels(model, (), [name], arg)              # a name the model has, else SceneError at arg
    if not (t_end - t_skip >= 2.0 * segment):
        raise SceneError("t_skip", t_skip, f"must leave at least two segments of {segment:g} s of the "
                                           f"{t_end:g} s run for the spectra")
    channels = {"rotor torque": "turbine:aero_torque", "tooth force": tooth_force, "bearing axial": bearing_axial}
    coupled = simulate(model, t_end, dt, ["turbine:aero_torque", tooth_force, bearing_axial, "turbine:rotor_speed"],
                       base_dir=base_dir, progress=progress)
    tm = two_mass(scene)
    tm_scene = two_mass_scene(scene, tm)
    two = simulate(tm_scene, t_end, dt, ["turbine:aero_torque", "turbine:thrust", "turbine:generator_torque",
                                         "turbine:rotor_speed"], base_dir=base_dir, progress=progress)
    with tempfile.TemporaryDirectory(prefix="flexgear-oneway-") as tmp:
        table = Path(tmp) / "two_mass_loads.csv"
        np.savetxt(table, np.column_stack([two.time_s, two.outputs["turbine:aero_torque"],
                                           two.outputs["turbine:thrust"], two.outputs["turbine:generator_torque"]]),
                   delimiter=",", header="time,torque,thrust,generator", comments="")
        one = simulate(one_way_scene(scene, table), t_end, dt, [tooth_force, bearing_axial],
                       base_dir=base_dir, progress=progress)
    one_out = {"turbine:aero_torque": np.interp(one.time_s, two.time_s, two.outputs["turbine:aero_torque"]),
               tooth_force: one.outputs[tooth_force], bearing_axial: one.outputs[bearing_axial]}
    keep = coupled.time_s >= t_skip
    spectra = []
    for label, name in channels.items():
        f, a = density(coupled.time_s[keep], coupled.outputs[name][keep], segment)
        _, b = density(one.time_s[keep], one_out[name][keep], segment)
        rms = {"coupled": float(np.std(coupled.outputs[name][keep])), "one-way": float(np.std(one_out[name][keep]))}
        spectra.append(Spectrum(label, name, coupled.units[name], f, a, b, rms))
    modes = detailed_modes(model)
    peaks = [p for s in spectra for p in spectrum_peaks(s, modes)]
    return Comparison(coupled, two, one, spectra, peaks, verdicts(spectra, peaks), tm, (t_skip, t_end), modes)


def two_mass_scene(scene: Scene, tm) -> Scene:
    """A torsional two-mass drivetrain (rotor J_R; generator J_G N^2 on the low-speed side with
    ``generator_ratio`` N; shaft DTTorSpr, DTTorDmp) in ``scene``'s turbine, starting at its speed."""
    n = abs(tm.speed_ratio)
    c = tm.damping or 0.0
    rotor = next(b for b in scene.expanded().bodies if b.name == tm.rotor)
    axis = np.asarray(rotor.axis, float)
    pos = np.asarray(rotor.position, float)
    sim = scene.simulation
    tb = dataclasses.replace(scene.turbine, rotor=None, generator=None, generator_ratio=n, gravity=False)
    return scene_from_dict({
        "name": "two-mass equivalent", "fidelity": "torsional", "band_hz": scene.band,
        "bodies": [{"name": "rotor", "role": "rotor", "mass": 1.0, "polar_inertia": tm.rotor_inertia,
                    "position": pos.tolist(), "axis": axis.tolist()},
                   {"name": "generator", "role": "generator", "mass": 1.0, "polar_inertia": tm.generator_inertia * n * n,
                    "position": (pos + axis).tolist(), "axis": axis.tolist()}],
        "shafts": [{"name": "shaft", "body1": "rotor", "body2": "generator", "k_torsion": tm.stiffness,
                    "c_torsion": c}],
        "simulation": {"speed": sim.speed if sim is not None else 0.0},
        "turbine": to_dict(tb, defaults=False)})


def one_way_scene(scene: Scene, table: Path) -> Scene:
    """``scene`` without its rotor in the loop: the rotor driven by ``table``'s torque and thrust
    (along its axis), the generator by its generator torque (law "table"); gravity kept."""
    tb = scene.turbine
    sim = scene.simulation
    rotor = tb.rotor or next(b.name for b in scene.bodies if b.role == "rotor")
    axis = next(b for b in scene.expanded().bodies if b.name == rotor).axis
    file = {"table": str(table), "time_column": "time"}
    loads = [TimeLoad(body=rotor, kind="torque", column="torque", **file)]
    if tb.thrust:
        loads.append(TimeLoad(body=rotor, kind="force", direction=tuple(float(x) for x in axis), column="thrust",
                              **file))
    gen = Generator(body=tb.generator, law="table", column="generator", **file)
    if tb.generator_ratio != 1.0:
        gen = dataclasses.replace(gen, scale=tb.generator_ratio)
    new_sim = dataclasses.replace(sim, loads=(*sim.loads, *loads), generator=gen)
    frame = Turbine(tilt=tb.tilt, gravity=True) if tb.gravity else None
    return with_tables(scene, simulation=new_sim, turbine=frame)


def density(t: np.ndarray, y: np.ndarray, segment: float) -> tuple[np.ndarray, np.ndarray]:
    """(Hz, amplitude spectral density) of a uniformly sampled ``y``: Welch, Hann windows of
    ``segment`` s, half overlap, mean removed."""
    from scipy.signal import welch
    fs = 1.0 / float(t[1] - t[0])
    nper = min(len(y), int(round(segment * fs)))
    f, p = welch(np.asarray(y, float), fs=fs, window="hann", nperseg=nper, noverlap=nper // 2, detrend="constant")
    return f, np.sqrt(p)


def detailed_modes(model) -> list:
    """[(Hz, class label, ((element, strain share), ...) top three)] of the model's elastic
    modes."""
    res = solve_modes(model)
    info = classify_modes(res, nodal_diameters=False)
    shares = strain_by_element(res)
    names = [el.name for el in res.model.elements]
    out = []
    for k in range(res.n_rigid, len(res.frequencies_hz)):
        top = np.argsort(shares[k])[::-1][:3]
        out.append((float(res.frequencies_hz[k]), info[k].label,
                    tuple((names[j], float(shares[k, j])) for j in top if shares[k, j] > 0.0)))
    return out


def spectrum_peaks(s: Spectrum, modes: list, most: int = PEAKS) -> list:
    """The ``most`` highest peaks of each run's density (local maxima above 1e-3 of the
    channel's largest), merged, each with both densities, their ratio (dB) and the mode it is
    the resonance of (within 10 % or two lines), None when none is."""
    from scipy.signal import find_peaks
    top = max(float(s.coupled[1:].max(initial=0.0)), float(s.one_way[1:].max(initial=0.0)))
    found = set()
    for a in (s.coupled, s.one_way):
        idx, _ = find_peaks(a, height=1e-3 * top)
        idx = idx[idx > 0]
        found.update(int(i) for i in idx[np.argsort(a[idx])[::-1][:most]])
    out = []
    df = float(s.frequency_hz[1] - s.frequency_hz[0]) if len(s.frequency_hz) > 1 else 0.0
    for i in sorted(found):
        f = float(s.frequency_hz[i])
        c, o = float(s.coupled[i]), float(s.one_way[i])
        ratio = 20.0 * math.log10(c / o) if c > 0 and o > 0 else math.inf if c > 0 else -math.inf
        # a peak within 10 % (or two lines) of a natural frequency is that mode's resonance; else
        # the response is quasi-static there and no mode is named
        near = min(modes, key=lambda m: abs(m[0] - f)) if modes else None
        if near is not None and abs(near[0] - f) > max(0.1 * near[0], 2.0 * df):
            near = None
        out.append({"channel": s.label, "output": s.output, "frequency_hz": f, "coupled": c, "one_way": o,
                    "ratio_db": ratio, "mode_hz": near[0] if near else None, "mode_class": near[1] if near else None,
                    "strain_shares": list(near[2]) if near else []})
    return out


def verdicts(spectra: list, peaks: list) -> list:
    """Sentences: per channel the RMS of both runs, and the peaks where they differ by more than
    :data:`DIFFER_DB` (or that they agree within it)."""
    out = []
    for s in spectra:
        c, o = s.rms["coupled"], s.rms["one-way"]
        if c == 0.0 and o == 0.0:
            out.append(f"{s.label} ({s.output}): does not fluctuate in either run (nothing at this fidelity moves "
                       f"it): not compared")
            continue
        if c == 0.0 or o == 0.0:
            out.append(f"{s.label} ({s.output}): fluctuation RMS {c:.4g} coupled, {o:.4g} one-way {s.unit}: "
                       f"one run does not fluctuate at all")
            continue
        rel = 20.0 * math.log10(c / o)
        out.append(f"{s.label} ({s.output}): fluctuation RMS {c:.4g} coupled, {o:.4g} one-way {s.unit} "
                   f"({rel:+.1f} dB)")
        differ = [p for p in peaks if p["output"] == s.output and abs(p["ratio_db"]) > DIFFER_DB]
        if not differ:
            out.append(f"  its peaks agree within {DIFFER_DB:g} dB")
        for p in differ:
            mode = (f"; the mode at {p['mode_hz']:.4g} Hz ({p['mode_class']}: "
                    + ", ".join(f"{n} {100 * v:.0f} %" for n, v in p["strain_shares"]) + " of its strain)"
                    if p["mode_hz"] is not None else "; no mode there (quasi-static)")
            out.append(f"  differs at {p['frequency_hz']:.4g} Hz: coupled {p['ratio_db']:+.1f} dB against "
                       f"one-way{mode}")
    return out
