"""Show a robot in the browser (meshcat): its URDF visuals, base and tool frames, a target.

The arm stands at --q (default zeros, clipped to the limits). --frames adds an axis triad on
every DH frame (frame0..frameN; x red, y green, z blue): a wrong twist sign shows at a glance.
--target marks a tool position (a sphere; with --rpy, URDF roll-pitch-yaw, also a triad); --ik
solves it from --q and animates the joint-space motion to the answer (meshcat's "Animations"
controls replay it). --plan FILE animates the plan `kin plan -o FILE.json` wrote (its robot
when --robot is not given), --path FILE a joint path written by `kin path --json` (in real
time when it was timed with --time), and both draw the tool's trace; --workspace N draws the tool
points of N joint vectors drawn uniformly within the limits (seeded), colored by height;
--reach FILE.npz draws the voxels of a `kin reach` map, colored by index (viridis, as its PNG).
--scene FILE (a TOML cell, a PlanningScene or a URDF) draws the cell's objects in grey and the
objects its [[attached]] entries hang on links in teal (they move with the arm); with it or
--srdf, the links and objects in collision at the shown configuration turn red and a magenta rod
joins the closest pair's witness points (its distance on stdout, in the page's title and in a
caption at the page's foot).

The camera frames the arm (every configuration shown, the target, a path's trace, a workspace
or reach cloud) so that it fills at least a third of the picture where a side allows, from a
side where no object of the cell hides it; the cell around the arm shows, not all of it.
--camera X Y Z TX TY TZ puts the camera at X Y Z looking at TX TY TZ instead (base frame,
in --unit); --zoom F magnifies the view F times (2: twice as large; with or without --camera).

Without --html or --png: start meshcat's server, print the viewer URL and serve until Ctrl-C
(exit 130). With --html FILE: write one self-contained page (three.js inlined; no server, no
network needed to view it) and exit. With --png FILE: write an 800 x 600 picture of that page
taken by headless Chromium (Debian: apt-get install chromium), after any animation has played.

Units: every length (target, camera, prismatic joint values) in --unit; revolute joint values
and --rpy in radians, degrees with --deg. Exit 0, 1 when --ik finds no valid solution (--html,
--png) or the browser fails, 2 for bad input (and for --png without Chromium).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING

from dh2urdf.command_line import whole_number
from dh2urdf.output_text import shown_name

from ..cli import (
    ArgumentParser,
    angle_scale,
    finite_float,
    length_scale,
    positive_float,
    run_guarded,
)
from .collision_options import add_collision_options
from .preview_picture import (
    add_picture_options,
    check_outputs,
    check_picture_options,
    place_camera,
    write_still,
)

if TYPE_CHECKING:
    import numpy as np

    from ..ik.targets.target import Target
    from ..robot_model import RobotModel
    from .joint_units import JointUnits

PROG = "kin preview"
EXIT_NO_SOLUTION = 1
#: Points of --workspace without a count, and the most it takes (a page stays light).
WORKSPACE_POINTS = 20_000
MAX_WORKSPACE_POINTS = 1_000_000
#: Color of the tool's trace along a --path (RGB in [0, 1]).
TRACE_RGB = (0.95, 0.55, 0.1)


def get_argument_parser(prog: str = PROG) -> ArgumentParser:
    """Command-line arguments of ``kin preview``."""
    parser = ArgumentParser(prog=prog, description=__doc__)
    add = parser.add_argument
    from .robot_argument import add_robot_arguments

    add_robot_arguments(parser, required=False)  # --plan names its own
    add(
        "--q",
        type=finite_float,
        nargs="+",
        help="joint values, base to tip: revolute [rad, or deg with --deg], prismatic [--unit]",
    )
    add("--deg", action="store_true", help="revolute joint values and angles in degrees")
    add("--unit", choices=("m", "cm", "mm"), default="m", help="unit of every length (default m)")
    add(
        "--target",
        type=finite_float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="tool target position in the world frame [--unit]",
    )
    add(
        "--rpy",
        type=finite_float,
        nargs=3,
        metavar=("R", "P", "Y"),
        help="target orientation: URDF roll-pitch-yaw [rad, or deg with --deg]",
    )
    add("--ik", action="store_true", help="solve the target and animate the motion from --q")
    add("--frames", action="store_true", help="axis triads on every DH frame")
    add("--plan", metavar="FILE", help="animate a plan written by kin plan -o FILE.json")
    add("--path", metavar="FILE", help="animate a joint path written by kin path --json")
    add(
        "--workspace",
        type=whole_number,
        nargs="?",
        const=WORKSPACE_POINTS,
        metavar="N",
        help=f"draw the tool points of N random joint vectors (default N {WORKSPACE_POINTS:,})",
    )
    add("--reach", metavar="FILE.npz", help="draw the voxels of a kin reach map by index")
    add_collision_options(
        parser,
        scene="draw a cell (TOML of boxes... or URDF) and check it",
        srdf="a MoveIt SRDF: its disable_collisions pairs are allowed",
        self_check=True,
    )
    add_picture_options(parser)
    add(
        "--duration", type=positive_float, default=2.0, help="--ik animation length [s] (default 2)"
    )
    add(
        "--timeout",
        type=positive_float,
        default=200.0,
        help="numeric IK time budget [ms] (default 200)",
    )
    return parser


def main(argv: list[str] | None = None, prog: str = PROG) -> int:
    """Preview; exit 0, 1 (--ik without a valid solution, --html), 130 (Ctrl-C) or 2."""
    parser = get_argument_parser(prog)
    args = parser.parse_args(argv)
    if args.ik and args.target is None:
        parser.error("--ik needs --target X Y Z")
    if args.rpy is not None and args.target is None:
        parser.error("--rpy needs --target X Y Z")
    animations = [name for name in ("plan", "path", "ik") if getattr(args, name)]
    if len(animations) > 1:
        given = " or ".join(f"--{name}" for name in animations)
        parser.error(
            f"give {given}, not {'both' if len(animations) == 2 else 'all'} (each is an animation)"
        )
    if args.robot is None and args.plan is None:
        parser.error("the following arguments are required: --robot (or --plan FILE)")
    if args.workspace is not None and not 1 <= args.workspace <= MAX_WORKSPACE_POINTS:
        parser.error(f"--workspace: expected 1 to {MAX_WORKSPACE_POINTS:,} points")
    check_picture_options(parser, args)
    return run_guarded(prog, lambda: _run_held(args, prog), extra=(ModuleNotFoundError,))


def _run_held(args: argparse.Namespace, prog: str) -> int:
    """:func:`_run` with Ctrl-C (and SIGTERM) held while the scene is built, raised after.

    The build imports meshcat, pyzmq, trimesh and networkx on first use; trimesh wraps its
    optional imports in ``except BaseException``, so a ``KeyboardInterrupt`` raised inside one
    was swallowed (the server then served until a second Ctrl-C), and one raised inside a
    finalizer (pyzmq's ``Socket.__del__``) printed an "Exception ignored" traceback. Held, the
    signal is only noted (:class:`~.interrupt_gate.InterruptGate`) and raised once the page is
    written or the server is about to wait; a second one raises at once.
    """
    from .interrupt_gate import interrupt_gate

    with interrupt_gate() as gate:
        gate.hold()
        code = _run(args, prog, gate.release)
        gate.release()  # a Ctrl-C while the page was written: 130 (the page is whole)
        return code


def _run(args: argparse.Namespace, prog: str, release: Callable[[], None]) -> int:
    """Build the scene, then write the page or serve it (``release``: Ctrl-C raises again)."""
    import numpy as np

    from ..configuration import limit_violations
    from .joint_units import JointUnits, limits_line
    from .robot_argument import load_robot_argument
    from .targets import build_target

    check_outputs(args)
    if args.plan is not None:
        from .preview_plan import check_plan_robot, plan_robot, read_plan

        plan = read_plan(args.plan)
        args.robot = plan_robot(args.plan, plan, args.robot)
    robot = load_robot_argument(args)
    if args.plan is not None:
        check_plan_robot(args.plan, plan, robot.name)
    units = JointUnits.of(robot.name, robot.table, args.unit, args.deg)
    if args.q is None:
        q_start = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    else:
        q_start = units.to_si(args.q, "--q", warn_units=False)
    slip = None if args.q is None else units.unit_slip(args.q, "--q")
    warning = limits_line(limit_violations(robot, q_start), slip)
    if warning is not None:  # one line
        print(f"{prog}: warning: {warning}", file=sys.stderr)
    target = None
    if args.target is not None:
        length = length_scale(args.unit)
        target, _ = build_target(
            args.target, rpy=args.rpy, length=length, angle=angle_scale(args.deg)
        )
    q_goal = None
    if args.ik and target is not None:
        q_goal = _solve(robot, target, q_start, args, units, prog)
    animated = None
    if args.path is not None or args.plan is not None:
        option = "--path" if args.plan is None else "--plan"
        animated = _path_frames(robot, args.path or args.plan, args.duration, option)
        q_start = animated[1][0]

    model = None
    if args.scene is not None or args.srdf is not None:
        from .preview_collisions import load_model

        model = load_model(robot, args)

    from ..viewer import RobotViewer  # meshcat: only now

    static = args.html is not None or args.png is not None
    viewer = RobotViewer(robot, serve=not static)
    try:
        if model is not None and model.attached:  # before an animation: they ride through it
            from ..viewer.collision_view import show_attached

            show_attached(viewer, model)
        viewer.show_frames(["base_link", robot.tool_frame])
        if args.frames:
            dh_frames = [f"frame{i}" for i in range(len(robot.table.rows) + 1)]
            viewer.show_frames(dh_frames, length=0.06 * viewer.arm_length)
        viewer.display(q_start)
        if target is not None:
            viewer.show_target(target.position, getattr(target, "rotation", None))
        played = 0.0  # animation length [s]
        if q_goal is not None:
            steps = max(2, int(round(args.duration * 30)) + 1)
            path = np.linspace(q_start, q_goal, steps)
            played = viewer.show_path(path, dt=args.duration / (steps - 1))
        in_view = [q_start] if q_goal is None else [q_start, q_goal]
        extra = [] if target is None else [target.position]
        if animated is not None:
            from ..batch_fk import batch_tool_positions

            samples, frames, dt = animated
            trace = batch_tool_positions(robot.table, samples)
            viewer.show_points(trace, rgb=TRACE_RGB, size=0.012 * viewer.arm_length, name="trace")
            played = viewer.show_path(frames, dt=dt)
            extra.extend(trace)
            in_view.append(frames[-1])
        if args.workspace is not None:
            cloud = _workspace_points(robot, args.workspace)
            viewer.show_points(cloud, rgb=_height_colors(cloud), name="workspace")
            extra.extend(cloud[:: max(1, len(cloud) // 2000)])
        if args.reach is not None:
            extra.extend(_reach_voxels(viewer, robot.name, args.reach))
        title = None
        if model is not None:
            from .preview_collisions import show_collisions

            title = show_collisions(viewer, model, args)
        place_camera(viewer, args, np.array(extra).reshape(-1, 3) if extra else None, in_view)
        if static:
            write_still(viewer, args, title, played)
            return EXIT_NO_SOLUTION if args.ik and q_goal is None else 0
        release()  # raises a Ctrl-C (SIGTERM) that came while the scene was built
        print(viewer.url, flush=True)
        while True:  # short naps: a signal taken by another thread is seen within one
            time.sleep(0.5)
    finally:
        viewer.close()


def _solve(
    robot: RobotModel,
    target: Target,
    q_start: np.ndarray,
    args: argparse.Namespace,
    units: JointUnits,
    prog: str,
) -> np.ndarray | None:
    """The valid IK answer closest to ``q_start`` [rad, m], or None after a warning line."""
    from ..ik.exceptions import StructureError
    from .solver_choice import choose_solver, solve_function, target_kinds
    from .targets import check_kind

    try:
        solver = choose_solver(robot)
    except StructureError:  # no closed form: the numeric solver takes any chain
        solver = choose_solver(robot, "mink")
    kinds = target_kinds(solver)
    if kinds is not None:
        given = "--rpy" if args.rpy is not None else "a position target"
        check_kind(robot.name, robot.nq, kinds, target, given)
    result = solve_function(solver, args.timeout / 1e3)(target, q_start)
    if not result.solutions:
        print(f"{prog}: warning: no IK solution: {result.message}", file=sys.stderr)
        return None
    q_goal = result.solutions[0].q
    shown = ", ".join(f"{v:.4g} {u}" for v, u in zip(units.from_si(q_goal), units.labels))
    branch = result.solutions[0].branch or result.method or result.solver
    print(f"{shown_name(robot.name)}: IK ({branch}): q = {shown}")
    return q_goal


def _path_frames(
    robot: RobotModel, file: str, duration: float, option: str
) -> tuple[np.ndarray, np.ndarray, float]:
    """Samples and animation frames [rad, m], frame interval [s] of a ``kin path --json`` file.

    Or of a ``kin plan`` file (``option`` ``--plan``): both hold ``q`` and ``t_s`` in SI.
    """
    from pathlib import Path

    from ..path.exceptions import PathError
    from ..path.joint_path_file import animation_frames, read_joint_path

    if not Path(file).is_file():
        raise PathError(f"{option} {file}: no such file", option)
    joint_path = read_joint_path(file, robot.nq)
    if joint_path.robot and joint_path.robot != robot.name:
        raise PathError(
            f"{option} {file} was computed for '{joint_path.robot}', not '{robot.name}': give "
            f"--robot {joint_path.robot} (or a {option[2:]} of this robot)",
            option,
        )
    frames, dt = animation_frames(joint_path, duration)
    return joint_path.q, frames, dt


def _reach_voxels(viewer: object, robot: str, file: str) -> list[np.ndarray]:
    """Draw the map of ``kin reach`` in ``file``; some of its voxel centres [m] (for the camera)."""
    from ..exceptions import KinError
    from ..reach.map import load_reach_map
    from ..viewer.reach_voxels import show_reach_voxels

    reach_map = load_reach_map(file)
    if reach_map.robot and reach_map.robot != robot:
        raise KinError(
            f"--reach {file} was computed for '{reach_map.robot}', not '{robot}': give "
            f"--robot {reach_map.robot} (or a map of this robot)"
        )
    drawn = show_reach_voxels(viewer, reach_map.centers_m, reach_map.index, reach_map.voxel_m)
    return list(drawn[:: max(1, len(drawn) // 2000)])


def _workspace_points(robot: RobotModel, count: int) -> np.ndarray:
    """Tool points [m] of ``count`` joint vectors drawn uniformly within the limits (seed 0)."""
    import numpy as np

    from ..batch_fk import batch_tool_positions

    rng = np.random.default_rng(0)
    q = rng.uniform(robot.lower, robot.upper, size=(count, robot.nq))
    return batch_tool_positions(robot.table, q)


def _height_colors(points: np.ndarray) -> np.ndarray:
    """RGB per point from blue (lowest) to orange (highest), by the world z coordinate."""
    import numpy as np

    z = points[:, 2]
    span = float(z.max() - z.min())
    s = (z - z.min()) / span if span > 0.0 else np.zeros_like(z)
    low, high = np.array([0.15, 0.35, 0.9]), np.array([0.95, 0.5, 0.1])
    return low + s[:, None] * (high - low)
