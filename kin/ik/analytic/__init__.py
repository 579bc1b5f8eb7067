"""Closed-form IK: structure plug-ins recognised from the DH table, every branch, batched in NumPy.

One module per structure: ``planar2r``, ``offset3r``, ``five_dof``, and the 6R families
``ur_wrist`` (three parallel axes, two meeting wrist axes), ``spherical_wrist`` (spherical wrist,
axes 2 and 3 parallel), ``pieper`` (spherical wrist, any first three joints),
``three_parallel`` (axes 2-4 parallel, any other joints) and ``reversed_chain`` (any of these
read from the tool end: a spherical shoulder, ...); what a structure provides
(``closed_form_structure``), the registry asked in turn (``registry``), the structure-agnostic
solvers (``closed_form``, ``batch``). The seven-joint closed forms with a free
joint, used by the numeric solver's first stage: ``seven_dof`` (humanoid7, joint 1 free) and
``spherical_shoulder7`` (Panda, xArm7, joint 7 free). The compiled twins (``_closed7``,
``_shoulder7``, ``_ur_wrist``, ``_spherical_wrist``; ``six_r_twin`` loads the 6R ones) are
optional extensions.
"""
