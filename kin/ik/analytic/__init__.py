"""Closed-form IK: structure plug-ins recognised from the DH table, every branch, batched in NumPy.

One module per structure (``planar2r``, ``offset3r``, ``five_dof``), what a structure provides
(``closed_form_structure``), the registry asked in turn (``registry``), the structure-agnostic
solvers (``closed_form``, ``batch``). The compiled twin of the seven-joint closed form
(``_closed7``) is an optional extension.
"""
