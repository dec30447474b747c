"""Regenerate the small committed test meshes (meshes/cms_*). Needs gmsh; the tests
themselves only read the files.

    python -m tests.support.testmeshes
"""
from __future__ import annotations

import os


def make_shaft_mesh(path: str, radius: float = 0.025, length: float = 0.1,
                    size: float = 0.006) -> None:
    """Round shaft along z (m), 10-node curved tetrahedra, gmsh MSH 4.1."""
    from fe_components.gmsh_session import gmsh_model

    with gmsh_model("shaft") as gmsh:
        v = gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, length, radius)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [v], 1)
        gmsh.option.setNumber("Mesh.CharacteristicLengthMax", size)
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.model.mesh.generate(3)
        tmp = path + ".tmp.msh"
        gmsh.write(tmp)
        os.replace(tmp, path)


if __name__ == "__main__":
    here = os.path.join(os.path.dirname(__file__), "..", "..", "meshes")
    make_shaft_mesh(os.path.join(here, "cms_shaft.msh"))
