"""Closed form of three-joint arms that are a wrist alone: three revolute axes through one point.

``wrist3`` (Valkyrie's forearm model): a pose's rotation by two sub-problems, two branches; a
point with the seed's free joints.
"""
