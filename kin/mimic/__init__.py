"""A URDF arm whose chain holds mimic joints: FK and IK over the independent joints only.

The arm (:mod:`~kin.mimic.arm`, loaded by :func:`kin.load_arm`), its IK search's stages
(:mod:`~kin.mimic.descent`) and the search behind the solvers' interface for ``kin ik``
(:mod:`~kin.mimic.solver`).
"""
