"""Exports to other tools: the ElastoDyn two-mass drivetrain fragment (:mod:`.elastodyn`) and
a flexible body's superelement as .npz and Nastran DMIG (:mod:`.superelement`)."""
