"""What a time-domain run records: the channels of its outputs (:mod:`assembly.dynamics.frf_channels`'
names, plus ``speed:BODY`` and the named stress points of ``[[simulation.points]]``), read
at every step from the state (:class:`Recorder`), and their histories in the end.

A section load (``torque:``, ``force:``, ``stress:``) carries its share of the scene's
``[damping]`` as the frequency response does, ``k_e B_e G q'`` (:mod:`assembly.dynamics.damping`;
a nonlinear mesh: its contact force plus the share of its mean spring ``k0``, the spring the
damping matrix was built with), so that each body's balance ``M q'' + C q' + K q + U nu = f``
holds with the recorded loads. An ``acceleration:`` output reads q''. A stress is the von
Mises stress of its six back-expanded components at each instant.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..model.probes import body_point, spin_row
from .frf_channels import output_channels, output_rows, von_mises_peak
from .observe_rows import Rows


@dataclass(frozen=True)
class Recorder:
    """The rows a run reads at each step: ``Ok q + Oc v`` of the channels (their damper rows
    with the scene's share), ``Oa a`` of the accelerations, ``Sv v`` of the speeds; a
    nonlinear mesh's force (``swap``: channel index, mesh index) is its contact force plus
    the share ``Os v``. ``chans`` and ``speed_names`` in the order recorded."""

    Ok: np.ndarray
    Oc: np.ndarray
    Os: np.ndarray
    Oa: np.ndarray
    Sv: np.ndarray
    swap: tuple
    chans: list
    speed_names: list
    extra: tuple = ()

    @property
    def size(self) -> int:
        """Values recorded a step (``extra``: ((name, unit), ...) of values an observer appends after
        the rows, e.g. the turbine's)."""
        return len(self.chans) + len(self.speed_names) + len(self.extra)

    def observe(self, meshes) -> Rows:
        """``observe(q, v, a, nu)`` for :func:`assembly.dynamics.transient.integrate` (the
        contact forces read from ``meshes``), as its rows (:class:`Rows`)."""
        return Rows(self.Ok, self.Oc, self.Oa, self.Sv, self.Os, self.swap, meshes)

    def histories(self, Y: np.ndarray):
        """{name: history} and {name: unit} of the recorded rows ``Y`` (:func:`collect`)."""
        values, units = collect(Y, self.chans, self.speed_names)
        base = len(self.chans) + len(self.speed_names)
        for k, (name, unit) in enumerate(self.extra):
            values[name], units[name] = Y[:, base + k], unit
        return values, units


def recorder(model, points, names, G, meshes, extra: tuple = ()) -> Recorder:
    """The :class:`Recorder` of the outputs ``names`` (``points``: ``[[simulation.points]]``;
    ``G``: the section loads' share of the scene damping, :func:`scene_share`; ``meshes``:
    the run's nonlinear meshes, whose ``force:`` outputs are their contact forces; ``extra``:
    ((name, unit), ...) of the values an observer appends)."""
    n = model.K.shape[0]
    chans, speed_rows = recorded_channels(model, points, names)
    Ok, Oc = output_rows(chans) if chans else (np.zeros((0, n)), np.zeros((0, n)))
    Os = scene_share(Ok, chans, G)
    acc = np.array([c.derivative == 2 for c in chans], bool)
    Oa, Ok, Oc, Os = Ok[acc], Ok[~acc], Oc[~acc] + Os[~acc], Os[~acc]
    chans = [c for c in chans if c.derivative != 2] + [c for c in chans if c.derivative == 2]
    mesh_idx = {f"force:{mi.name}": j for j, mi in enumerate(meshes.info)}
    swap = tuple((i, mesh_idx[c.name]) for i, c in enumerate(chans) if c.name in mesh_idx)
    Sv = np.array(list(speed_rows.values())).reshape(len(speed_rows), n)
    return Recorder(Ok, Oc, Os, Oa, Sv, swap, chans, list(speed_rows), tuple(extra))


def recorded_channels(model, points, names, arg: str = "outputs") -> tuple[list, dict]:
    """The channels and the speed rows (``speed:BODY``) that record ``names``: a named stress
    point of ``points`` (``simulation.points``) or an output of
    :func:`assembly.dynamics.frf_channels.output_channels`; SceneError at ``arg`` for a name
    the model does not have."""
    named = {f"stress:{p.name}": (i, p) for i, p in enumerate(points)}
    chans, speed_rows = [], {}
    for name in names:
        if name.startswith("speed:"):
            body, _ = body_point(model, name[6:], arg, name)
            speed_rows[name] = spin_row(model, body)
        elif name in named:
            i, p = named[name]
            where = f"stress:{p.body}:" + ",".join(f"{v:.17g}" for v in p.point)
            chans.extend(dataclasses.replace(c, name=f"{name}:{c.name.rsplit(':', 1)[1]}", group=name)
                         for c in output_channels(model, where, f"simulation.points[{i}]"))
        else:
            chans.extend(output_channels(model, name, arg))
    return chans, speed_rows


def scene_share(Ok: np.ndarray, chans: list, G) -> np.ndarray:
    """The damper rows of the scene-damping share of each output (zero but for section loads):
    ``Ok G`` (module notes)."""
    out = np.zeros_like(Ok)
    sec = np.array([c.section for c in chans], bool)
    if G is not None and sec.any():
        out[sec] = Ok[sec] @ G if np.ndim(G) else G * Ok[sec]
    return out


def collect(Y: np.ndarray, chans: list, speed_names: list):
    """{name: history} and units from the recorded rows (stress components -> von Mises)."""
    values, units = {}, {}
    for j, c in enumerate(chans):
        if c.group is None:
            values[c.name], units[c.name] = Y[:, j], c.unit
        elif c.group not in values:
            cols = [i for i, o in enumerate(chans) if o.group == c.group]
            values[c.group], units[c.group] = von_mises_peak(Y[:, cols]).real, c.unit
    for k, name in enumerate(speed_names):
        values[name], units[name] = Y[:, len(chans) + k], "rad/s"
    return values, units
