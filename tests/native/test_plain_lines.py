"""The compiled reader and writer of ``kin ik --stdin``'s plainest lines (kin/_native/commands/_plain_lines.c).

The json module is the reference: a line the reader takes (kind 1 or 2) must be one the json
module reads as ``{"target": [...]}`` or ``{"target": [...], "rpy": [...]}``, with the same
float64 values bit for bit (``np.array(..., dtype=float)`` of what it gives, as the stream's
Python path makes them); every other line is left to it (kind 0). Every value the writer writes
must read back (``float``) as the same float64, laid out as ``repr`` lays it out.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kin.commands import ik_stream

needs_twin = pytest.mark.skipif(ik_stream._read_plain is None, reason="_plain_lines not built")
needs_writer = pytest.mark.skipif(ik_stream._write_plain is None, reason="_plain_lines not built")


def read(lines: list[bytes]) -> tuple[np.ndarray, np.ndarray]:
    kinds, values = ik_stream._read_plain(lines)
    return np.frombuffer(kinds, dtype=np.uint8), np.frombuffer(values).reshape(-1, 6)


def expected(line: bytes) -> tuple[int, np.ndarray]:
    """What the json module makes of a line: (kind, six float64 values, NaN where absent)."""
    values = np.full(6, np.nan)
    try:
        request = json.loads(line)
    except (ValueError, RecursionError):
        return 0, values
    if request.__class__ is not dict or "target" not in request:
        return 0, values
    if set(request) == {"target"}:
        kind = 1
    elif set(request) == {"target", "rpy"} and list(request) == ["target", "rpy"]:
        kind = 2
    else:
        return 0, values
    try:
        with np.errstate(all="ignore"):
            values[:3] = np.array(request["target"], dtype=float)
            if kind == 2:
                values[3:] = np.array(request["rpy"], dtype=float)
    except (TypeError, ValueError, OverflowError):
        return 0, values
    return kind, values


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal as float64 bit patterns (NaN equal to NaN, -0.0 not equal to 0.0)."""
    return bool(np.all((a.view(np.int64) == b.view(np.int64)) | (np.isnan(a) & np.isnan(b))))


numbers = st.one_of(
    st.floats(allow_nan=False, allow_infinity=False),
    st.floats(min_value=-10.0, max_value=10.0),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.sampled_from([0, -0.0, 0.0, 5e-324, 1.7976931348623157e308, 1e-300, 0.1, 1e22]),
)
texts = st.one_of(
    st.sampled_from(
        [
            "-0",
            "-0.0",
            "1e400",
            "-1e400",
            "1E+2",
            "1e-2",
            "0.5e-3",
            "123456789012345678901234567890",
        ]
    ),
    numbers.map(json.dumps),
)


@needs_twin
@settings(max_examples=400, deadline=None)
@given(st.lists(texts, min_size=6, max_size=6), st.booleans())
def test_canonical_lines_read_as_json_reads_them(tokens, with_rpy):
    """A line as json.dumps writes it (and any JSON number spelling): the json module's floats."""
    line = '{"target": [' + ", ".join(tokens[:3]) + "]"
    line += (', "rpy": [' + ", ".join(tokens[3:]) + "]}") if with_rpy else "}"
    kind, values = read([line.encode()])
    want_kind, want = expected(line.encode())
    assert kind[0] == want_kind == (2 if with_rpy else 1)
    assert same_bits(values[0], want), (line, values[0], want)


canonical = b'{"target": [0.25, -1, 3e-2], "rpy": [0.0, -0.5, 1.5]}'
mutations = st.one_of(
    st.binary(max_size=80),
    st.tuples(st.integers(0, len(canonical)), st.binary(max_size=3)).map(
        lambda c: canonical[: c[0]] + c[1] + canonical[c[0] :]
    ),
    st.tuples(st.integers(0, len(canonical)), st.integers(1, 4)).map(
        lambda c: canonical[: c[0]] + canonical[c[0] + c[1] :]
    ),
    st.sampled_from(
        [
            b"",
            b" ",
            b'{"target": [1, 2, 3]} ',
            b'{"target": [1, 2, 3]}\r',
            b'{"target":[1,2,3]}',
            b'{"target": [01, 2, 3]}',
            b'{"target": [+1, 2, 3]}',
            b'{"target": [.5, 2, 3]}',
            b'{"target": [5., 2, 3]}',
            b'{"target": [NaN, 2, 3]}',
            b'{"target": [Infinity, 2, 3]}',
            b'{"target": [1_0, 2, 3]}',
            b'{"target": [1, 2]}',
            b'{"target": [1, 2, 3, 4]}',
            b'{"target": [1, 2, 3], "rpy": [1, 2, 3], "seed_q": [0]}',
            b'{"rpy": [1, 2, 3], "target": [1, 2, 3]}',
            b'{"target": [1, 2, 3], "rpy": [true, 2, 3]}',
            b'{"target": [1, 2, 3]}{"target": [1, 2, 3]}',
            b'{"target": [1, 2, 3], "target": [4, 5, 6]}',
            b'{"target": [' + b"1" * 60 + b", 2, 3]}",
            b'{"target": [1e, 2, 3]}',
            b'{"target": [1e+, 2, 3]}',
            b'{"target": [-, 2, 3]}',
            b'{"target": [1, 2, 3\xff]}',
        ]
    ),
)


@needs_twin
@settings(max_examples=600, deadline=None)
@given(st.lists(mutations, min_size=1, max_size=5))
def test_any_line_is_read_as_json_reads_it_or_left_to_it(lines):
    """Hostile lines: the reader never takes a line the json module reads otherwise or rejects."""
    kinds, values = read(lines)
    assert len(kinds) == len(lines)
    for line, kind, row in zip(lines, kinds, values):
        if kind == 0:
            assert np.isnan(row).all()
            continue
        want_kind, want = expected(line)
        assert kind == want_kind, line
        assert same_bits(row, want), (line, row, want)


@needs_twin
def test_reader_takes_any_sequence_and_refuses_the_rest():
    kinds, _ = read([b'{"target": [1, 2, 3]}', '{"target": [1, 2, 3]}', None, 3])
    assert kinds.tolist() == [1, 0, 0, 0]  # str and other objects: the json module's
    assert read([])[0].size == 0
    with pytest.raises(TypeError):
        ik_stream._read_plain(5)


@needs_twin
def test_stream_with_and_without_the_reader_gives_the_same_lines():
    """Through a pipe (bytes, so the reader runs) and with it switched off, with the compiled
    writer and without, reading ahead and not: the same answers.

    Reachable poses (the tool poses of random q), so that no answer depends on a time budget.
    """
    from kin import load_robot
    from kin.batch_fk import batch_forward_kinematics

    robot = load_robot("humanoid7")
    rng = np.random.default_rng(3)
    poses = batch_forward_kinematics(robot.table, rng.uniform(robot.lower, robot.upper, (120, 7)))
    lines = []
    for k, pose in enumerate(poses):
        x, y, z = pose[:3, 3].tolist()
        m = pose[:3, :3]
        r = math.atan2(m[2, 1], m[2, 2])
        p = math.asin(-max(-1.0, min(1.0, m[2, 0])))
        w = math.atan2(m[1, 0], m[0, 0])
        form = k % 6
        if form == 0:
            lines.append(json.dumps({"target": [x, y, z]}))
        elif form == 1:
            lines.append(f'{{"target": [{x!r}, {y!r}, {z!r}], "rpy": [-0, 0, 1e400]}}')  # error
        elif form == 2:
            lines.append(f'{{"target":[{x!r},{y!r},{z!r}],"rpy":[{r!r},{p!r},{w!r}]}}')
        else:
            lines.append(json.dumps({"target": [x, y, z], "rpy": [r, p, w]}))
    text = "\n".join(lines * 5) + "\n"  # over 64 KiB: several reads (one read ahead)
    code = (
        "import sys\n"
        "from kin.commands import ik_stream, main\n"
        "if sys.argv[1] == 'off':\n"
        "    ik_stream._read_plain = None\n"
        "else:  # count the lines the reader takes\n"
        "    reader, taken = ik_stream._read_plain, []\n"
        "    def counted(lines):\n"
        "        kinds, values = reader(lines)\n"
        "        taken.append(sum(k > 0 for k in kinds))\n"
        "        return kinds, values\n"
        "    ik_stream._read_plain = counted\n"
        "if sys.argv[1] == 'nowriter':  # the %-format writes the answers\n"
        "    ik_stream._write_plain = None\n"
        "if sys.argv[1] == 'noahead':  # no batch read before the last one is answered\n"
        "    ik_stream._input_waiting = lambda source: False\n"
        "code = main(['ik', '--robot', 'humanoid7', '--stdin'])\n"
        "if sys.argv[1] == 'on':\n"
        "    print(sum(taken), file=sys.stderr)\n"
        "raise SystemExit(code)\n"
    )
    outputs = []
    for switch in ("on", "off", "nowriter", "noahead"):
        done = subprocess.run(
            [sys.executable, "-c", code, switch], input=text.encode(), capture_output=True
        )
        if switch == "on":  # forms 0, 1, 3, 4 and 5 (not the compact 2): 100 lines taken, 5 times
            assert int(done.stderr.decode().split()[-1]) == 500
        answers = [json.loads(line) for line in done.stdout.decode().splitlines()]
        for answer in answers:
            answer.pop("time_s", None)
        outputs.append(answers)
    assert len(outputs[0]) == 5 * len(lines)
    assert outputs[0] == outputs[1] == outputs[2] == outputs[3]


def write_values(values: list[float]) -> list[str]:
    """The writer's text of each value (one line per value, no line number)."""
    lines = ik_stream._write_plain(
        ("", "", ""), np.array(values, dtype=float), np.zeros(len(values), dtype=np.int64)
    )
    return [line[:-1] for line in lines]  # the number 0 ends each line


def json_text(value: float) -> str:
    """The json module's text of a float (repr, NaN and the infinities as JavaScript names)."""
    return json.dumps(value)


@needs_writer
@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True), max_size=20))
def test_written_floats_read_back_bit_for_bit(values):
    for value, text in zip(values, write_values(values)):
        if math.isnan(value):
            assert text == "NaN"
            continue
        assert same_bits(np.array([json.loads(text)]), np.array([value])), (value, text)
        if text != json_text(value):  # another text that reads back: at most 17 digits, alike
            mantissa = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0").rstrip("0")
            assert len(mantissa) <= 17, text
            assert ("e" in text) == ("e" in json_text(value)), (text, json_text(value))


@pytest.mark.slow  # CI runs it; the default run stays under 5 minutes
@needs_writer
def test_written_floats_over_every_exponent_read_back_and_are_reprs():
    """A million random bit patterns (every exponent, subnormals) and values of the stream's
    ranges (joint angles, errors near 1e-16): all read back; all but a few per thousand are
    exactly ``repr`` (Grisu2 is sometimes one digit longer or not the nearest of the shortest)."""
    rng = np.random.default_rng(11)
    patterns = rng.integers(0, 2**63, size=1_000_000, dtype=np.int64).view(np.float64)
    patterns = patterns[np.isfinite(patterns)]
    patterns[::2] *= -1.0
    values = np.concatenate(
        [patterns, rng.uniform(-7.0, 7.0, 200_000), rng.normal(0.0, 1e-16, 200_000)]
    ).tolist()
    texts = write_values(values)
    assert all(float(t) == v for t, v in zip(texts, values))
    differ = sum(t != repr(v) for t, v in zip(texts, values))
    assert differ < 0.003 * len(values), differ
    specials = [
        0.0,
        -0.0,
        1.0,
        0.1,
        1e-05,
        0.0001,
        123.0,
        1e15,
        1e16,
        1e22,
        5e-324,
        1.7976931348623157e308,
        2.2250738585072014e-308,
        -3.141592653589793,
        0.3,
    ]
    assert write_values(specials) == [repr(v) for v in specials]
    assert write_values([math.inf, -math.inf, math.nan]) == ["Infinity", "-Infinity", "NaN"]


@needs_writer
def test_written_lines_join_pieces_values_and_numbers():
    pieces = ('{"q": [', ", ", '], "line": ', "}\n")
    values = np.array([[0.5, -1.25], [1e-20, 3.0]])
    numbers = np.array([7, -(2**63)], dtype=np.int64)
    assert ik_stream._write_plain(pieces, values, numbers) == [
        '{"q": [0.5, -1.25], "line": 7}\n',
        '{"q": [1e-20, 3.0], "line": -9223372036854775808}\n',
    ]
    assert ik_stream._write_plain(("a", "b"), np.empty(0), np.array([1, 2], dtype=np.int64)) == [
        "a1b",
        "a2b",
    ]
    assert ik_stream._write_plain(("", "", ""), np.empty(0), np.empty(0, dtype=np.int64)) == []


@needs_writer
@pytest.mark.parametrize(
    "args, error",
    [
        ((["a", "b", "c"], np.zeros(1), np.zeros(1, dtype=np.int64)), TypeError),
        ((("a",), np.zeros(0), np.zeros(1, dtype=np.int64)), ValueError),
        ((("a", "\u00e9", "c"), np.zeros(1), np.zeros(1, dtype=np.int64)), ValueError),
        ((("a", 3, "c"), np.zeros(1), np.zeros(1, dtype=np.int64)), ValueError),
        ((("a", "b", "c"), np.zeros(2), np.zeros(1, dtype=np.int64)), ValueError),
        ((("a", "b", "c"), np.zeros(1), np.zeros(3, dtype=np.int8)), ValueError),
        ((("a", "b", "c"), "text", np.zeros(1, dtype=np.int64)), TypeError),
    ],
)
def test_write_refuses_malformed_arguments(args, error):
    with pytest.raises(error):
        ik_stream._write_plain(*args)


def paired_answers(q: np.ndarray, positions_every: int) -> list[tuple[dict, dict]]:
    """humanoid7's ``--stdin`` answers of the tool poses of ``q``, each line plain and again with
    ``"seed_q"`` equal to the default seed (read by the json module, the target made by
    ``request``): the pairs, their times and line numbers taken off. Every
    ``positions_every``-th line is a position, the others poses (rpy)."""
    from kin import load_robot
    from kin.batch_fk import batch_forward_kinematics

    poses = batch_forward_kinematics(load_robot("humanoid7").table, q)
    lines = []
    for k, pose in enumerate(poses):
        x, y, z = pose[:3, 3].tolist()
        m = pose[:3, :3]
        rpy = [
            math.atan2(m[2, 1], m[2, 2]),
            math.asin(-max(-1.0, min(1.0, m[2, 0]))),
            math.atan2(m[1, 0], m[0, 0]),
        ]
        plain = {"target": [x, y, z]}
        if k % positions_every:
            plain["rpy"] = rpy
        lines.append(json.dumps(plain))
        lines.append(json.dumps({**plain, "seed_q": [0.0] * 7}))
    done = subprocess.run(
        [sys.executable, "-m", "kin", "ik", "--robot", "humanoid7", "--stdin"],
        input=("\n".join(lines) + "\n").encode(),
        capture_output=True,
    )
    answers = [json.loads(line) for line in done.stdout.decode().splitlines()]
    assert len(answers) == len(lines)
    assert [a["line"] for a in answers] == list(range(1, len(lines) + 1))
    for answer in answers:
        answer.pop("time_s")
        answer.pop("line")
    return list(zip(answers[::2], answers[1::2]))


def test_an_encoded_answer_is_the_records_json():
    """A plain line's answer, written by the stream's own encoder, is what ``json.dumps`` writes for
    the same answer through the records path (a line with a ``seed_q`` equal to the default
    seed): the same keys in the same order, the same values; positions and poses."""
    rng = np.random.default_rng(8)
    robot_q = rng.uniform(*_humanoid7_limits(), (40, 7))
    for encoded, record in paired_answers(robot_q, 2):
        assert encoded["success"] and record["success"]
        assert list(encoded) == list(record)
        assert encoded == record


def test_lines_the_batch_leaves_are_answered_as_read_alone():
    """Targets near the zero seed's tool whose branch at the seed's free joint moved too far: the
    batch leaves them and the solver answers them one by one from the targets the batch read
    (not read again). The answers equal those of the same lines with an explicit ``seed_q``
    (read by the json module, their targets made by ``request``): the same targets."""
    rng = np.random.default_rng(21)
    one_by_one = 0
    for plain, seeded in paired_answers(rng.uniform(-0.7, 0.7, (60, 7)), 3):
        one_by_one += "damped Newton" in plain.get("message", "") or plain["iterations"] > 0
        assert plain == seeded
    assert one_by_one >= 3, one_by_one  # the lines this test is about were there


def _humanoid7_limits() -> tuple[np.ndarray, np.ndarray]:
    from kin import load_robot

    robot = load_robot("humanoid7")
    return robot.lower, robot.upper


@needs_twin
def test_numbers_in_every_spelling_are_floats_reading():
    """Numbers in every spelling a writer uses (repr, %.15g to %.17g, exponents, integers, the
    edges of exact float64 digits: 2^53, 1e22, 22 fraction digits): bit for bit ``float(text)``."""
    rng = np.random.default_rng(5)
    values = np.concatenate(
        [
            rng.uniform(-7.0, 7.0, 20_000),
            rng.normal(0.0, 1e-16, 5_000),
            10.0 ** rng.uniform(-30, 30, 5_000),
        ]
    ).tolist()
    texts = []
    for k, value in enumerate(values):
        texts.append(("%r", "%.15g", "%.16g", "%.17g", "%.3e", "%.22f")[k % 6] % value)
    texts += ["9007199254740992", "9007199254740993", "9007199254740993.0", "1e22", "1e23",
              "0.0000000000000000000001", "123456789012345678", "-0.0", "0.1e-22", "4.5e15",
              "1.7976931348623157e308", "5e-324", "2.2250738585072014e-308", "12345678901234567890"]  # fmt: skip
    lines = [f'{{"target": [{t}, {t}, {t}]}}'.encode() for t in texts]
    kinds, read_values = read(lines)
    taken = kinds == 1  # a number over 40 characters is left to the json module
    assert all(len(t) > 40 for t, ok in zip(texts, taken) if not ok) and taken.mean() > 0.9
    want = np.array([float(t) for t in texts])
    assert same_bits(read_values[taken, 0], want[taken])
