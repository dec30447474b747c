"""Flexible gearbox components: gmsh geometry, scikit-fem K/M, interface master nodes.

SI units throughout (m, kg, N, s, rad, Pa; frequencies in Hz).  Importing this
package does not import gmsh (only meshing a new geometry does).
"""
from __future__ import annotations

from .lazy import lazy_exports

#: Public name -> submodule, imported on first use (``from fe_components import X`` works), so
#: importing ``fe_components.params`` does not load scikit-fem or meshio.
_EXPORTS = {
    "CoupledModel": "coupling", "couple": "coupling", "couple_nodes": "coupling",
    "CouplingError": "errors", "GeometryError": "errors", "MaterialError": "errors",
    "MeshCacheError": "errors", "MeshingError": "errors",
    "write_vtu": "export",
    "FEModel": "fe_model", "Interface": "fe_model", "build_component": "fe_model", "default_mesh_size": "fe_model",
    "GearBlank": "gear_blank", "blank_mass_properties": "gear_blank",
    "STEEL": "material", "Material": "material",
    "MeshOptions": "meshing",
    "COMPONENT_KINDS": "params", "CarrierParams": "params", "CylinderParams": "params", "GearTeeth": "params",
    "PinionParams": "params", "ShaftSegment": "params", "WheelParams": "params",
}
__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
