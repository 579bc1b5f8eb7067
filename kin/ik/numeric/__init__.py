"""Numeric IK for any table: seed table, damped Newton, mink QP with hard limits, the paper's NR."""
