"""Reproduction of the numeric tables of the seed papers (``../shared/seeds/``)."""

from .report import Row, Section, render
from .sections import SECTION_PROVIDERS, SectionProvider, all_sections

__version__ = "0.1.0"

__all__ = ["Row", "SECTION_PROVIDERS", "Section", "SectionProvider", "all_sections", "render"]
