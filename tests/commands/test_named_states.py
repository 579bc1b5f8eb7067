"""Named states as seeds (issue 43 item 8b): a table's ``[states]`` and an SRDF's ``<group_state>``
work wherever a seed does (``kin ik --seed-q ready``, ``kin path --seed-q ready``, ``"seed_q":
"ready"`` on a ``kin ik --stdin`` line), with the answers of the same vector given as numbers; an
unknown name is one line listing the names there are (exit 2)."""

from __future__ import annotations

import io
import json
import math

import numpy as np
import pytest
from support.cli_helper import assert_one_line_error

from dh2urdf import load_table
from dh2urdf.exceptions import TableError
from dh2urdf.table_writer import table_text
from kin import load_robot
from kin.commands import ik, path
from kin.exceptions import NamedStateError
from kin.named_states import named_states

#: MoveIt's Panda ``ready`` (moveit_resources, panda_moveit_config/config/panda.srdf) [rad].
PANDA_READY = ["0", "-0.785", "0", "-2.356", "0", "1.571", "0.785"]
#: The UR driver's MoveIt ``up`` (ur_moveit_config/srdf/ur_macro.srdf.xacro) [rad].
UR_UP = ["0", "-1.5707", "0", "-1.5707", "0", "0"]

#: An SRDF with a full state of UR5's arm (in the file's joint order, not the chain's), a
#: gripper state and a state that overrides the table's "home".
SRDF = """<robot name="ur5">
  <group_state name="folded" group="manipulator">
    <joint name="wrist_3_joint" value="0.3"/>
    <joint name="elbow_joint" value="2.5"/>
    <joint name="shoulder_lift_joint" value="-2.0"/>
    <joint name="shoulder_pan_joint" value="0.1"/>
    <joint name="wrist_1_joint" value="-1.0"/>
    <joint name="wrist_2_joint" value="1.2"/>
  </group_state>
  <group_state name="open" group="gripper">
    <joint name="finger_joint" value="0.04"/>
  </group_state>
  <group_state name="home" group="manipulator">
    <joint name="shoulder_pan_joint" value="1"/><joint name="shoulder_lift_joint" value="-1"/>
    <joint name="elbow_joint" value="1"/><joint name="wrist_1_joint" value="-1"/>
    <joint name="wrist_2_joint" value="1"/><joint name="wrist_3_joint" value="-1"/>
  </group_state>
</robot>
"""


def _q(answer: dict) -> list[float]:
    """The first (nearest) solution's q [rad] of an answer."""
    return answer["solutions"][0]["q"]


def _ik_json(capsys, argv: list[str]) -> dict:
    assert ik.main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_shipped_states_are_the_makers_values():
    """Panda's ready and the URs' home and up, as the MoveIt files write them [rad]."""
    assert named_states(load_robot("panda")).q("ready").tolist() == [float(v) for v in PANDA_READY]
    for robot in ("ur3", "ur5", "ur10"):
        states = named_states(load_robot(robot))
        assert states.names == ("home", "up")
        assert states.q("up").tolist() == [float(v) for v in UR_UP]
        assert states.q("home").tolist() == [0.0, -1.5707, 0.0, 0.0, 0.0, 0.0]


@pytest.mark.parametrize("deg", [False, True])
def test_ik_seed_name_answers_as_the_numbers(capsys, deg):
    """A 7R position target (numeric solver, seeded): the same answer from --seed-q ready as from
    the ready values written out (converted to degrees with --deg)."""
    values = [f"{math.degrees(float(v))!r}" for v in PANDA_READY] if deg else PANDA_READY
    unit = ["--deg"] if deg else []
    common = ["--robot", "panda", "--target", "0.45", "0.1", "0.35", "--position-only", *unit]
    named = _ik_json(capsys, [*common, "--seed-q", "ready"])
    numbers = _ik_json(capsys, [*common, "--seed-q", *values])
    assert named["success"] and _q(named) == pytest.approx(_q(numbers), abs=1e-12)
    unseeded = _ik_json(capsys, common)  # from q = 0: elsewhere, so the seed was used
    assert np.abs(np.subtract(_q(unseeded), _q(named))).max() > 0.5


def test_an_srdf_group_state_is_a_seed_and_overrides_the_tables(tmp_path, capsys):
    """--srdf's full group states are named states (joints matched by name, not order); its
    'home' takes the table's place; a gripper's state says which arm joints it leaves out."""
    srdf = tmp_path / "ur5.srdf"
    srdf.write_text(SRDF)
    states = named_states(load_robot("ur5"), srdf)
    assert states.names == ("up", "folded", "home")
    assert states.q("folded").tolist() == [0.1, -2.0, 2.5, -1.0, 1.2, 0.3]
    assert states.q("home").tolist() == [1.0, -1.0, 1.0, -1.0, 1.0, -1.0]
    with pytest.raises(NamedStateError, match="'open' leaves out joints shoulder_pan_joint"):
        states.q("open")
    common = ["--robot", "ur5", "--target", "0.3", "0.2", "0.4", "--rpy", "3.1", "0", "0"]
    common += ["--srdf", str(srdf)]
    named = _ik_json(capsys, [*common, "--seed-q", "folded"])
    numbers = _ik_json(capsys, [*common, "--seed-q", "0.1", "-2.0", "2.5", "-1.0", "1.2", "0.3"])
    assert named["success"] and _q(named) == _q(numbers)


def test_path_seed_name(capsys):
    """kin path --seed-q up: the path of the numbers' seed (the start's branch is the one near it)."""
    rpy = ["--rpy", "3.14", "0", "0"]
    common = ["--robot", "ur5", "--from", "0.3", "0.2", "0.4", *rpy, "--to", "0.3", "-0.2", "0.4"]
    common += [*rpy, "--steps", "5", "--json"]
    assert path.main([*common, "--seed-q", "up"]) == 0
    named = json.loads(capsys.readouterr().out)
    assert path.main([*common, "--seed-q", *UR_UP]) == 0
    assert json.loads(capsys.readouterr().out) == named
    assert path.main(common) == 0  # from q = 0: another branch, so the seed was used
    assert json.loads(capsys.readouterr().out) != named


def test_stdin_seed_name(monkeypatch, capsys):
    """ "seed_q": "ready" on a line answers as the values do; an unknown name is that line's error
    listing the names, the other lines answered."""
    target = '"target": [0.45, 0.1, 0.35], "position_only": true'
    numbers = ", ".join(PANDA_READY)
    lines = [
        f'{{{target}, "seed_q": "ready"}}',
        f'{{{target}, "seed_q": [{numbers}]}}',
        f'{{{target}, "seed_q": "stow"}}',
    ]
    monkeypatch.setattr("sys.stdin", io.StringIO("".join(line + "\n" for line in lines)))
    ik.main(["--robot", "panda", "--stdin"])
    answers = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert _q(answers[0]) == pytest.approx(_q(answers[1]), abs=1e-12)
    assert answers[2]["error"] == "panda: no named state 'stow'; its named states: ready"


@pytest.mark.parametrize(
    ("command", "argv", "needle"),
    [
        (ik, ["--target", "0.3", "0.2", "0.4", "--seed-q", "stow"], "its named states: home, up"),
        (ik, ["--target", "0.3", "0.2", "0.4", "--seed-q", "0", "up"], "one named state, not 'up'"),
        (
            path,
            [
                "--from",
                "0.3",
                "0.2",
                "0.4",
                "--to",
                "0.3",
                "0",
                "0.4",
                "--steps",
                "3",
                "--seed-q",
                "x",
            ],
            "ur5: no named state 'x'; its named states: home, up",
        ),
    ],
)
def test_unknown_name_is_one_line(command, argv, needle, capsys):
    code = command.main(["--robot", "ur5", *argv])
    assert_one_line_error(code, capsys.readouterr().err, needle)


def test_a_robot_without_states_says_where_names_come_from(capsys):
    code = ik.main(["--robot", "puma560", "--target", "0.3", "0.2", "0.4", "--seed-q", "ready"])
    assert_one_line_error(code, capsys.readouterr().err, "it has none: give a [states] table")


def test_table_states_in_the_tables_units_and_written_back(tmp_path):
    """[states] in degrees and mm (a prismatic row) read as rad and m; table_text writes them
    (SI) and reads back the same; a bad state names the table and the key."""
    from support.cli_helper import RRPR4_TOML

    table_path = tmp_path / "rrpr4.toml"
    table_path.write_text(RRPR4_TOML + "\n[states]\nparked = [90.0, -45.0, 50.0, 180.0]\n")
    table = load_table(table_path)
    (state,) = table.states
    assert state.name == "parked"
    assert state.q == pytest.approx((math.pi / 2, -math.pi / 4, 0.05, math.pi), abs=1e-15)
    again = tmp_path / "again.toml"
    again.write_text(table_text(table))
    assert load_table(again).states == table.states
    for bad, needle in (
        ("parked = [90.0, 0.0, 50.0]", "expected 4 values"),
        ("parked = [400.0, 0.0, 50.0, 0.0]", "outside the limits of joint row 1"),
        ('"2nd" = [0.0, 0.0, 50.0, 0.0]', "a state's name is a letter"),
        ("parked = [0.0, nan, 50.0, 0.0]", "expected a finite number"),
    ):
        table_path.write_text(RRPR4_TOML + f"\n[states]\n{bad}\n")
        with pytest.raises(TableError, match="field 'states") as caught:
            load_table(table_path)
        assert needle in str(caught.value)


def test_named_state_seed_is_a_valid_joint_vector():
    """The looked-up vector has one finite value per joint, within the limits."""
    robot = load_robot("panda")
    q = named_states(robot).q("ready")
    assert q.shape == (robot.nq,) and np.isfinite(q).all()
    assert (robot.lower <= q).all() and (q <= robot.upper).all()
