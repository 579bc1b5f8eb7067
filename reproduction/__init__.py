"""Reproduction of the numeric tables of the seed papers (``../shared/seeds/``)."""

from .report import Row, Section, render

__all__ = ["Row", "Section", "render"]
