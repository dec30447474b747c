"""Images of an assembled drivetrain (pyvista off-screen, imported lazily): mode shapes and
stresses (:mod:`.renderer`), flexible bodies' FE surfaces (:mod:`.fe`), labels
(:mod:`.labels`), beam shafts (:mod:`.shafts`) and the static twist (:mod:`.twist`)."""
