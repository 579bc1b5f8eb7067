"""dh2urdf on tables with extreme values, every shipped table (issue 19, hypothesis).

Each example takes a shipped table and sets one to three numbers (a, alpha, d, theta, a limit,
a base or tool coordinate) to an extreme finite value (1e308, 1e200, the 1e6 m length bound and
just past it, denormals) or a non-finite one, then runs ``dh2urdf TABLE -o OUT`` in-process, as
URDF or MJCF. Never a traceback; exit 0 with a complete file whose every number is finite and whose
Pinocchio model puts the tool where a NumPy DH product of the same table does, or exit 2 with one
line on stderr and no file (nothing half-written).
"""

from __future__ import annotations

import copy
import math
import re
import sys
import tempfile
import warnings
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st
from lxml import etree
from support.cli_helper import call
from support.dh_reference import fk_frames, load_reference

from dh2urdf import ROBOTS, get_robot
from dh2urdf.command import main as dh2urdf_main

#: The shipped tables as parsed TOML documents.
DOCUMENTS = {
    name: tomllib.loads(get_robot(name).table_path.read_text(encoding="utf-8")) for name in ROBOTS
}
_METERS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}

EXTREME = st.sampled_from(
    [1e308, -1e308, 1e200, -1e200, 5e-324, -5e-324, 1e-300, 1e3, -1e3, 1e6, -1e6]
    + [1e6 * (1 + 1e-12), 1e9, math.nan, math.inf, -math.inf]
)
_NUMBER = re.compile(r"-?(?:\d+\.?\d*(?:e[-+]?\d+)?|nan|inf)", re.IGNORECASE)


def _toml_value(value: float) -> str:
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    return repr(value)


def _toml(document: dict) -> str:
    """The few shapes a shipped table has, written back as TOML (floats at full precision).

    Top-level keys, ``[[joints]]`` rows with their ``[[joints.housing]]`` tables, ``[base]`` and
    ``[tool]``.
    """

    def value(item) -> str:  # noqa: ANN001
        if isinstance(item, bool):
            return "true" if item else "false"
        if isinstance(item, float):
            return _toml_value(item)
        if isinstance(item, int):
            return str(item)
        if isinstance(item, str):
            return '"' + item.replace("\\", "\\\\").replace('"', '\\"') + '"'
        return "[" + ", ".join(value(v) for v in item) + "]"

    lines = [f"{k} = {value(v)}" for k, v in document.items() if not isinstance(v, dict | list)]
    lines += [
        f"{k} = {value(v)}" for k, v in document.items() if isinstance(v, list) and k != "joints"
    ]

    def tables(item) -> bool:  # noqa: ANN001
        return isinstance(item, list) and bool(item) and all(isinstance(v, dict) for v in item)

    for row in document["joints"]:
        lines += ["", "[[joints]]"] + [f"{k} = {value(v)}" for k, v in row.items() if not tables(v)]
        for key, entries in row.items():  # a row's volumes: [[joints.housing]]
            if tables(entries):
                for entry in entries:
                    lines += [f"[[joints.{key}]]"] + [f"{k} = {value(v)}" for k, v in entry.items()]
    for key, table in document.items():
        if isinstance(table, dict) and key != "drives":
            lines += ["", f"[{key}]"] + [f"{k} = {value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


@st.composite
def extreme_tables(draw: st.DrawFn) -> tuple[str, dict]:
    """A shipped table (without drives) with one to three numbers set to extreme values."""
    name = draw(st.sampled_from(sorted(DOCUMENTS)))
    document = copy.deepcopy(DOCUMENTS[name])
    document.pop("drives", None)
    for _ in range(draw(st.integers(1, 3))):
        extreme = draw(EXTREME)
        where = draw(st.sampled_from(["row", "row", "row", "limit", "base", "tool"]))
        if where in ("base", "tool"):
            document[where] = {"xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}
            key = draw(st.sampled_from(["xyz", "rpy"]))
            document[where][key][draw(st.integers(0, 2))] = extreme
            continue
        row = draw(st.sampled_from(document["joints"]))
        if where == "limit":
            row["limits"] = sorted([extreme, row["limits"][1 - draw(st.integers(0, 1))]])
            if any(math.isnan(v) for v in row["limits"]):
                row["limits"] = [extreme, extreme]
        else:
            row[draw(st.sampled_from(["a", "alpha", "d", "theta"]))] = extreme
    return name, document


def _fk_check(path, urdf_text: str) -> None:
    """Pinocchio's tool pose at q = 0 (clipped into the limits) equals the NumPy DH product's."""
    reference = load_reference(path)
    q = np.clip(np.zeros(reference.dof), reference.lower, reference.upper)
    T_reference = fk_frames(reference, q[None, :])[0, -1]
    model = pin.buildModelFromXML(urdf_text)
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    T = data.oMf[model.getFrameId("tool")].homogeneous
    assert np.all(np.isfinite(T))
    scale = 1.0 + float(np.abs(T_reference[:3, 3]).max())
    np.testing.assert_allclose(T[:3, 3], T_reference[:3, 3], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(T[:3, :3], T_reference[:3, :3], rtol=0, atol=1e-9)


@pytest.mark.parametrize("kind", ["urdf", "mjcf"])
@settings(
    max_examples=100,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(case=extreme_tables())
def test_extreme_table_gives_a_finite_file_or_one_line(kind, case, tmp_path, monkeypatch, capsys):
    """Exit 0: a whole file, every number finite (URDF: FK as NumPy's); exit 2: one line, no file.

    Run in the temporary folder: nothing may appear in the working folder (MuJoCo's log file)."""
    monkeypatch.chdir(tmp_path)
    name, document = case
    folder = Path(tempfile.mkdtemp(dir=tmp_path))  # one per example: hypothesis reuses tmp_path
    path = folder / f"{name}_extreme.toml"
    path.write_text(_toml(document), encoding="utf-8")
    out = folder / f"{name}_extreme.{'urdf' if kind == 'urdf' else 'xml'}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # unit warnings of a long arm are printed, not raised
        code = call(dh2urdf_main, [str(path), "-o", str(out)])
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err, captured.err
    assert code in (0, 2), (code, captured)
    event(f"exit {code}")
    if code == 2:
        assert len(captured.err.strip().splitlines()) == 1, captured.err
        assert str(path) in captured.err, captured.err
        assert not out.exists(), "a file was written although the command failed"
        assert list(folder.iterdir()) == [path], "a temporary file was left behind"
        return
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    text = out.read_text(encoding="utf-8")
    root = etree.fromstring(text.encode("utf-8"))  # a whole XML document
    numbers = [
        float(token)
        for element in root.iter()
        if isinstance(element.tag, str)
        for attribute, value in element.attrib.items()
        if attribute not in ("name", "link", "type", "joint", "body", "class", "mesh", "material")
        for token in value.split()
        if _NUMBER.fullmatch(token)
    ]
    assert numbers and all(map(math.isfinite, numbers)), f"{name=} non-finite number in {out.name}"
    if kind == "urdf":
        _fk_check(path, text)


def test_the_toml_writer_round_trips_every_shipped_table():
    """The test's own TOML writer gives back each shipped document (drives aside)."""
    for name, document in DOCUMENTS.items():
        document = {k: v for k, v in document.items() if k != "drives"}
        assert tomllib.loads(_toml(document)) == document, name


def _meters(row: dict, scale: float) -> dict:
    """A TOML row's body keys (radii, housings) in meters."""
    out: dict = {k: row[k] * scale for k in ("radius", "radius_a", "radius_d") if k in row}
    out["housing"] = [
        {"from": [v * scale for v in h["from"]], "to": [v * scale for v in h["to"]]}
        | {"radius": h["radius"] * scale}
        for h in row.get("housing", [])
    ]
    return out


@pytest.mark.parametrize("name", sorted(DOCUMENTS))
def test_table_text_keeps_each_shipped_row_body(name):
    """table_text writes the radii and housings each shipped row states; read back, same rows."""
    from dh2urdf import parse_table
    from dh2urdf.table_writer import table_text

    table = get_robot(name).load_table()
    written = tomllib.loads(table_text(table))
    scale = _METERS[DOCUMENTS[name].get("length_unit", "m")]
    for index, (row, again) in enumerate(
        zip(DOCUMENTS[name]["joints"], written["joints"], strict=True), start=1
    ):
        expected, got = _meters(row, scale), _meters(again, 1.0)
        assert got.keys() == expected.keys(), f"{name=} {index=}"
        housings, expected_housings = got.pop("housing"), expected.pop("housing")
        assert got == pytest.approx(expected, rel=1e-15), f"{name=} {index=}"
        assert len(housings) == len(expected_housings), f"{name=} {index=}"
        for ours, theirs in zip(housings, expected_housings, strict=True):
            for key in ("from", "to", "radius"):
                assert ours[key] == pytest.approx(theirs[key], rel=1e-15, abs=1e-18), f"{name=}"
    assert parse_table(written, "<round trip>").rows == table.rows, f"{name=}"
