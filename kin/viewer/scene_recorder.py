"""An in-process meshcat window: records the scene and exports meshcat's static HTML page.

``meshcat.Visualizer()`` starts a server process (ZeroMQ and HTTP ports) and asks it for the
static page. For a file, none of that is needed: :class:`SceneRecorder` keeps the scene tree the
way meshcat's server does (the server's own tree, cache and page template, run in this process),
so that ``meshcat.Visualizer(window=SceneRecorder()).static_html()`` gives the server's page
without a process, a port or a network. The page inlines meshcat's JavaScript (three.js
included) and replays the recorded commands, animations included.
"""

from __future__ import annotations

import umsgpack
from meshcat.servers.tree import SceneTree
from meshcat.servers.zmqserver import ZMQWebSocketBridge

__all__ = ["SceneRecorder"]


class _Reply:
    """Stands for the server's ZeroMQ socket: keeps the last reply."""

    def __init__(self) -> None:
        self.data = b""

    def send(self, data: bytes) -> None:
        self.data = data


class SceneRecorder(ZMQWebSocketBridge):
    """A meshcat window without a server: ``send`` records, ``get_scene`` exports the page.

    Reuses the command handling of meshcat's server (:class:`ZMQWebSocketBridge`) with no
    socket, port or browser behind it.
    """

    def __init__(self) -> None:  # the bridge's own __init__ binds ports: not called
        self.tree = SceneTree()
        self.websocket_pool: set = set()
        self.zmq_socket = _Reply()
        self.web_url = ""

    def send(self, command: object) -> None:
        """Record one meshcat command (``SetObject``, ``SetTransform``, ``SetAnimation``...)."""
        data = command.lower()  # type: ignore[attr-defined]
        frames = [data["type"].encode("utf-8"), data["path"].encode("utf-8"), umsgpack.packb(data)]
        self.handle_zmq(frames)
        if self.zmq_socket.data != b"ok":
            raise RuntimeError(f"meshcat did not take the command: {self.zmq_socket.data!r}")

    def get_scene(self) -> str:
        """The static HTML page of the recorded scene (meshcat's own export)."""
        self.handle_zmq([b"get_scene"])
        return self.zmq_socket.data.decode("utf-8")
