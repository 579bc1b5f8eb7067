"""Monte Carlo workspace of a DH table: reach statistics, bounding box, voxel volume (meters).

One concept per module: the sampling and its statistics (:mod:`~kin.workspace.monte_carlo`),
the voxel grid (:mod:`~kin.workspace.grid`), one chunk's draw and reduction
(:mod:`~kin.workspace.chunk`), where the chunks run (:mod:`~kin.workspace.run`: this process,
a pool of workers that survives a worker's death, :mod:`~kin.workspace.pool`, or Dask) and the
pictures (:mod:`~kin.workspace.plot`, matplotlib imported there). ``kin.workspace`` was one
module up to 0.3.0; its names stay importable from here.
"""

from .monte_carlo import *  # noqa: F403 (the sampling's names, as the old module's)
from .monte_carlo import __all__ as __all__
