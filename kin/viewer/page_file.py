"""Write a page all at once: a temporary file beside the target, then an atomic rename."""

from __future__ import annotations

import os
from pathlib import Path

from .exceptions import PageWriteError

__all__ = ["captioned", "titled", "write_page"]


def _refused(path: str, _option: str, reason: str) -> PageWriteError:
    """A :class:`PageWriteError` for a path that cannot take the page (a device, a folder...)."""
    return PageWriteError(path, reason)


def write_page(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path``: either the whole page is there, or nothing changed.

    Only a regular file or a new path is written (:mod:`dh2urdf.output_file`).

    Args:
        path: Destination file; its folder must exist.
        text: The page.

    Returns:
        The destination path.

    Raises:
        PageWriteError: A folder, device, FIFO or socket at the path, a missing or unwritable
            folder, or the disk is full.
    """
    from dh2urdf.output_file import write_text_atomic

    return write_text_atomic(path, text, _refused, PageWriteError)


def titled(page: str, title: str) -> str:
    """``page`` (meshcat's static HTML) with ``title`` (escaped) in place of "MeshCat"."""
    import html

    return page.replace("<title>MeshCat</title>", f"<title>{html.escape(title)}</title>", 1)


#: The caption's box: the page's lower left corner, white on dark, over the 3D view.
_CAPTION_STYLE = (
    "position:fixed;left:8px;bottom:8px;margin:0;padding:4px 8px;z-index:10;"
    "font:14px/1.3 sans-serif;color:#fff;background:rgba(0,0,0,0.6);border-radius:3px;"
    "pointer-events:none"
)


def captioned(page: str, text: str) -> str:
    """``page`` (meshcat's static HTML) with ``text`` (escaped) in a caption over its lower left corner."""
    import html

    caption = f'<p id="kin-caption" style="{_CAPTION_STYLE}">{html.escape(text)}</p>'
    head, end, tail = page.rpartition("</body>")
    return f"{head}{caption}{end}{tail}" if end else page + caption
