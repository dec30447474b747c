"""Start-up of the command line: `flexgear modes` loads only what a rigid-body modal solve
needs. Checked on the modules a fresh interpreter has imported (not on wall-clock time,
which depends on the machine's load)."""
import json
import subprocess
import sys

#: Libraries a rigid-body `flexgear modes` never uses: meshing, FE, plotting, rendering,
#: the assignment solver (MAC pairing), iterative sparse eigensolvers; and SciPy at all (its
#: linear algebra and sparse matrices alone cost 0.2-0.3 s of a 0.3 s goal: a small rigid
#: model is assembled and solved with NumPy).
HEAVY = ("scipy.optimize", "scipy.sparse.linalg", "matplotlib", "pyvista", "gmsh", "skfem", "meshio",
         "scipy", "scipy.linalg", "scipy.sparse", "numpy.ma", "fe_components.meshing")

PROBE = """
import json, sys
from assembly.app.cli import main
rc = main(["modes", "kahraman_beta20.toml"])
print(json.dumps({"rc": rc, "loaded": sorted(m for m in %r if m in sys.modules)}))
""" % (HEAVY,)


def test_modes_command_imports_no_heavy_library():
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, timeout=120, check=True)
    report = json.loads(out.stdout.strip().splitlines()[-1])
    assert report["rc"] == 0
    assert report["loaded"] == [], report["loaded"]


def test_public_names_still_import():
    code = ("import sys; from assembly import assemble, compare, CacheDirs, track_modes, Scene; "
            "from cms import CraigBamptonReductor, recover_stress; from fe_components import PinionParams, build_component; "
            "import assembly; assert callable(assembly.compare) and 'with_value' in dir(assembly); "
            "print('skfem' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.strip() == "True"   # asking for stress recovery loads scikit-fem
