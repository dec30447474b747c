"""The dynamics floor: the damped model in frequency and in time.

Damping (:mod:`.damping`: the scene's ``[damping]`` on the modes and the section loads'
share of it; :mod:`.modal_ratios`; damped modes, :mod:`.damped_modes`), the frequency
response (:mod:`.frf`, its inputs and outputs :mod:`.frf_channels`), the Campbell diagram
(:mod:`.campbell`, :mod:`.orders`, :mod:`.phasing`, :mod:`.gyroscopic`) and the time domain:
the integrators (:mod:`.integrators`, :mod:`.transient`), the nonlinear meshes and drive
torques (:mod:`.mesh_contact`, :mod:`.mesh_variation`, :mod:`.drive_torques`), load
histories and the files they come from (:mod:`.load_series`, :mod:`.openfast_output`), and
a run of a scene split by job (:mod:`.simulate` calls :mod:`.run_model`,
:mod:`.run_start`, :mod:`.run_loads`, :mod:`.run_outputs`, :mod:`.run_checks`), within a
memory budget (:mod:`.budget`). It imports the analysis floor and below.
"""
