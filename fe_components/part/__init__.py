"""A user's own part as a flexible component: a CAD file (STEP/BREP) or a volume mesh file
(gmsh, Abaqus, MED, VTU, Nastran ...) read, checked, converted to metres and to the part's own
frame, its interfaces found by the rules, and meshed (CAD) or converted (mesh file) into the
mesh cache, where it is a component like the generated gears (docs/user_parts.md).

Modules, lowest first:

* :mod:`.file`: ``PartFile`` (``kind = "file"``) and ``InterfaceRule``, the user's input;
* :mod:`.frame`: the part's own frame in its file (``axis``, ``origin``);
* :mod:`.rules`: the geometric rules on face samples, computed masters;
* :mod:`.cells`: a mesh file's cells, what is read and dropped; :mod:`.nastran`: Nastran bulk data;
* :mod:`.geometry`: ``PartGeometry`` (size, volume, mass properties, interfaces), the rules
  applied to the faces a reader found;
* :mod:`.cad`: STEP/BREP through gmsh's OpenCASCADE; :mod:`.mesh`: mesh files through meshio;
* :mod:`.read`: ``part_geometry(part)``, the part read by the reader of its kind, once per process.

Importing the package imports none of them (nor gmsh).
"""
