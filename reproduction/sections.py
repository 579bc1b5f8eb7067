"""The section providers of ``docs/reproduction.md``, in report order.

A provider is a function returning ``list[Section]``; adding one is one line in
:data:`SECTION_PROVIDERS`.
"""

from __future__ import annotations

from collections.abc import Callable

from .humanoid7_fk import humanoid7_sections
from .ik_humanoid7 import humanoid7_ik_sections
from .ik_papers import ik_sections
from .ned5_fk import ned5_sections
from .pickplace3_drives import pickplace3_drive_sections
from .pickplace3_fk import pickplace3_sections
from .report import Section
from .scorbot_fk import scorbot_sections

SectionProvider = Callable[[], list[Section]]

#: Providers in report order (by paper number).
SECTION_PROVIDERS: list[SectionProvider] = [
    humanoid7_sections,
    humanoid7_ik_sections,
    ik_sections,
    ned5_sections,
    pickplace3_sections,
    pickplace3_drive_sections,
    scorbot_sections,
]


def all_sections(providers: list[SectionProvider] | None = None) -> list[Section]:
    """The sections of every provider (default :data:`SECTION_PROVIDERS`), in order."""
    return [section for provider in (providers or SECTION_PROVIDERS) for section in provider()]
