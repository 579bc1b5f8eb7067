"""Closed forms of seven-joint arms for chosen values of one free joint (the redundancy).

The numeric solver's first stage (:mod:`kin.ik.numeric.free_joint`) asks them: ``seven_dof``
(humanoid7's structure, joint 1 free; TIAGo's arm, Kinova's Gen3; its steps at one joint-1 value
in ``seven_dof_steps``, its frames in ``seven_dof_frames``), ``spherical_shoulder7`` (axes 1-3
and 5-6 meeting: Panda, xArm7; joint 7 free; its structure in ``shoulder7_structure``, its batched
steps in ``shoulder7_batch``) and ``general_7r`` (any other 7R arm: joint 1 or 7 held,
``held_end``, the 6R closed forms of :mod:`..six_r` for the rest; a snapped special form's
branches polished onto it, ``ideal_7r``; its starts and scans in ``free_value_scan``).
``subproblems`` holds the sub-problems the first two share; ``branches7`` lists every branch of
any of them over a stated grid of the free joint (``solve(..., all_branches=True)``). Their
compiled twins ``_closed7`` and ``_shoulder7`` (C, optional) run the same steps.
"""
