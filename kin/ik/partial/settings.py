"""The numbers of a partial-pose search (:mod:`kin.ik.partial_pose`): weights, grid, work, caps."""

from __future__ import annotations

#: Weight of the rotation rows in the least squares [m/rad]: 1 rad of tool rotation weighs as
#: 0.1 m of tool position when a pose cannot be reached and the nearest one is sought.
ROTATION_WEIGHT = 0.1

#: Roll values of an axis target tried by a closed form (evenly spaced over a turn), besides the
#: seed's roll.
ROLL_GRID = 24

#: Default cap on the time of one solve [s]: the work (:data:`RANDOM_STARTS`) decides the answer;
#: a call the cap stops first says ``timeout``.
DEFAULT_TIMEOUT = 2.0

#: Random starts of the least squares (drawn inside the limits from ``random_seed``), after the
#: closed-form candidates, the seed and the seed-table samples: the work of one search.
RANDOM_STARTS = 32

#: Levenberg-Marquardt steps per start.
MAX_ITERATIONS = 100

#: Largest joint change of one step (infinity norm) [rad].
MAX_STEP = 0.5

#: Damped Newton steps per start, and its patience (:func:`kin.ik.numeric.damped_newton.damped_newton`),
#: for a full pose before the least-squares starts (:func:`.starts.newton_starts`).
NEWTON_ITERATIONS, NEWTON_PATIENCE = 20, 3

#: Random starts (the first of the least squares' draw) damped Newton takes after the seed-table
#: samples, before the least squares.
NEWTON_RANDOM_STARTS = 8

#: Two solutions closer than this (largest joint difference [rad]) are the same.
SAME_SOLUTION = 1e-6
