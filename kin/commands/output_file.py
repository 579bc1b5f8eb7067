"""Output files checked before any work: a regular file or a new path, a writable folder, a known suffix.

A command that computes for minutes must not end in a traceback because ``-o nodir/ws.png``
names a missing folder, write PNG bytes into ``ws.jpg``, or rename its result over ``/dev/full``:
:func:`checked_output` runs first and refuses a folder, a device (``/dev/null`` too), a FIFO or a
socket at the path, and a file the command reads (:func:`input_files`: ``--robot arm.xml
--write-srdf arm.xml``, also through a link). The writers write through a temporary file and a rename, whole or not at all;
a full disk is one :class:`~kin.exceptions.OutputWriteError` (exit 1), the old file unchanged. A
symbolic link to a regular file is written through (the link stays). The rules live in
:mod:`dh2urdf.output_file`; this module raises kin's exceptions.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, BinaryIO

from ..exceptions import OutputFileError, OutputWriteError

if TYPE_CHECKING:
    from dh2urdf.output_file import InputFiles

#: Figure formats that matplotlib writes as such, by suffix.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def input_files(args: argparse.Namespace, *options: str) -> list[tuple[str, str]]:
    """The files ``args`` names under ``options`` (``"--robot"``...), for :func:`checked_output`.

    ``--robot`` with a shipped robot's name stands for its table file too (``dh2urdf --robot
    ur5`` reads it); an option not given is left out.
    """
    from dh2urdf.robots import get_robot, robot_names

    found: list[tuple[str, str]] = []
    for option in options:
        value = getattr(args, option.lstrip("-").replace("-", "_"), None)
        if not isinstance(value, str | os.PathLike):
            continue
        found.append((option, os.fspath(value)))
        if option == "--robot" and value in robot_names():
            found.append((option, os.fspath(get_robot(str(value)).table_path)))
    return found


def checked_output(
    path: str,
    option: str,
    suffixes: tuple[str, ...] | None = None,
    inputs: InputFiles = (),
) -> Path:
    """``path`` as a :class:`~pathlib.Path` once it is known to be writable.

    Args:
        path: The file a command is to write.
        option: The option that named it, for the message (``"-o"``, ``"--csv"``).
        suffixes: Allowed suffixes (lower case, with the dot), or None for any.
        inputs: The files the command reads (:func:`input_files`): ``path`` must be none.

    Raises:
        OutputFileError: A folder, device (``/dev/null`` included), FIFO or socket at the path,
            one of ``inputs`` (also through a symbolic or hard link), a missing or unwritable
            folder, or another suffix.
    """
    from dh2urdf.output_file import checked_output as checked

    return checked(path, option, suffixes, inputs, OutputFileError)


def write_atomic(path: str | os.PathLike[str], write: Callable[[BinaryIO], object]) -> Path:
    """Put what ``write`` writes on a binary handle at ``path``, whole or not at all.

    Raises:
        OutputFileError: ``path`` is not a regular file or a new path in a writable folder.
        OutputWriteError: The disk filled up (or another I/O error) part-way; nothing changed.
    """
    from dh2urdf.output_file import write_atomic as write_whole

    return write_whole(path, write, OutputFileError, OutputWriteError)


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8, newlines as given) to ``path`` with :func:`write_atomic`."""
    data = text.encode("utf-8")
    return write_atomic(path, lambda handle: handle.write(data))
