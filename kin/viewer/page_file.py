"""Write a page all at once: a temporary file beside the target, then an atomic rename."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from .exceptions import PageWriteError

__all__ = ["write_page"]


def write_page(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path``: either the whole page is there, or nothing changed.

    Args:
        path: Destination file; its folder must exist.
        text: The page.

    Returns:
        The destination path.

    Raises:
        PageWriteError: The folder is missing or not writable, or the disk is full.
    """
    target = Path(path)
    if target.is_dir():
        raise PageWriteError(str(target), "is a directory")
    folder = target.parent
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=folder)
    except OSError as err:
        raise PageWriteError(str(target), err.strerror or str(err)) from err
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as stream:
            stream.write(text)
        os.chmod(temporary, 0o644)
        os.replace(temporary, target)
    except OSError as err:
        Path(temporary).unlink(missing_ok=True)
        raise PageWriteError(str(target), err.strerror or str(err)) from err
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return target
