"""Closed forms of arms whose axes are all parallel, or a base yaw over parallel pitch axes.

``planar2r`` (two parallel axes, positions), ``offset3r`` (a base yaw over a planar 2R with
offsets), ``parallel_axes`` (every axis parallel: planar 2R read from any frame, RRP, planar 3R,
SCARA; a full pose projected on what the arm reaches), ``yaw_planar`` (a base yaw over three
parallel pitch joints: AL5D, Orion5) and ``yaw_roll`` (a base yaw, two pitch joints and a roll:
Kinova's 4-DOF arms, the QArm). Their shared steps: ``plane_chain`` (a chain of parallel axes in
its plane and its two-link solves), ``base_yaw`` (the yaws that put a point on the chain's
plane), ``free_angle`` (the free angle a position leaves, and its sweep; compiled twin
``kin/_native/ik/analytic/planar/_pitch_sweep.c``).
"""
