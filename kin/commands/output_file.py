"""Output files checked before any work: the folder exists and is writable, the suffix is known.

A command that computes for minutes must not end in a traceback because ``-o nodir/ws.png``
names a missing folder, nor write PNG bytes into ``ws.jpg``: :func:`checked_output` runs first,
and the writers write through a temporary file and a rename (nothing half-written).
"""

from __future__ import annotations

import os
from pathlib import Path

from ..exceptions import OutputFileError

#: Figure formats that matplotlib writes as such, by suffix.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def checked_output(path: str, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """``path`` as a :class:`~pathlib.Path` once it is known to be writable.

    Args:
        path: The file a command is to write.
        option: The option that named it, for the message (``"-o"``, ``"--csv"``).
        suffixes: Allowed suffixes (lower case, with the dot), or None for any.

    Raises:
        OutputFileError: A directory, a missing or unwritable folder, or another suffix.
    """
    target = Path(path)
    if target.is_dir():
        raise OutputFileError(path, option, "is a directory; give a file name")
    if suffixes is not None and target.suffix.lower() not in suffixes:
        raise OutputFileError(
            path,
            option,
            f"unknown file type {target.suffix or '(no suffix)'!r}; use " + ", ".join(suffixes),
        )
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise OutputFileError(path, option, f"the folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputFileError(path, option, f"the folder {str(folder)!r} is not writable")
    return target


def write_text_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file in its folder and a rename."""
    import tempfile

    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as stream:
            stream.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
