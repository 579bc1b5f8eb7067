"""Parse URDF text as other URDF readers do: its XML, its kind, and Pinocchio's model of it.

Three steps that every URDF reader of the project shares:

- :func:`parse_urdf_xml`: :mod:`xml.etree` is namespace-aware where urdfdom (TinyXML) is not, so a
  prefix used but never declared (``<gazebo><sensor:camera/></gazebo>``, common in files written
  for Gazebo) makes it fail with "unbound prefix". Such prefixes are declared on the root element
  (``xmlns:sensor="urn:undeclared:sensor"``) and the text parsed again: the elements they name are
  extensions the kinematics never reads, as urdfdom ignores them.
- :func:`is_urdf_file`: a file is a URDF by its content (root element ``<robot>``) whatever its
  suffix (``.urdf``, ``.xml``, ``.URDF``, none); another XML file (an MJCF ``<mujoco>``) is an
  error that says what it is.
- :func:`build_pinocchio_model`: urdfdom and console_bridge write their complaints on the C
  stderr (file descriptor 2), several lines per bad file; they are captured around the parse and
  put into the one error line.

Errors are :class:`~dh2urdf.exceptions.UrdfChainError`: one line that names the file
and the fix.
"""

from __future__ import annotations

import os
import re
import tempfile
import threading
import xml.etree.ElementTree as ElementTree
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .exceptions import UrdfChainError
from .input_file import open_input

__all__ = [
    "build_pinocchio_model",
    "captured_stderr",
    "declare_prefixes",
    "is_urdf_file",
    "parse_urdf_xml",
]

#: Suffixes that say "URDF" without reading the file.
URDF_SUFFIXES = (".urdf", ".xacro")
#: Longest text of the parser's own messages kept in an error line [characters].
PARSER_TEXT = 200
#: Bytes read to find the root element of a file of unknown kind.
SNIFF_BYTES = 65536

_PREFIX = re.compile(
    r"</?\s*([A-Za-z_][\w.-]*):[A-Za-z_]|\s([A-Za-z_][\w.-]*):[A-Za-z_][\w.-]*\s*="
)
_DECLARED = re.compile(r"xmlns:([A-Za-z_][\w.-]*)\s*=")
_ROOT_NAME = re.compile(r"<([A-Za-z_][\w:.-]*)")
#: Kinds of XML files users mistake for URDF: root element -> what it is.
_OTHER_XML = {
    "mujoco": "an MJCF (MuJoCo) model",
    "sdf": "an SDF model",
    "COLLADA": "a COLLADA mesh",
}
_STDERR_LOCK = threading.Lock()


def _root_start(text: str) -> int:
    """Index of the ``<`` that opens the root element (after the prolog), or -1."""
    position = 0
    while True:
        start = text.find("<", position)
        if start < 0:
            return -1
        if text.startswith("<?", start):
            position = text.find("?>", start) + 2
        elif text.startswith("<!--", start):
            position = text.find("-->", start) + 3
        elif text.startswith("<!", start):
            position = text.find(">", start) + 1
        else:
            return start
        if position < start:  # an unclosed declaration or comment: not XML we can mend
            return -1


def declare_prefixes(text: str) -> str:
    """``text`` with every namespace prefix it uses but never declares declared on its root.

    The declared namespace is ``urn:undeclared:PREFIX``; text that declares every prefix it uses
    comes back unchanged.
    """
    used = {a or b for a, b in _PREFIX.findall(text)} - {"xml", "xmlns"}
    missing = sorted(used - set(_DECLARED.findall(text)))
    start = _root_start(text)
    match = _ROOT_NAME.match(text, start) if start >= 0 else None
    if not missing or match is None:
        return text
    declarations = "".join(f' xmlns:{prefix}="urn:undeclared:{prefix}"' for prefix in missing)
    return text[: match.end()] + declarations + text[match.end() :]


def parse_urdf_xml(text: str, where: str) -> tuple[ElementTree.Element, str]:
    """The root element of URDF ``text`` and the text parsed (undeclared prefixes declared).

    Args:
        text: The URDF text.
        where: The file it came from, for messages.

    Raises:
        UrdfChainError: Not XML, or its root element is not ``<robot>``.
    """
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as err:
        if "unbound prefix" not in str(err):
            raise UrdfChainError(where, f"not XML: {err}") from None
        mended = declare_prefixes(text)
        try:
            root = ElementTree.fromstring(mended)
        except ElementTree.ParseError:
            raise UrdfChainError(where, f"not XML: {err}") from None
        text = mended
    if root.tag != "robot":
        raise UrdfChainError(where, _not_urdf(root.tag.rpartition("}")[2]))
    return root, text


def _not_urdf(tag: str) -> str:
    kind = _OTHER_XML.get(tag)
    what = f"{kind} (root element <{tag}>)" if kind else f"the root element is <{tag}>"
    return f"not a URDF: {what}, not <robot>; give the arm's URDF file"


def is_urdf_file(path: str | Path) -> bool:
    """Whether ``path`` names a URDF: by suffix (``.urdf``, ``.xacro``) or by its content.

    A file whose suffix says nothing (``.xml``, ``.URDF``, none) is read: a root element
    ``<robot>`` makes it a URDF. A file that is not XML (a DH table) is not one.

    Raises:
        UrdfChainError: The file is XML with another root element (``<mujoco>``...): the message
            says what it is.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in URDF_SUFFIXES or path.name.lower().endswith(".urdf.xacro"):
        return True
    if not path.is_file():
        return suffix == ".xml"  # then "cannot read the file" says what is wrong
    if suffix == ".toml":
        return False
    try:
        with open_input(path) as stream:
            head = stream.read(SNIFF_BYTES).decode("utf-8", errors="replace")
    except OSError:
        return False
    start = _root_start(head.lstrip("\ufeff"))
    if start < 0 or not head.lstrip("\ufeff \t\r\n").startswith("<"):
        return False
    match = _ROOT_NAME.match(head.lstrip("\ufeff"), start)
    tag = match.group(1).rpartition(":")[2] if match else ""
    if tag == "robot":
        return True
    raise UrdfChainError(str(path), _not_urdf(tag or "?"))


def captured_stderr(call: Callable[[], Any]) -> tuple[Any, BaseException | None, str]:
    """Run ``call`` with file descriptor 2 sent to a temporary file.

    Returns:
        ``(result or None, the exception raised or None, the text written on fd 2)``.
    """
    with _STDERR_LOCK, tempfile.TemporaryFile() as capture:
        saved = os.dup(2)
        try:
            os.dup2(capture.fileno(), 2)
            try:
                return_value, error = call(), None
            except (RuntimeError, ValueError) as err:
                return_value, error = None, err
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        capture.seek(0)
        written = capture.read().decode("utf-8", errors="replace")
    return return_value, error, written


def build_pinocchio_model(text: str, where: str, mimic: bool = False) -> Any:
    """Pinocchio's model of URDF ``text``; the parser's own stderr lines go into the error.

    Args:
        text: The URDF text.
        where: The file it came from, for messages.
        mimic: Build mimic joints as Pinocchio mimic joints (their value follows their leader).

    Raises:
        UrdfChainError: Pinocchio (urdfdom) cannot load it, or loads it after writing an
            ``Error:`` line (a number it cannot read, such as a 5000-digit one, makes urdfdom
            drop the element: no shipped or example-robot-data URDF does that); the message
            holds the parser's messages, joined on one line and cut to :data:`PARSER_TEXT`
            characters.
    """
    import pinocchio as pin

    model, error, written = captured_stderr(lambda: pin.buildModelFromXML(text, mimic=mimic))
    if error is None and not re.search(r"^\s*Error:", written, re.MULTILINE):
        return model
    said = " ".join(line.strip() for line in written.splitlines() if line.strip())
    said = re.sub(r"\s*at line \d+ in \S+", "", said)  # the C++ source line: not the user's
    said = re.sub(r"(\S{24})\S{16,}", r"\1...", said)  # a 5000-digit value, shortened
    if len(said) > PARSER_TEXT:
        said = said[: PARSER_TEXT - 3] + "..."
    if error is None:
        raise UrdfChainError(where, f"Pinocchio's URDF parser rejects part of it: {said}")
    detail = re.sub(r"(\S{24})\S{16,}", r"\1...", " ".join(str(error).split()))
    message = f"Pinocchio cannot load the URDF: {detail}" + (f" ({said})" if said else "")
    raise UrdfChainError(where, message) from error
