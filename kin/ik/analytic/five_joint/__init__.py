"""Closed form of five-joint arms: a base yaw, three parallel pitch joints and a wrist roll.

``five_dof`` (lab5, ned5, scorbot, SO-100): a position with the tool's pitch (and roll), or a full
pose the arm reaches.
"""
