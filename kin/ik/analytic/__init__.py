"""Closed-form IK: structure plug-ins recognised from the DH table, every branch, batched in NumPy.

Split by arm class, the number of joints and the geometry a user looks an arm up by, each class
a subpackage of one module per structure:

- ``planar``: every axis parallel, or a base yaw over parallel pitch axes (2-4 joints);
- ``three_joint``: three revolute axes through one point (a wrist alone);
- ``five_joint``: a base yaw, three parallel pitch joints and a wrist roll;
- ``six_r``: revolute 6R arms, the special families (every branch in closed form, compiled
  twins) and the general elimination for the rest;
- ``seven_r``: seven-joint arms for chosen values of a free joint (the numeric solver's first
  stage).

What every class shares stays here: what a structure provides (``closed_form_structure``), the
checks it reads a table with (``structure``), the branches it returns (``branches``), the one
registry asked in turn (``registry``), the structure-agnostic solvers (``closed_form``, one
target; ``batch``, N targets), reversed and antiparallel joints (``joint_directions``), rounded
tables (``idealised``), the batch of one-target structures (``per_target_batch``) and the C
helpers of the compiled twins (``_twin.h``).
"""
