"""Images of an assembled drivetrain (pyvista off-screen, imported lazily: :mod:`.plotter`):
mode shapes and the overview (:mod:`.renderer`), drawn from the bodies' solids
(:mod:`.shapes`) and their surfaces (:mod:`.surfaces`), springs (:mod:`.springs`), beam
shafts (:mod:`.shafts`), fixed cameras (:mod:`.views`), stage labels (:mod:`.labels`) and
twist arrows (:mod:`.twist`); flexible bodies' FE surfaces and stress images (:mod:`.fe`)."""
