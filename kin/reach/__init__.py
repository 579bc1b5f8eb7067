"""Reachability maps: per voxel, the fraction of tool orientations the arm reaches (``kin reach``).

The map is computed in :mod:`~kin.reach.map` over the grid and orientations of
:mod:`~kin.reach.grid`, on a Dask client of :mod:`~kin.reach.cluster` when asked; it is written
and read as ``.npz`` by :mod:`~kin.reach.map_file` and drawn by :mod:`~kin.reach.plot`.
"""
