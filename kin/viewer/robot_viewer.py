"""A robot in a meshcat scene: its URDF visuals through Pinocchio, frames, targets, paths, points.

:class:`RobotViewer` draws the arm from the visual geometry of its URDF with Pinocchio's
``MeshcatVisualizer`` (a DH arm's fitted volumes see-through: :mod:`.see_through`), and adds
what a DH table's user wants to see: the axis triads of chosen frames (base, tool, every DH
frame), a target marker, a joint-space path as a meshcat animation, point clouds, and nodes that
ride on a joint (:mod:`.riders`: objects attached to a link). The scene goes either to a live
meshcat server (a browser follows it) or into a
:class:`~kin.viewer.scene_recorder.SceneRecorder`, whose static HTML page needs no server and no
network.

Scene layout (meshcat paths under ``/meshcat/scene``): ``robot/visuals/<geometry>``
(Pinocchio's), ``frames/<frame>`` (triads that follow the arm), ``attached/<name>`` (riders),
``markers/<name>`` (targets, points). Poses are ``T_world_frame`` in the URDF root frame ``base_link``; lengths in meters.
The camera (:meth:`RobotViewer.set_camera`, :meth:`RobotViewer.fit_camera`) is placed by
:mod:`kin.viewer.arm_camera`.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from collections.abc import Sequence

import meshcat
import meshcat.animation
import meshcat.transformations as tf
import numpy as np
import numpy.typing as npt
import pinocchio as pin
import zmq

from ..configuration import as_joint_vector
from ..exceptions import FrameError
from ..robot_model import RobotModel
from .arm_camera import aim_camera, framed_view
from .camera_view import CameraView, Obstacle
from .exceptions import ViewerError, ViewerInputError
from .finite_array import finite_array
from .maker_meshes import MakerMeshes, maker_meshes
from .markers import draw_points, draw_sphere, draw_triad
from .mesh_files import ReadableMeshes
from .riders import Rider, rider_pose
from .scene_recorder import SceneRecorder
from .see_through import see_through_body

__all__ = ["RobotViewer"]

#: Target marker color (RGB in [0, 1]).
TARGET_RGB = (0.95, 0.75, 0.1)

# Scales of meshcat's grid (20 m, 0.5 m cells): 0.1 gives a 2 m grid of 5 cm cells.
_GRID_SCALES = (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0)


class RobotViewer:
    """A robot shown in meshcat: arm, frame triads, markers, animations.

    Args:
        robot: The robot (its URDF gives the visual geometry).
        serve: Start meshcat's server (a browser at :attr:`url` follows the scene); else the
            scene is recorded in this process for :meth:`static_html`.

    Raises:
        ViewerError: Pinocchio cannot build the visual geometry, or the server does not start.
    """

    def __init__(self, robot: RobotModel, *, serve: bool = False):
        self.robot = robot
        #: The maker's meshes of a robot loaded from a URDF, or None (the DH cylinders).
        self.meshes: MakerMeshes | None = None
        if robot.urdf_source is not None:
            try:
                self.meshes = maker_meshes(robot)
            except ViewerError as err:
                warnings.warn(f"{err}: drawing the DH cylinders instead", stacklevel=2)
        if self.meshes is not None:
            drawn, visual_model = self.meshes.model, self.meshes.visual_model
        else:
            drawn = robot.model
            try:
                visual_model = pin.buildGeomFromUrdfString(
                    robot.model, robot.urdf, pin.GeometryType.VISUAL
                )
            except (RuntimeError, ValueError) as err:
                raise ViewerError(
                    f"'{robot.name}': no visual geometry from its URDF: {err}"
                ) from err
            see_through_body(visual_model)  # fitted volumes would hide the joints
        self.visual_model = visual_model
        self.viewer = _open_viewer(serve)
        self._pin = ReadableMeshes(drawn, None, visual_model)
        self._pin.initViewer(viewer=self.viewer)
        self.scene = self.viewer["scene"]
        self._pin.loadViewerModel(rootNodeName="scene/robot")
        if self.meshes is not None:  # the URDF root's drawing in the chain's base frame
            self.scene["robot"].set_transform(np.linalg.inv(self.meshes.base_in_root))
        self._frames = robot.model.createData()  # the DH model's frames (triads)
        self.viewer["/Axes"].set_property("visible", False)  # the base triad stands for them
        self._followed: dict[str, int] = {}  # frame name -> Pinocchio frame id
        self.q = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
        self.arm_length = _arm_length(robot, self.q)
        # meshcat's grid is 20 m wide in 0.5 m cells: shrink it to the arm, round cell sizes
        self.grid_scale = max([s for s in _GRID_SCALES if 10.0 * s <= self.arm_length] or [0.01])
        self.viewer["/Grid"].set_transform(tf.scale_matrix(self.grid_scale))
        #: Boxes of the scene objects drawn: the camera looks past them (:meth:`fit_camera`).
        self.obstacles: list[Obstacle] = []
        #: Nodes that ride on a joint (attached objects), by meshcat path (:meth:`add_rider`).
        self.riders: dict[str, Rider] = {}
        self.display(self.q)

    @property
    def url(self) -> str | None:
        """Address of the live viewer, or None for a recorded scene."""
        return self.viewer.url() or None

    @property
    def geometry_nodes(self) -> tuple[str, ...]:
        """Meshcat paths of the arm's visual geometries (``scene/robot/visuals/<name>``)."""
        return tuple(f"scene/robot/visuals/{g.name}" for g in self.visual_model.geometryObjects)

    def display(self, q: npt.ArrayLike) -> None:
        """Place the arm and the followed frames at joint values ``q`` [rad] or [m].

        Raises:
            kin.JointVectorError: Not one finite value per joint.
        """
        self.q = as_joint_vector(self.robot, q)
        self._place(self.q, self.viewer)

    def show_frames(self, frames: Sequence[str], length: float | None = None) -> None:
        """Draw an axis triad (x red, y green, z blue) on each frame; it follows the arm.

        Args:
            frames: Frame names of the model (``base_link``, ``frame0``..``frame{n}``, ``tool``).
            length: Axis length [m] (default a tenth of the arm's length).

        Raises:
            kin.FrameError: A name is not a frame of the model.
        """
        length = 0.1 * self.arm_length if length is None else float(length)
        for name in frames:
            if not self.robot.model.existFrame(name):
                raise FrameError(name, self.robot.frame_names)
            draw_triad(self.scene["frames"][name], length)
            self._followed[name] = self.robot.model.getFrameId(name)
        self._place(self.q, self.viewer)

    def add_rider(self, rider: Rider) -> None:
        """Move ``rider.node`` with its joint in every configuration shown from now on, and now.

        A rider of the same node replaces the earlier one. Animations recorded before miss it.
        """
        self.riders[rider.node] = rider
        self._place(self.q, self.viewer)

    def show_target(
        self,
        position: npt.ArrayLike,
        rotation: npt.ArrayLike | None = None,
        name: str = "target",
        radius: float | None = None,
    ) -> None:
        """Draw a target: a sphere at ``position``, and a triad when ``rotation`` is given.

        Args:
            position: Target position in the world frame [m], shape (3,).
            rotation: Target orientation ``R_world_target``, shape (3, 3), or None.
            name: Marker name (``markers/<name>``); a second call with it replaces the first.
            radius: Sphere radius [m] (default 3 % of the arm's length).

        Raises:
            ViewerInputError: Not a finite position (3,) or rotation (3, 3).
        """
        pose = np.eye(4)
        pose[:3, 3] = finite_array(position, (3,), "target position")
        if rotation is not None:
            pose[:3, :3] = finite_array(rotation, (3, 3), "target rotation")
        node = self.scene["markers"][name]
        node.delete()
        radius = 0.03 * self.arm_length if radius is None else float(radius)
        draw_sphere(node["sphere"], radius, TARGET_RGB, opacity=0.6)
        if rotation is not None:
            draw_triad(node["axes"], 0.15 * self.arm_length)
        node.set_transform(pose)

    def show_points(
        self,
        points: npt.ArrayLike,
        rgb: npt.ArrayLike = (0.15, 0.45, 0.9),
        size: float | None = None,
        name: str = "points",
    ) -> int:
        """Draw a point cloud in the world frame (e.g. a workspace sample).

        Args:
            points: Positions [m], shape (N, 3).
            rgb: One color (3,) or one per point (N, 3), RGB in [0, 1].
            size: Point size [m] (default 1 % of the arm's length).
            name: Marker name (``markers/<name>``); a second call with it replaces the first.

        Returns:
            The number of points drawn.

        Raises:
            ViewerInputError: Malformed points or colors.
        """
        size = 0.01 * self.arm_length if size is None else float(size)
        return draw_points(self.scene["markers"][name], points, rgb, size)

    def show_path(
        self, q_path: npt.ArrayLike, dt: float = 1.0 / 30.0, repetitions: int = 1
    ) -> float:
        """Animate the arm (and followed frames) along joint vectors, ``dt`` apart.

        The page or browser plays it once loaded; meshcat's "Animations" controls replay and
        scrub it. The still scene shows the last configuration.

        Args:
            q_path: Joint vectors, shape (K, nq), K >= 2 [rad] or [m].
            dt: Time between two vectors [s].
            repetitions: How many times the animation plays.

        Returns:
            The animation's duration [s].

        Raises:
            ViewerInputError: Fewer than two vectors, or ``dt`` not positive.
            kin.JointVectorError: A vector of the wrong size or not finite.
        """
        path = [as_joint_vector(self.robot, q) for q in np.asarray(q_path, dtype=float)]
        if len(path) < 2 or not (np.isfinite(dt) and dt > 0.0):
            raise ViewerInputError(f"a path needs >= 2 joint vectors and dt > 0, got {len(path)}")
        animation = meshcat.animation.Animation(default_framerate=1.0 / dt)
        for index, q in enumerate(path):
            with animation.at_frame(self.viewer, index) as frame:
                self._place(q, frame)
        self.display(path[-1])
        self.viewer.set_animation(animation, play=True, repetitions=int(repetitions))
        return (len(path) - 1) * dt

    def set_camera(self, target: npt.ArrayLike, position: npt.ArrayLike, zoom: float = 1.0) -> None:
        """Aim the camera from ``position`` at ``target`` [m] (:func:`.arm_camera.aim_camera`)."""
        aim_camera(self, target, position, zoom)

    def set_view(self, view: CameraView) -> None:
        """Place the camera as ``view`` says (:meth:`set_camera`)."""
        self.set_camera(view.target, view.position, view.zoom)

    def framed_view(
        self,
        extra_points: npt.ArrayLike | None = None,
        configurations: Sequence[npt.ArrayLike] | None = None,
    ) -> CameraView:
        """The view of the arm at ``configurations`` and ``extra_points`` (:mod:`.arm_camera`)."""
        return framed_view(self, extra_points, configurations)

    def fit_camera(
        self,
        extra_points: npt.ArrayLike | None = None,
        configurations: Sequence[npt.ArrayLike] | None = None,
        zoom: float = 1.0,
    ) -> CameraView:
        """Place the camera at :meth:`framed_view`, magnified ``zoom`` times more; returns the view."""
        view = self.framed_view(extra_points, configurations)
        view = CameraView(view.target, view.position, view.zoom * zoom)
        self.set_view(view)
        return view

    def static_html(self) -> str:
        """The scene as one self-contained HTML page (meshcat's export, three.js inlined)."""
        return self.viewer.static_html()

    def close(self) -> None:
        """Close the connection to the meshcat server and stop it, if this viewer started one.

        The socket is closed here, not left to pyzmq's finalizer at interpreter exit (where a
        second Ctrl-C printed an "Exception ignored" traceback); unsent messages are dropped.
        """
        socket = getattr(self.viewer.window, "zmq_socket", None)
        if isinstance(socket, zmq.Socket) and not socket.closed:
            socket.close(linger=0)
        process = getattr(self.viewer.window, "server_proc", None)
        if process is not None and process.poll() is None:
            process.kill()
            process.wait()

    def _place(self, q: np.ndarray, viewer: object) -> None:
        """Write the poses at ``q`` to ``viewer`` (the live one or an animation frame)."""
        live = self._pin.viewer
        self._pin.viewer = viewer
        try:
            self._pin.display(q if self.meshes is None else self.meshes.full_q(q))
        finally:
            self._pin.viewer = live
        data = self._frames
        pin.forwardKinematics(self.robot.model, data, q)
        for name, frame_id in self._followed.items():
            pin.updateFramePlacement(self.robot.model, data, frame_id)
            viewer["scene/frames"][name].set_transform(data.oMf[frame_id].homogeneous)  # type: ignore[index]
        for rider in self.riders.values():
            viewer[rider.node].set_transform(rider_pose(data, rider))  # type: ignore[index]


def _open_viewer(serve: bool) -> meshcat.Visualizer:
    """A meshcat visualizer over a new server process, or over a :class:`SceneRecorder`."""
    if not serve:
        return meshcat.Visualizer(window=SceneRecorder())
    try:
        with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints its URL itself
            return meshcat.Visualizer()
    except (RuntimeError, OSError) as err:
        raise ViewerError(f"the meshcat server did not start: {err}") from err


def _arm_length(robot: RobotModel, q: np.ndarray) -> float:
    """Length of the chain of frame origins, base to tool, at ``q`` [m] (a scale for markers)."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    origins = np.array([frame.translation for frame in data.oMf])
    length = float(np.linalg.norm(np.diff(origins, axis=0), axis=1).sum())
    return max(length, 0.05)
