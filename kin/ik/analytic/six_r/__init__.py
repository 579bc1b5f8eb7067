"""Closed forms of revolute 6R arms: every branch (8 for the families, up to 16 in general).

Two families, each one NumPy algorithm for N targets and one compiled twin for all its cases
(``_three_parallel``, ``_pieper_arms``; their quartics by LAPACK):
``three_parallel`` (axes 2-4 parallel, any other joints; its case of meeting wrist axes 5 and 6
is ``ur_wrist``: the UR arms, Unitree Z1) with ``three_parallel_batch``, and ``pieper`` (a
spherical wrist, any first three joints; its case of parallel axes 2 and 3 is
``spherical_wrist``: PUMA 560, Kinova Jaco 2) with ``pieper_batch`` and ``pieper_quartic`` (the
general arms' equation in joint 3); both quartics are solved by ``_trig_quartic``. The modules
``ur_wrist`` and ``spherical_wrist`` keep the cases' import paths. ``reversed_chain`` reads
either family from the tool end; ``general_6r`` solves any other 6R arm by elimination
(``_general_6r_elimination``; ``_stacked_transforms`` multiplies its stacks of transforms).
``_six_r`` holds the steps the families share; ``six_r_twin`` the families' solve and the
compiled twins' parameters and verification (``_three_parallel``, ``_pieper_arms``: C, optional).
"""
