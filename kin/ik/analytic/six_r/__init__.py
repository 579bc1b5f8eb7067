"""Closed forms of revolute 6R arms: every branch (8 for the families, up to 16 in general).

The families, each a special geometry: ``ur_wrist`` (three parallel axes, two meeting wrist
axes: the UR arms, Unitree Z1), ``spherical_wrist`` (a spherical wrist, axes 2 and 3 parallel:
PUMA 560, Kinova Jaco 2), ``pieper`` (a spherical wrist, any first three joints: a quartic in
joint 3, ``_trig_quartic``), ``three_parallel`` (axes 2-4 parallel, any other joints) and
``reversed_chain`` (any of these read from the tool end). ``general_6r`` solves any other 6R
arm by elimination (``_general_6r_elimination``; ``_stacked_transforms`` multiplies its stacks of
transforms). ``_six_r`` holds the steps the families share,
``pieper_batch`` and ``three_parallel_batch`` the batched steps of those two families,
``pieper_quartic`` the general Pieper family's equation in joint 3 (scalar and batched); the
compiled twins ``_ur_wrist`` and ``_spherical_wrist`` (C, optional) solve and verify a pose in one
call, loaded by ``six_r_twin``.
"""
