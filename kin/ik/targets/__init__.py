"""The targets of IK: what a solver is asked to reach, checked once when built (world frame; m, rad)."""
