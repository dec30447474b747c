"""Flexible gearbox components: gmsh geometry, scikit-fem K/M, interface master nodes.

SI units throughout (m, kg, N, s, rad, Pa; frequencies in Hz).  Importing this
package does not import gmsh (only meshing a new geometry does).
"""
from .coupling import CoupledModel, couple, couple_nodes
from .errors import CouplingError, GeometryError, MaterialError, MeshCacheError, MeshingError
from .export import write_vtu
from .fe_model import FEModel, Interface, build_component, default_mesh_size
from .material import STEEL, Material
from .meshing import MeshOptions
from .params import (COMPONENT_KINDS, CarrierParams, CylinderParams, GearTeeth, PinionParams, ShaftSegment,
                     WheelParams)

__all__ = [
    "CarrierParams", "CoupledModel", "CouplingError", "CylinderParams", "FEModel", "GearTeeth",
    "GeometryError", "Interface", "Material", "MaterialError", "MeshCacheError", "MeshOptions",
    "MeshingError",
    "PinionParams", "STEEL", "ShaftSegment", "WheelParams", "build_component", "COMPONENT_KINDS",
    "couple", "couple_nodes", "default_mesh_size", "write_vtu",
]
