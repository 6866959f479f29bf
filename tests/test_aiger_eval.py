# SPDX-License-Identifier: Apache-2.0
"""sim/aiger_eval.py against Python's own arithmetic: Yosys writes the AIG of a small
function (mapped to gates, not optimised, so that one that never holds keeps its gates), the
sweep finds the first assignment that sets its output, and Python finds the same one by
counting through the operands (the lowest input bit first)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from sim.aiger_eval import first_one, read_aiger, support
from sim.gate import yosys_exe


def _aig(tmp_path: Path, width: int, expr: str) -> tuple[Path, dict[int, tuple[str, int]]]:
    """The AIG of ``y = expr`` over inputs a and b of ``width`` bits and an unread c, and each
    input variable's (name, bit) from Yosys's map."""
    (tmp_path / "t.v").write_text(
        f"module t (input [{width - 1}:0] a, input [{width - 1}:0] b, input [2:0] c, "
        f"output y);\n  assign y = {expr};\nendmodule\n"
    )
    subprocess.run(
        [yosys_exe(), "-q", "-p",
         "read_verilog t.v; hierarchy -top t; proc; techmap; opt_clean; aigmap; "
         "write_aiger -map t.map t.aig"],
        cwd=tmp_path, check=True, capture_output=True,
    )  # fmt: skip
    names = {}
    for line in (tmp_path / "t.map").read_text().splitlines():
        kind, index, bit, name = line.split()
        if kind == "input":
            names[int(index) + 1] = (name, int(bit))
    return tmp_path / "t.aig", names


def _first(width: int, holds) -> tuple[int, int] | None:
    """The first (a, b) by the count over a's bits then b's (Yosys's input order) for which
    ``holds(a, b)``."""
    for code in range(1 << (2 * width)):
        a, b = code & ((1 << width) - 1), code >> width
        if holds(a, b):
            return a, b
    return None


@pytest.mark.parametrize(
    ("width", "expr", "holds"),
    [
        (2, "a * b == 4'd6", lambda a, b: a * b == 6),  # 16 assignments: part of one word
        (4, "a * b == 8'd35", lambda a, b: a * b == 35),  # 256 assignments: four words
        (7, "a * b == 14'd5183", lambda a, b: a * b == 5183),  # 16 384: several sweep steps
        (7, "(a + b) > 8'd250", lambda a, b: a + b > 250),
        # 8191 is prime and above 127: no two 7-bit operands make it
        (7, "a * b == 14'd8191", lambda a, b: a * b == 8191),
    ],
)
def test_the_sweep_finds_python_s_first_assignment(tmp_path: Path, width, expr, holds) -> None:
    path, names = _aig(tmp_path, width, expr)
    aig = read_aiger(path)
    # c is never read: the support is a's and b's bits only
    assert sorted(names[v] for v in support(aig)) == sorted(
        (n, i) for n in ("a", "b") for i in range(width)
    )
    found = first_one(aig)
    want = _first(width, holds)
    if want is None:
        assert found is None
        return
    assert found is not None
    value = {"a": 0, "b": 0}
    for v, bit in found.items():
        name, i = names[v]
        value[name] |= bit << i
    assert (value["a"], value["b"]) == want


@pytest.mark.parametrize("target", [0, 1, 2, 3, 5, 6, 12, 24, 40, 48, 63])
def test_each_lane_of_a_word_is_its_own_assignment(tmp_path: Path, target: int) -> None:
    """Six inputs fill one 64-bit word: the one assignment {b, a} = target that sets the
    output is found at its own lane, whichever of the input patterns' bits it sits on."""
    path, names = _aig(tmp_path, 3, f"{{b, a}} == 6'd{target}")
    found = first_one(read_aiger(path))
    assert found is not None
    value = {"a": 0, "b": 0}
    for v, bit in found.items():
        name, i = names[v]
        value[name] |= bit << i
    assert value["a"] | value["b"] << 3 == target


@pytest.mark.parametrize(("output", "want"), [(8, {2: 1, 3: 1}), (9, {2: 0, 3: 0}), (4, {2: 1})])
def test_a_hand_written_aig_by_the_format_s_rules(tmp_path: Path, output: int, want) -> None:
    """An AIG written by hand by the AIGER format's rules: inputs 1..3 (literals 2, 4, 6) and
    one and gate, variable 4 = x2 & x3 (literal 8 = 4 & 6: the deltas 8 - 6 = 2 and 6 - 4 =
    2); its one output the gate (found where both inputs are 1), the gate inverted (literal 9:
    both 0) or input 2 alone (literal 4).  Input 1 is never read."""
    head = f"aig 4 3 0 1 1\n{output}\n".encode()
    (tmp_path / "h.aig").write_bytes(head + bytes([2, 2]))
    aig = read_aiger(tmp_path / "h.aig")
    assert support(aig) == sorted(want)
    assert first_one(aig) == want


def test_a_support_wider_than_the_limit_is_refused(tmp_path: Path) -> None:
    path, _ = _aig(tmp_path, 4, "a * b == 8'd35")
    with pytest.raises(ValueError, match="reads 8 inputs; at most 6 are swept"):
        first_one(read_aiger(path), limit=6)


def test_an_aig_with_latches_is_refused(tmp_path: Path) -> None:
    (tmp_path / "l.aig").write_bytes(b"aig 1 0 1 1 0\n2\n2\n")
    with pytest.raises(ValueError, match="1 latches; only a combinational AIG"):
        read_aiger(tmp_path / "l.aig")
