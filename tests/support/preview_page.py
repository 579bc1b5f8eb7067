"""Reading a preview page back: the meshcat commands packed in its HTML and the animation tracks,
object paths and point clouds they hold.
"""

from __future__ import annotations

import base64
import re
from pathlib import Path

import numpy as np
import pytest

from kin.commands import preview as command

umsgpack = pytest.importorskip("umsgpack")  # comes with meshcat
_COMMAND = re.compile(r'data:application/octet-binary;base64,([A-Za-z0-9+/=]+)"')


def page_commands(html: str) -> list[dict]:
    """The meshcat commands a static page replays, decoded (type, path, object, animations)."""
    return [umsgpack.unpackb(base64.b64decode(data)) for data in _COMMAND.findall(html)]


def object_paths(commands: list[dict]) -> set[str]:
    """Paths of the objects the page creates."""
    return {c["path"] for c in commands if c["type"] == "set_object"}


def animation_tracks(commands: list[dict]) -> dict[str, list]:
    """Position keyframe values per animated path, in time order."""
    (animation,) = [c for c in commands if c["type"] == "set_animation"]
    tracks = {}
    for item in animation["animations"]:
        for track in item["clip"]["tracks"]:
            if track["name"] == ".position":
                tracks[item["path"]] = [key["value"] for key in track["keys"]]
    return tracks


def write_page(tmp_path: Path, capsys, argv: list[str], name: str = "page.html") -> str:
    """Run ``kin preview ... --html FILE``; the page's text (exit 0 asserted)."""
    page = tmp_path / name
    code = command.main([*argv, "--html", str(page)])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.out.strip().endswith(f"preview written to {page}")
    return page.read_text(encoding="utf-8")


def cloud_points(commands: list[dict], name: str) -> np.ndarray:
    """Positions (N, 3) of the point cloud ``markers/<name>`` of a page [m]."""
    (created,) = [c for c in commands if c["path"] == f"/meshcat/scene/markers/{name}"]
    attribute = created["object"]["geometries"][0]["data"]["attributes"]["position"]
    return np.frombuffer(attribute["array"].data, dtype=np.float32).reshape(-1, 3)
