"""The Timoshenko elements of a beam shaft (``[[shafts]]`` with ``diameter``): one element
between consecutive nodes of the shaft as the scene lays it out (:func:`assembly.scene.shafts.beam_nodes`:
body1's point, the stations by ``at``, body2's point)."""
from __future__ import annotations

import dataclasses

from ..mechanics.beam import section, timoshenko_element
from ..scene.shafts import beam_nodes
from ..scene.tables import Shaft


def beam_elements(s: Shaft, i: int, by_name: dict, masters: dict, name: str) -> list:
    """Timoshenko elements of beam shaft ``i`` (``name``: the shaft's element name) between
    consecutive nodes: body1's point, the stations by ``at``, body2's point. Item
    ``("shafts", i)``; the end bodies' half masses on the first and last element; with
    ``beta`` (s) > 0 each element's dampers are ``beta k`` on its strain rows
    (``C_e = beta K_e``)."""
    nodes = beam_nodes(s, i, by_name, masters)
    sec = section(s.diameter, s.bore_diameter, s.material.nu)
    last = len(nodes) - 2
    out = []
    for j, (a, b) in enumerate(zip(nodes, nodes[1:])):
        label = name if len(nodes) == 2 else f"{name}:{a[3]}-{b[3]}"
        el = timoshenko_element(label, a[0], b[0], a[1], b[1], sec, s.material,
                                lumped=(j == 0, j == last), interfaces=(a[2], b[2]), item=("shafts", i))
        out.append(dataclasses.replace(el, c=s.beta * el.k) if s.beta > 0 else el)
    return out
