"""The IK side of collisions: a solver's answers checked against the model, and the numeric search that keeps a distance bound (coal queries stay in :mod:`kin.collision`)."""
