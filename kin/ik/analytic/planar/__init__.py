"""Closed forms of arms whose axes are all parallel, or a base yaw over parallel pitch axes.

``planar2r`` (two parallel axes, positions), ``offset3r`` (a base yaw over a planar 2R with
offsets), ``parallel_axes`` (every axis parallel: planar 2R read from any frame, RRP, planar 3R,
SCARA; a full pose projected on what the arm reaches) and ``yaw_planar`` (a base yaw over three
parallel pitch joints: AL5D, Orion5).
"""
