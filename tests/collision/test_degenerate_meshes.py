"""Degenerate meshes never reach coal's qhull, which killed the process on them (issue 42).

A flat, collinear, NaN or 1e308 mesh as a scene ``[[mesh]]`` or as a robot's ``<collision>``
mesh was a SIGSEGV in ``kin check``, ``kin ik --scene`` and ``kin collisions``. Now a scene's is
one line and exit 2, a robot's one warning naming the file and the link (the link keeps its
other shapes). Whatever could crash runs in a child process: a segfault fails the test, it does
not stop pytest. The property test draws meshes (flat, collinear, duplicate, few, tiny, huge,
far, non-finite vertices), writes them as ASCII or binary STL, and loads each as a scene object
and as a link's collision mesh in one child.
"""

from __future__ import annotations

import logging
import math
import os
import struct
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from support import TESTS
from support.cli_helper import kin_command

ROOT = Path(__file__).resolve().parents[2]
#: This module's own folder (os.path, not Path: a mover of test files keeps it): children import it.
HERE = os.path.dirname(os.path.abspath(__file__))
#: A command answers in about 1 s idle; the margin is for a busy machine, a hang still fails [s].
TIMEOUT_S = 60
TETRAHEDRON = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
FACES = ((0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2))
CHECK = ["check", "--robot", "ur5", "--q", "0", "-1.5", "1.5", "0", "0", "0"]


def write_stl(path: Path, points: np.ndarray, binary: bool) -> Path:
    """Write ``points`` (3k, 3) as k triangles of an ASCII or binary STL at ``path``."""
    triangles = np.asarray(points, dtype=float).reshape(-1, 3, 3)
    if binary:
        with np.errstate(over="ignore"):  # 1e308 is inf in float32, as a binary STL holds it
            corners = triangles.astype("<f4")
        body = b"".join(
            struct.pack("<3f", 0.0, 0.0, 1.0) + corners[i].tobytes() + b"\0\0"
            for i in range(len(triangles))
        )
        path.write_bytes(b"\0" * 80 + struct.pack("<I", len(triangles)) + body)
        return path
    lines = ["solid test"]
    for triangle in triangles:
        lines += [" facet normal 0 0 1", "  outer loop"]
        lines += ["   vertex " + " ".join(repr(float(v)) for v in corner) for corner in triangle]
        lines += ["  endloop", " endfacet"]
    path.write_text("\n".join([*lines, "endsolid test", ""]))
    return path


def tetrahedron_stl(path: Path, changed: dict[int, tuple[float, float, float]], binary=False):
    """The unit tetrahedron's four faces, with vertices ``changed`` (index -> point)."""
    points = TETRAHEDRON.copy()
    for index, point in changed.items():
        points[index] = point
    return write_stl(path, points[np.array(FACES).ravel()], binary)


#: Reproducers of the issue, each an STL that crashed qhull, and what the error line says.
CRASHERS = {
    "flat": ({3: (0.3, 0.3, 0.0)}, "in one plane"),
    "collinear": ({1: (1, 0, 0), 2: (2, 0, 0), 3: (3, 0, 0)}, "on one line"),
    "nan": ({3: (math.nan, 0.0, 1.0)}, "not finite"),
    "1e308": ({3: (1e308, 0.0, 1.0)}, "beyond 1000 m"),
    "slab 1e-8": ({3: (0.3, 0.3, 1e-8)}, "in one plane"),
}


def run_child(code: str, cwd: Path, timeout: float = TIMEOUT_S) -> subprocess.CompletedProcess:
    """Run Python ``code`` in a child with the tests folder importable; a crash is its exit code."""
    return subprocess.run(
        [sys.executable, "-X", "faulthandler", "-c", textwrap.dedent(code)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=timeout,
        env={**os.environ, "PYTHONPATH": os.pathsep.join([HERE, str(TESTS), str(ROOT)])},
    )


def in_child(call: str, cwd: Path) -> None:
    """Run ``call`` (a ``check_...`` function of this module) in a child; it must exit 0."""
    done = run_child(f"from test_degenerate_meshes import *\n{call}\n", cwd)
    assert done.returncode == 0, (done.returncode, done.stderr[-3000:])


def run_kin(argv: list[str], cwd: Path) -> tuple[int, str]:
    done = subprocess.run(
        kin_command() + argv,
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )
    return done.returncode, done.stderr


def robot_urdf(folder: Path, mesh: Path, name: str = "arm.urdf") -> Path:
    """The UR5's URDF with ``mesh`` as a second <collision> of link2 (which keeps a cylinder)."""
    text = (ROOT / "urdf" / "ur5.urdf").read_text()
    at = text.index('<collision name="a2_collision">')
    extra = f'<collision name="extra"><geometry><mesh filename="{mesh}"/></geometry></collision>'
    path = folder / name
    path.write_text(text[:at] + extra + "\n    " + text[at:])
    return path


@pytest.mark.parametrize("case", sorted(CRASHERS))
def test_a_degenerate_scene_mesh_is_one_line_in_kin_check_and_kin_ik(case, tmp_path):
    """kin check and kin ik --scene with a crashing mesh: exit 2, one line (was SIGSEGV)."""
    changed, said = CRASHERS[case]
    tetrahedron_stl(tmp_path / "part.stl", changed)
    scene = tmp_path / "scene.toml"
    scene.write_text("[[mesh]]\nfile = 'part.stl'\nxyz = [1.0, 0.0, 0.0]\n")
    for argv in (
        [*CHECK, "--scene", str(scene)],
        ["ik", "--robot", "ur5", "--target", "0.4", "0.1", "0.4", "--scene", str(scene)],
    ):
        code, err = run_kin(argv, tmp_path)
        assert code == 2, (argv, code, err[-1000:])
        lines = err.strip().splitlines()
        assert len(lines) == 1, err
        assert "scene.toml: mesh[0].file: cannot read the mesh" in lines[0] and said in lines[0]
        assert "part.stl" in lines[0] and "Traceback" not in err, lines[0]


@pytest.mark.parametrize("case", sorted(CRASHERS))
def test_a_degenerate_robot_mesh_is_one_warning_and_the_link_keeps_its_cylinder(case, tmp_path):
    """kin collisions --write-srdf on a URDF with a crashing <collision> mesh: one warning naming
    the file and the link, exit 0, and the SRDF written (was SIGSEGV)."""
    changed, said = CRASHERS[case]
    mesh = tetrahedron_stl(tmp_path / "part.stl", changed, binary=case != "nan")
    urdf = robot_urdf(tmp_path, mesh)
    code, err = run_kin(["collisions", "--robot", str(urdf), "--write-srdf", "out.srdf"], tmp_path)
    assert code == 0, (code, err[-1000:])
    warnings = [line for line in err.splitlines() if "left without this shape" in line]
    assert len(warnings) == 1, err
    assert "arm.urdf" in warnings[0] and "'link2'" in warnings[0] and "part.stl" in warnings[0]
    assert said in warnings[0] or case == "1e308", warnings[0]  # binary: 1e308 is inf
    assert len(err.strip().splitlines()) == 2 and "Traceback" not in err, err  # + the summary
    assert (tmp_path / "out.srdf").read_text().startswith("<")


def check_robot_link_keeps_its_cylinder(folder: str) -> None:
    """In the child: the link with a flat mesh keeps its cylinders; one warning.

    The shapes link2 keeps are counted in the URDF itself: its <collision> cylinders (the DH
    table's ``a2`` segment and, since the tables have volumes, its housings), without the mesh.
    """
    import coal
    from lxml import etree

    import kin
    from kin.collision import load_collision_model

    work = Path(folder)
    urdf = robot_urdf(work, tetrahedron_stl(work / "flat.stl", CRASHERS["flat"][0]))
    records: list[str] = []
    handler = logging.Handler()
    handler.emit = lambda record: records.append(record.getMessage())  # type: ignore[method-assign]
    logging.getLogger("kin.collision").addHandler(handler)
    model = load_collision_model(kin.load_robot(str(urdf)))
    assert [message.count("flat.stl") for message in records] == [1], records
    link2 = etree.parse(str(urdf)).find("link[@name='link2']")
    cylinders = link2.findall("collision/geometry/cylinder")
    assert len(link2.findall("collision")) == len(cylinders) + 1 >= 2  # the mesh and cylinders
    kept = [
        thing.geometry
        for thing, owner in zip(model.geometry_model.geometryObjects, model.owners, strict=True)
        if owner == "link2"
    ]
    assert len(kept) == len(cylinders), (kept, len(cylinders))  # the cylinders, not the mesh
    assert all(isinstance(shape, coal.Cylinder) for shape in kept), kept
    assert sorted(shape.radius for shape in kept) == sorted(
        float(cylinder.get("radius")) for cylinder in cylinders
    )


def test_the_robot_link_keeps_its_other_shapes(tmp_path):
    """A link with a flat <collision> mesh and a cylinder keeps the cylinder (in a child)."""
    in_child(f"check_robot_link_keeps_its_cylinder({str(tmp_path)!r})", tmp_path)


@pytest.mark.parametrize(
    ("name", "content", "said"),
    [
        ("folder.stl", "folder", "a folder"),
        ("fifo.stl", "fifo", "a FIFO"),
        ("loop.stl", "loop", "a loop of symbolic links"),
        ("zero.stl", "device", "a character device"),
        ("junk.stl", b"junk", "not an STL file"),
        ("short.stl", b"\0" * 80 + struct.pack("<I", 2_000_000) + b"\0" * 50, "2,000,000"),
        ("empty.stl", b"solid x\nendsolid x\n", "no triangles"),
        ("word.stl", b"solid x\n vertex 0 0 zero\nendsolid x\n", "'zero' is not a number"),
        ("gone.stl", None, "mesh not found"),
    ],
)
def test_a_mesh_that_is_not_one_says_what_it_is(name, content, said, tmp_path):
    """A folder, FIFO, link loop, device or junk as a mesh: named as what it is, not "not found"
    (the FIFO is never opened: the call returns)."""
    from kin.collision.urdf_shapes import load_mesh

    path = tmp_path / name
    if content == "folder":
        path.mkdir()
    elif content == "fifo":
        os.mkfifo(path)
    elif content == "loop":
        path.symlink_to(path)
    elif content == "device":
        path.symlink_to("/dev/zero")
    elif content is not None:
        path.write_bytes(content)
    with pytest.raises(OSError) as caught:
        load_mesh(path, np.ones(3))
    message = str(caught.value)
    assert said in message and name in message and "\n" not in message, message


def test_a_2_million_triangle_stl_is_refused_from_its_size(tmp_path):
    """A 100 MB binary STL (2 million triangles, qhull ran for minutes deaf to Ctrl-C): refused
    before it is read."""
    from kin.collision.urdf_shapes import load_mesh

    path = tmp_path / "huge.stl"
    with path.open("wb") as handle:
        handle.write(b"\0" * 80 + struct.pack("<I", 2_000_000))
        handle.truncate(84 + 50 * 2_000_000)  # sparse
    with pytest.raises(OSError, match=r"100,000,084 bytes, more than the 32 MiB.*decimate"):
        load_mesh(path, np.ones(3))


def test_more_vertices_than_the_cap_are_refused(tmp_path, monkeypatch):
    """More distinct vertices than MAX_MESH_VERTICES: refused (not simplified), one line."""
    from kin.collision import mesh_file
    from kin.collision.urdf_shapes import load_mesh

    rng = np.random.default_rng(0)
    points = rng.normal(size=(3 * 40, 3))
    write_stl(tmp_path / "many.stl", points, binary=True)
    monkeypatch.setattr(mesh_file, "MAX_MESH_VERTICES", 100)
    with pytest.raises(OSError, match=r"120 distinct vertices, more than the 100"):
        load_mesh(tmp_path / "many.stl", np.ones(3))
    monkeypatch.setattr(mesh_file, "MAX_MESH_VERTICES", 120)
    assert load_mesh(tmp_path / "many.stl", np.ones(3)).num_points >= 4


def check_non_finite_obj(folder: str) -> None:
    """In the child: OBJ meshes with a NaN or 1e308 vertex (coal's loader reads them)."""
    from kin.collision.urdf_shapes import load_mesh

    for value in ("nan", "1e308"):
        path = Path(folder) / f"{value}.obj"
        corners = "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + f"v {value} 0 1\n"
        path.write_text(corners + "f 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
        with pytest.raises(OSError, match=r"vertex 4 of 4 is not finite after scaling"):
            load_mesh(path, np.ones(3))


def test_a_non_finite_obj_is_one_line_and_coal_says_nothing(tmp_path):
    """A NaN or 1e308 OBJ (through coal's loader): refused, and Eigen's "too many iterations"
    lines that the loader printed on stderr are not shown (in a child: its hull crashed)."""
    done = run_child(
        f"from test_degenerate_meshes import *\ncheck_non_finite_obj({str(tmp_path)!r})", tmp_path
    )
    assert done.returncode == 0 and done.stderr == "", (done.returncode, done.stderr[-3000:])


def test_coal_loader_messages_lose_the_source_location(tmp_path):
    """A mesh coal's loader refuses (OBJ): its reason kept, its C++ file and line dropped."""
    from kin.collision.urdf_shapes import load_mesh

    (tmp_path / "one.obj").write_text("v 0 0 0\n")
    with pytest.raises(OSError) as caught:
        load_mesh(tmp_path / "one.obj", np.ones(3))
    message = str(caught.value)
    assert "OBJ-file is too small" in message, message
    assert "assimp.cpp" not in message and "line" not in message and "\n" not in message


@pytest.mark.parametrize("binary", [False, True])
def test_a_good_stl_gives_the_hull_of_its_vertices(binary, tmp_path):
    """A scaled tetrahedron: a hull whose points are its four corners times the scale."""
    from kin.collision.urdf_shapes import load_mesh

    path = tetrahedron_stl(tmp_path / "tet.stl", {}, binary=binary)
    hull = load_mesh(path, np.array([0.5, 2.0, 3.0]))
    corners = sorted(tuple(point) for point in np.round(hull.points(), 9).tolist())
    assert corners == [(0, 0, 0), (0, 0, 3), (0, 2, 0), (0.5, 0, 0)]


#: Slabs (size [m], thickness [m], offset [m]) and what comes of them: a hull (True), refused
#: as flat (False), refused as too far or too long (the error's words).
SLABS = [
    (1.0, 1e-3, 0.0, True),
    (1.0, 1e-6, 0.0, False),  # 1e-6 of its length: qhull crashed from 1e-7
    (1e-3, 5e-6, 0.0, True),
    (1e-3, 5e-6, 999.0, True),  # at the coordinate bound: the round-off margin is 1e-8 m
    (1e-3, 5e-6, 9e5, "beyond 1000 m"),  # 900 km away (qhull's round-off crashed such slabs)
    (11.0, 1.0, 0.0, "more than the 10 m"),  # longer than a collision shape may measure
]


def check_slabs(folder: str) -> None:
    """In the child: each slab of SLABS is a hull or refused as flat."""
    from kin.collision.urdf_shapes import load_mesh

    for size, thickness, offset, solid in SLABS:
        corners = np.array([[0, 0, 0], [size, 0, 0], [0, size, 0], [size, size, thickness]])
        path = write_stl(
            Path(folder) / "slab.stl", (corners + offset)[np.array(FACES).ravel()], False
        )
        if solid is True:
            assert load_mesh(path, np.ones(3)).num_points == 4, (size, thickness, offset)
        else:
            with pytest.raises(OSError, match="in one plane" if solid is False else solid):
                load_mesh(path, np.ones(3))


def test_the_flatness_bound_follows_size_and_distance(tmp_path):
    """A slab: a hull when thicker than 1e-5 of its length and 1e-11 of its largest coordinate
    (in a child: a slab too thin crashed qhull)."""
    in_child(f"check_slabs({str(tmp_path)!r})", tmp_path)


# --- property: any drawn mesh is a hull, one error line or one warning, never a crash ---------

#: Sizes [m], offsets [m] and flattening ratios drawn: the usual first, then the extremes, with
#: ratios just above the flatness bound (1e-5) where qhull is closest to failing.
_SCALES = [1.0, 0.1, 1e-3, 10.0, 1e-6, 1e-9, 1e-12, 1e5, 1e6, 1e7, 1e-300, 1e-320, 1e308]
_OFFSETS = [0.0, 1.0, 1e3, 1e5, 5e5, 1e6, 1e9]
_FLAT = [1.0, 0.1, 1e-4, 2e-5, 1.2e-5, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-12, 1e-16, 0.0]
_POISON = [math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-320, 1e7]


@st.composite
def degenerate_meshes(draw: st.DrawFn) -> tuple[np.ndarray, bool]:
    """Triangle corners (3k, 3) of a drawn mesh, and whether to write it as binary STL."""
    count = draw(st.integers(1, 40))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    points = rng.uniform(-1.0, 1.0, size=(count, 3))
    points[:, 2] *= draw(st.sampled_from(_FLAT))
    if draw(st.booleans()):
        points[:, 1] *= draw(st.sampled_from(_FLAT))  # collinear when both are small
    rotation = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    points = points @ rotation.T * draw(st.sampled_from(_SCALES))
    points += draw(st.sampled_from(_OFFSETS))
    if draw(st.booleans()):
        points = np.repeat(points, draw(st.integers(2, 5)), axis=0)  # duplicate vertices
    if draw(st.integers(0, 3)) == 0:
        points[draw(st.integers(0, len(points) - 1)), draw(st.integers(0, 2))] = draw(
            st.sampled_from(_POISON)
        )
    corners = np.resize(points, (3 * math.ceil(len(points) / 3), 3))
    return corners, draw(st.booleans())


def check_drawn_meshes_in_this_process(examples: int, folder: str) -> None:
    """Run the property here (in the child): each mesh as a scene object and a link's mesh."""
    import coal

    from kin.collision.scene import read_scene
    from kin.collision.urdf_shapes import link_shapes
    from kin.exceptions import CollisionModelError

    work = Path(folder)
    warnings: list[str] = []

    class Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            warnings.append(record.getMessage())

    logging.getLogger("kin.collision").addHandler(Keep())

    @settings(
        max_examples=examples,
        deadline=None,
        database=None,
        derandomize=True,
        suppress_health_check=list(HealthCheck),
    )
    @given(degenerate_meshes())
    def check(drawn: tuple[np.ndarray, bool]) -> None:
        corners, binary = drawn
        mesh = write_stl(work / "drawn.stl", corners, binary)
        print("trying", binary, repr(corners.tolist())[:3000], file=sys.stderr, flush=True)
        scene = work / "scene.toml"
        scene.write_text("[[mesh]]\nfile = 'drawn.stl'\n")
        try:
            shapes = read_scene(scene)
        except CollisionModelError as err:
            message = str(err)
            assert message.startswith(f"{scene}: mesh[0].file: "), message
            assert "\n" not in message and len(message) < 500, message
            hull = None
        else:
            hull = shapes[0].geometry
            assert hull.num_points >= 4
            request, result = coal.DistanceRequest(), coal.DistanceResult()
            far = coal.Transform3s()
            far.setTranslation(np.array([5.0, 0.0, 0.0]))
            coal.distance(hull, coal.Transform3s(), coal.Sphere(0.1), far, request, result)
        root = ET.fromstring(
            "<robot name='r'><link name='l'>"
            "<collision><geometry><box size='1 1 1'/></geometry></collision>"
            f"<collision><geometry><mesh filename='{mesh}'/></geometry></collision>"
            "</link></robot>"
        )
        warnings.clear()
        made = link_shapes(root, ["l"], str(work / "arm.urdf"), strict_meshes=False)
        kinds = [shape.kind for shape in made]
        if hull is None:
            assert kinds == ["box"] and len(warnings) == 1, (kinds, warnings)
            assert "'l'" in warnings[0] and "drawn.stl" in warnings[0], warnings
        else:
            assert kinds == ["box", "mesh"] and not warnings, (kinds, warnings)

    check()


def test_drawn_degenerate_meshes_never_crash(tmp_path):
    """Hypothesis: flat, collinear, duplicate, few, tiny, huge, far and non-finite meshes as
    ASCII and binary STL, as a scene object and a link's mesh: a hull, or one error line, or
    one warning; never a crash (the child's exit code would say so)."""
    done = run_child(
        f"""
        from test_degenerate_meshes import check_drawn_meshes_in_this_process
        check_drawn_meshes_in_this_process(300, {str(tmp_path)!r})
        """,
        tmp_path,
    )
    last = [line for line in done.stderr.splitlines() if line.startswith("trying")][-1:]
    assert done.returncode == 0, (done.returncode, last, done.stderr[-3000:])


@pytest.mark.slow
def test_many_drawn_degenerate_meshes_never_crash(tmp_path):
    """The same property over 3,000 meshes."""
    done = run_child(
        f"""
        from test_degenerate_meshes import check_drawn_meshes_in_this_process
        check_drawn_meshes_in_this_process(3000, {str(tmp_path)!r})
        """,
        tmp_path,
        timeout=20 * TIMEOUT_S,
    )
    last = [line for line in done.stderr.splitlines() if line.startswith("trying")][-1:]
    assert done.returncode == 0, (done.returncode, last, done.stderr[-3000:])
