"""Closed forms of seven-joint arms for chosen values of one free joint (the redundancy).

The numeric solver's first stage (:mod:`kin.ik.numeric.free_joint`) asks them: ``seven_dof``
(humanoid7's structure, joint 1 free; TIAGo's arm) and ``spherical_shoulder7`` (axes 1-3 and 5-6
meeting: Panda, xArm7; joint 7 free). Their compiled twins ``_closed7`` and ``_shoulder7`` (C,
optional) run the same steps.
"""
