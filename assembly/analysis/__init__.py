"""The analysis floor: what an assembled model is, undamped.

Its modes (:mod:`.modal`, checked by :mod:`.resolution` and :mod:`.lever_arms`), their
energies, places and classes (:mod:`.energy`, :mod:`.locality`, :mod:`.harmonics`,
:mod:`.classify`), tracked along a parameter (:mod:`.tracking`) and paired across
fidelities (:mod:`.compare`), modal stresses (:mod:`.modal_stress`), static load cases and
their reactions (:mod:`.load_cases`, :mod:`.static`, :mod:`.reactions`), the drivetrain's
kinematic chain and its two-mass equivalent (:mod:`.drivetrain`, :mod:`.two_mass`), and one
user part checked alone (:mod:`.part_check`). It imports the model floor and below.
"""
