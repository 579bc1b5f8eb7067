"""The URDF text of a table as yourdfpy writes it back, and a body of that text without its header."""

from __future__ import annotations

from lxml import etree

from dh2urdf.urdf_writer import _PLACEHOLDER_NOTE, MUJOCO_COMPILER
from dh2urdf.yourdfpy_model import build_urdf


def yourdfpy_text(table) -> str:
    """Body of the URDF (after the header comment) as yourdfpy and lxml write it."""
    root = build_urdf(table).write_xml().getroot()
    if any(row.mass is None for row in table.rows):
        root.insert(0, etree.Comment(_PLACEHOLDER_NOTE))
    mujoco = etree.Element("mujoco")
    etree.SubElement(mujoco, "compiler", attrib=MUJOCO_COMPILER)
    root.insert(0, mujoco)
    return etree.tostring(root, pretty_print=True, encoding="unicode")


def body(text: str) -> str:
    """``urdf_string``'s text from ``<robot`` on."""
    return text[text.index("<robot ") :]
