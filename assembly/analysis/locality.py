"""Where a mode's energy sits: a per-mode energy table over the model's parts (bodies,
bearings, meshes, shafts), its sums per stage, and the mode's scope.

Peeters, Vandepitte & Sas (2006), "Analysis of internal drive train dynamics in a wind
turbine", Wind Energy 9: the modes of a whole drivetrain are *global* or *local to a
stage*, judged by where the mode's energy sits. Here a mode is local to group S when S
holds at least :data:`LOCAL_SHARE` of the mode's total energy, else global.

Groups: a body belongs to its ``stage`` (planetary members carry their stage's name), a body
without ``stage`` forms its own group named after the body. An element (bearing, mesh,
shaft) belongs to the group of its bodies when all its non-housing bodies share one;
otherwise to the link between their groups, named ``"<group a>/<group b>"`` (groups in body
order), e.g. ``"wheel/planetary"`` for a quill shaft.

Energies of a mass-normalised mode z (absolute coordinates) of eigenvalue omega^2:
strain ``V_p`` (J) of a spring ``e' diag(k) e / 2`` and of a flexible body ``z_b' K_b z_b / 2``;
kinetic ``omega^2 T_p`` with ``T_p = z_p' M_p z_p / 2`` (J s^2) of a body's own mass matrix
and of an element's lumped ``mass``. At resonance the peak kinetic and strain energies are
equal (Rayleigh's quotient), so a mode's total energy is ``2 V`` and a group's share of it is
the mean of its kinetic share and its strain share; a rigid-body mode (no strain) is judged
on its kinetic shares. Every judgement is made on energies summed over a group of repeated
frequencies, which do not depend on the basis the solver returns for that eigenspace.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .energy import kinetic_by_element, kinetic_energy_by_body, strain_energy_by_body, strain_energy_by_element

log = logging.getLogger(__name__)

#: A mode is local to a group (a stage) holding at least this share of its total energy
#: (kinetic + strain); otherwise it is global. Peeters et al. (2006) sort modes this way but
#: give no number: 0.8 is assumed (four fifths of the energy in one stage).
LOCAL_SHARE = 0.8
#: Scope of a mode that no group holds.
GLOBAL = "global"
#: Largest relative difference between a mode's strain energy and omega^2 x its kinetic
#: energy (Rayleigh's quotient) before the energy table warns that the parts do not add up.
RAYLEIGH_RTOL = 1e-6


@dataclass(frozen=True)
class EnergyTable:
    """Energies of every mode (rows) in every part (columns: the bodies in model order,
    then the elements). ``kinds``: "body", "bearing", "mesh" or "shaft"; ``groups``: the
    group (stage) of each part; ``kinetic``: ``T_p = z_p' M_p z_p / 2`` (J s^2, the kinetic
    energy per unit omega^2); ``strain``: ``V_p`` (J); ``eigenvalues``: omega^2 (rad^2/s^2)."""

    names: tuple
    kinds: tuple
    groups: tuple
    kinetic: np.ndarray
    strain: np.ndarray
    eigenvalues: np.ndarray

    @property
    def group_names(self) -> tuple:
        """The groups, each once, in part order (bodies' groups first)."""
        return tuple(dict.fromkeys(self.groups))

    def membership(self) -> np.ndarray:
        """(n_parts, n_groups) 0/1 matrix: part p belongs to group g."""
        names = self.group_names
        G = np.zeros((len(self.names), len(names)))
        G[np.arange(len(self.names)), [names.index(g) for g in self.groups]] = 1.0
        return G


def body_group(body) -> str:
    """Group of a scene body: its ``stage``, or its own name when it has none."""
    return body.stage or body.name


def part_groups(model) -> tuple[tuple, tuple, tuple]:
    """(names, kinds, groups) of the model's parts: bodies, then elements."""
    sc = model.scene
    of_body = {b: body_group(sc.body(b)) for b in model.bodies}
    order = list(dict.fromkeys(of_body.values()))
    names, kinds, groups = list(model.bodies), ["body"] * len(model.bodies), list(of_body.values())
    for el in model.elements:
        own = sorted({of_body[b] for b in el.bodies if b is not None}, key=order.index)
        names.append(el.name)
        kinds.append(el.kind)
        groups.append("/".join(own))
    return tuple(names), tuple(kinds), tuple(groups)


def energy_table(result) -> EnergyTable:
    """The :class:`EnergyTable` of a modal result; logs a warning when a mode's strain energy
    differs from omega^2 x its kinetic energy by more than :data:`RAYLEIGH_RTOL`."""
    names, kinds, groups = part_groups(result.model)
    table = EnergyTable(names, kinds, groups,
                        0.5 * np.hstack([kinetic_energy_by_body(result), kinetic_by_element(result)]),
                        np.hstack([strain_energy_by_body(result), strain_energy_by_element(result)]),
                        np.asarray(result.eigenvalues, float))
    err = rayleigh_error(table)[result.n_rigid:]
    if err.size and err.max() > RAYLEIGH_RTOL:
        log.warning("energy table: strain energy differs from omega^2 x kinetic energy by up to %.1e "
                    "(relative, mode %d): parts missing from the bookkeeping?", err.max(),
                    result.n_rigid + int(err.argmax()) + 1)
    return table


def rayleigh_error(table: EnergyTable) -> np.ndarray:
    """(n_modes,) ``|V - omega^2 T| / (V + omega^2 T)`` of the parts' totals: zero to
    round-off when the parts hold all of each mode's energy (nan where both are zero)."""
    V = table.strain.sum(axis=1)
    T = np.abs(table.eigenvalues) * table.kinetic.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.abs(V - T) / (V + T)


def shares(E: np.ndarray) -> np.ndarray:
    """Rows of ``E`` divided by their sums (rows of zeros where a row holds no energy, or
    only round-off of the largest row's: a rigid-body mode's strain energy)."""
    tot = E.sum(axis=1, keepdims=True)
    has = tot > 1e-12 * np.abs(tot).max(initial=0.0)
    return np.where(has, E / np.where(has, tot, 1.0), 0.0)


def total_share(kinetic_share: np.ndarray, strain_share: np.ndarray) -> np.ndarray:
    """Share of the total energy from kinetic and strain shares (rows): their mean, or the
    kinetic share alone for a row without strain energy (a rigid-body mode)."""
    strained = strain_share.sum(axis=-1, keepdims=True) > 0
    return np.where(strained, 0.5 * (kinetic_share + strain_share), kinetic_share)


def group_shares(table: EnergyTable, mode_groups, parts: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(kinetic, strain): (n_modes, n_groups) shares of each group (``table.group_names``),
    or with ``parts`` (n_modes, n_parts) shares of each part (``table.names``). Each mode gets
    the shares of its repeated-frequency group (``mode_groups``: lists of mode indices, e.g.
    ``ModalResult.groups``), which do not depend on the basis of that eigenspace."""
    G = np.eye(len(table.names)) if parts else table.membership()
    Tg, Vg = table.kinetic @ G, table.strain @ G
    K, S = np.zeros_like(Tg), np.zeros_like(Vg)
    for g in mode_groups:
        K[g] = Tg[g].sum(axis=0)
        S[g] = Vg[g].sum(axis=0)
    return shares(K), shares(S)


def mode_scopes(table: EnergyTable, kinetic_share: np.ndarray, strain_share: np.ndarray) -> list:
    """Scope of every mode: the group holding at least :data:`LOCAL_SHARE` of its total
    energy, else :data:`GLOBAL` (shares from :func:`group_shares`)."""
    E = total_share(kinetic_share, strain_share)
    names = table.group_names
    top = E.argmax(axis=1)
    return [names[j] if E[i, j] >= LOCAL_SHARE else GLOBAL for i, j in enumerate(top)]
