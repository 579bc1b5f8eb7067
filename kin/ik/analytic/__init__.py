"""Closed-form IK: structure recognition from the DH table, every branch, batched in NumPy.

The compiled twin of the seven-joint closed form (``_closed7``) is an optional extension.
"""
