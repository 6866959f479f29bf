# SPDX-License-Identifier: Apache-2.0
"""The sixth proof of ``make mutants`` (sim/mutation.py): an induction over the original and
the mutant as one transition function, with invariants a design states by hand, decided by z3
per invariant and per case of a few control signals.

What the other five cannot reach is a mutation that changes a value only where a wide
datapath keeps it out of a range (the shading core's Gouraud value of a negative
accumulator): pdr and the window see the multipliers and the 33-bit accumulator as bits,
and SymbiYosys's incremental z3 bit-blasts both multipliers.  Here the two netlists go
through Yosys's functional back end (``write_functional_smt2``: one SMT-LIB function from
inputs and state to outputs and next state, ``functional_miter``), with a harness module
beside them (shadow registers the invariants speak of), and z3's Python API runs the
induction (``Machine``, ``decide``):

* each state is the state datatype's constructor over fresh constants, one per field, so
  that z3's ``solve-eqs`` substitutes a field proven equal in the two copies and the
  multipliers of the two copies become one term;
* the base: from any power-up state the two copies share (every flip-flop, FIFO word and
  ROM; the harness's registers free), one clock with ``rst_n`` low gives a state where every
  invariant holds, and the outputs of that cycle obey the contract;
* the step: from any state where every invariant holds, one clock with any inputs gives a
  state where each holds again, and the outputs obey the contract, one query per invariant
  and per case of the ``cases`` signals (each case small enough for z3's preprocessing);
* lemmas: claims proven once per value of a narrow field (a span's length), which the step
  then assumes for every value: what needs a product of a table word and a free operand is
  decided with the table word a constant.

The queries run in that order on a pool of processes and stop at the first not proven
(``run``, each verdict and its seconds in ``induction.log``), so a mutant the step does not
hold for fails before the lemmas' many queries.

A memory without a write port (a ROM) stays an array in the state; its next state is the
same array (checked: ``Machine.roms``), so its words are the netlist's initial ones in every
state, which a lemma may read (``rom_images``).
"""

from __future__ import annotations

import functools
import hashlib
import inspect
import multiprocessing
import os
import re
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import z3

from sim.mutation_proof import keep_verdict, known_verdict, run_yosys

# The miter's module (and the functional netlist's datatypes, named after it)
MITER = "mutation_miter"
# Seconds z3 is given for one query
QUERY_TIMEOUT = 120.0
# What decide does, in the key of its verdicts (a change of method runs them again)
_METHOD = "functional smt2, z3 induction per invariant and case, lemmas per field value"


def functional_miter(
    folder: Path, gold_il: Path, gate_il: Path, top: str, expose: Sequence[str], harness: str
) -> Path:  # fmt: skip
    """The original ``gold_il`` and the mutant ``gate_il`` (RTLIL, module ``top``) under the
    harness module ``harness`` (Verilog, module ``mutation_miter``: it instantiates
    ``mutation_gold`` and ``mutation_gate``), written as one functional SMT-LIB netlist
    (``folder``/miter.smt2).  ``expose``: wires of the original made output ports, for the
    harness.  Memories with a write port are mapped to flip-flops (the FIFO's words); the
    others stay arrays.  Flip-flops are named after their outputs (``autoname``: a
    register ``r_reg`` of the original is the field ``gold.r_reg_$ff_Q``)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "harness.v").write_text(harness)
    gold, gate = (os.path.relpath(p, folder) for p in (gold_il, gate_il))
    shown = " ".join(f"mutation_gold/{w}" for w in expose)
    run_yosys(
        f"read_rtlil {gold}\nrename {top} mutation_gold\nexpose {shown}\n"
        f"read_rtlil {gate}\nrename {top} mutation_gate\n"
        f"read_verilog -sv harness.v\nhierarchy -top {MITER}\nproc\nflatten\n"
        "memory -nomap\nmemory_map t:$mem_v2 r:WR_PORTS>0 %i\nmemory_nordff\ndffunmap\n"
        "formalff -clk2ff\nsetundef -undriven -zero\nopt_clean\nautoname\n"
        "write_functional_smt2 miter.smt2\n",
        folder,
        "functional",
    )
    return folder / "miter.smt2"


_INITIAL = f"(declare-const {MITER}-initial"


def rom_images(smt2: str) -> dict[str, dict[int, int]]:
    """field -> (address -> word) of every memory the initial state of ``smt2`` fills."""
    at = smt2.index(_INITIAL)
    pattern = rf"\(select\s+\({MITER}_State_(\S+)\s+{MITER}-initial\)\s+#b([01]+)\)\s+#b([01]+)\)"
    found: dict[str, dict[int, int]] = {}
    for field, a, w in re.findall(pattern, smt2[at:]):
        found.setdefault(field, {})[int(a, 2)] = int(w, 2)
    return found


class Machine:
    """The functional netlist ``smt2`` as a z3 transition: ``fields`` (the state's, by name),
    ``inputs``, ``outputs``, and ``step`` from a state and inputs to outputs and next
    state."""

    def __init__(self, smt2: str) -> None:
        text = smt2[: smt2.index(_INITIAL)] + (
            f"(declare-const s {MITER}_State)(declare-const i {MITER}_Inputs)"
            f"(assert (= ({MITER} i s) ({MITER} i s)))(assert (= i i))(assert (= s s))"
        )
        parsed = z3.parse_smt2_string(text)
        self.body, self.i, self.s = (a.arg(0) for a in parsed)
        self.state_sort, self.input_sort = self.s.sort(), self.i.sort()
        self.output_sort = self.body.sort().accessor(0, 0).range()

        def names(sort: z3.DatatypeSortRef) -> list[str]:
            prefix = f"{sort.name()}_"
            arity = sort.constructor(0).arity()
            return [sort.accessor(0, k).name().removeprefix(prefix) for k in range(arity)]

        self.fields = names(self.state_sort)
        self.inputs = names(self.input_sort)
        self.outputs = names(self.output_sort)
        self._sorts = {f: self.state_sort.accessor(0, k).range() for k, f in enumerate(self.fields)}
        self._input_sorts = {
            f: self.input_sort.accessor(0, k).range() for k, f in enumerate(self.inputs)
        }

    def state(self, name: Callable[[str], str]) -> dict[str, z3.ExprRef]:
        """A state of fresh constants, field ``f``'s named ``name(f)`` (one name for two
        fields: one constant)."""
        return {f: z3.Const(name(f), self._sorts[f]) for f in self.fields}

    def input_values(self, tag: str) -> dict[str, z3.ExprRef]:
        return {f: z3.Const(f"{tag}.{f}", self._input_sorts[f]) for f in self.inputs}

    def step(
        self, state: dict[str, z3.ExprRef], inputs: dict[str, z3.ExprRef]
    ) -> tuple[dict[str, z3.ExprRef], dict[str, z3.ExprRef]]:  # fmt: skip
        """The outputs in the cycle of ``state`` and ``inputs``, and the state after the
        clock."""
        s = self.state_sort.constructor(0)(*(state[f] for f in self.fields))
        i = self.input_sort.constructor(0)(*(inputs[f] for f in self.inputs))
        pair = z3.simplify(z3.substitute(self.body, (self.s, s), (self.i, i)))
        outputs, after = pair.arg(0), pair.arg(1)
        if outputs.decl() != self.output_sort.constructor(0) or (
            after.decl() != self.state_sort.constructor(0)
        ):
            raise RuntimeError("the functional netlist's step did not reduce to its datatypes")
        return dict(zip(self.outputs, outputs.children(), strict=True)), dict(
            zip(self.fields, after.children(), strict=True)
        )

    def roms(self) -> list[str]:
        """The array fields (memories without a write port), each checked to keep its words
        over a step (else RuntimeError)."""
        arrays = [f for f in self.fields if self._sorts[f].kind() == z3.Z3_ARRAY_SORT]
        state = self.state(lambda f: f"rom.{f}")
        _, after = self.step(state, self.input_values("rom"))
        kept = [f for f in arrays if after[f].eq(state[f])]
        if kept != arrays:
            raise RuntimeError(
                f"memories written in the functional netlist: {set(arrays) - set(kept)}"
            )
        return arrays


def unsat(assumptions: Sequence[z3.BoolRef], claim: z3.BoolRef, timeout: float = QUERY_TIMEOUT) -> (
    str
):  # fmt: skip
    """'unsat' (``claim`` follows from ``assumptions``), 'sat' or 'unknown': z3's
    preprocessing (sum-of-monomials simplification, value propagation, equation solving,
    unconstrained terms), then a QF_AUFBV solver per subgoal it leaves."""
    goal = z3.Goal()
    goal.add(*assumptions, z3.Not(claim))
    tactic = z3.Then(
        z3.With(
            "simplify", som=True, flat=True, hoist_mul=False, pull_cheap_ite=True, local_ctx=True
        ),
        "propagate-values",
        "solve-eqs",
        "elim-uncnstr",
        "simplify",
    )
    verdict = "unsat"
    for sub in tactic(goal):
        solver = z3.SolverFor("QF_AUFBV")
        solver.set("timeout", int(timeout * 1000))
        solver.add(sub.as_expr())
        found = solver.check()
        if found == z3.sat:
            return "sat"
        if found == z3.unknown:
            verdict = "unknown"
    return verdict


@dataclass(frozen=True)
class Query:
    """One query of an induction: ``kind`` 'base', 'step' or 'lemma'; ``goal`` the claim's
    index (an invariant's, or the contract's: -1); ``case`` the values of the case signals
    (step); ``value`` the lemma's field value."""

    kind: str
    goal: int
    case: tuple[int, ...] = ()
    value: int = 0


class Induction(ABC):
    """What a design states for the sixth proof, over ``Machine(smt2)``: its invariants, the
    contract its outputs obey, the case signals, the lemma and the base state.  Built in each
    worker process from the netlist's text and the subclass's arguments."""

    # invariants left out of the step's and lemmas' assumptions (to show a check fail)
    dropped: frozenset[str] = frozenset()

    def __init__(self, smt2: str) -> None:
        self.machine = Machine(smt2)

    @abstractmethod
    def invariants(self, state: dict[str, z3.ExprRef]) -> list[tuple[str, z3.BoolRef]]:
        """(name, claim) of every invariant over ``state``."""

    @abstractmethod
    def contract(self, outputs: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """The two copies' outputs of one cycle agree."""

    @abstractmethod
    def cases(self, outputs: dict[str, z3.ExprRef]) -> list[z3.ExprRef]:
        """One-bit signals each step query fixes (one query per combination)."""

    @abstractmethod
    def lemma_when(self, outputs: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """When the lemma speaks (a span taken)."""

    @abstractmethod
    def lemma_premise(self, state: dict, outputs: dict, value: int) -> z3.BoolRef:
        """The lemma's field at ``value``, and what that value fixes (a ROM's word)."""

    @abstractmethod
    def lemma_claim(self, after: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """The lemma's claim over the state after the clock; the step assumes it whenever
        ``lemma_when``, as the lemmas prove it for every value."""

    @abstractmethod
    def lemma_values(self) -> list[int]:
        """Every value the lemma is proven for (together: every value its premise allows)."""

    @abstractmethod
    def base_state(self) -> dict[str, z3.ExprRef]:
        """The power-up state (the copies' fields shared)."""

    @abstractmethod
    def reset(self, inputs: dict[str, z3.ExprRef]) -> z3.BoolRef:
        """The inputs of the first cycle."""

    def queries(self) -> list[Query]:
        """Every query of the proof: the base, the step, the lemmas (a mutant the step does not
        hold for fails before the lemmas' many queries)."""
        state = self.machine.state(lambda f: f"s.{f}")
        count = len(self.invariants(state))
        n_cases = len(self.cases(self.machine.step(state, self.machine.input_values("i"))[0]))
        found = [Query("base", g) for g in range(-1, count)]
        found += [
            Query("step", g, tuple((k >> b) & 1 for b in range(n_cases)))
            for g in range(-1, count)
            for k in range(1 << n_cases)
        ]
        return found + [Query("lemma", 0, value=v) for v in self.lemma_values()]

    @functools.cached_property
    def _base(self) -> tuple[z3.BoolRef, dict[str, z3.ExprRef], list[z3.BoolRef]]:
        """The power-up cycle: its reset, its outputs' contract and the invariants after it."""
        inputs = self.machine.input_values("i")
        outputs, after = self.machine.step(self.base_state(), inputs)
        return self.reset(inputs), outputs, [claim for _, claim in self.invariants(after)]

    @functools.cached_property
    def _step(self) -> tuple[dict, list[z3.BoolRef], dict, dict, list[z3.BoolRef]]:
        """A step from any state: the state, the invariants held (but ``dropped``), the
        outputs, the state after, and the invariants over it."""
        state = self.machine.state(lambda f: f"s.{f}")
        outputs, after = self.machine.step(state, self.machine.input_values("i"))
        held = [inv for name, inv in self.invariants(state) if name not in self.dropped]
        return state, held, outputs, after, [claim for _, claim in self.invariants(after)]

    def decide(self, query: Query) -> str:
        """'unsat' (the query's claim holds), 'sat' or 'unknown'."""
        if query.kind == "base":
            reset, outputs, claims = self._base
            return unsat([reset], self.contract(outputs) if query.goal < 0 else claims[query.goal])
        state, held, outputs, after, claims = self._step
        when, lemma = self.lemma_when(outputs), self.lemma_claim(after)
        if query.kind == "lemma":
            return unsat([*held, when, self.lemma_premise(state, outputs, query.value)], lemma)
        signals = self.cases(outputs)
        case = [s == 1 if v else s == 0 for s, v in zip(signals, query.case, strict=True)]
        claim = self.contract(outputs) if query.goal < 0 else claims[query.goal]
        return unsat([*held, *case, z3.Implies(when, lemma)], claim)


_worker: Induction | None = None


def _start(kind: type[Induction], smt2: str, args: tuple) -> None:
    global _worker
    _worker = kind(smt2, *args)


def _decide(query: Query) -> tuple[str, float]:
    assert _worker is not None
    t0 = time.monotonic()
    return _worker.decide(query), time.monotonic() - t0


def run(
    kind: type[Induction], smt2: str, args: tuple, queries: Sequence[Query], jobs: int,
    log: Path,
) -> list[str]:  # fmt: skip
    """``queries`` decided in order by ``kind(smt2, *args)`` in ``jobs`` processes (spawned:
    each parses the netlist once), up to the first that is not 'unsat' (the rest are
    cancelled); each verdict and its seconds written to ``log`` as it comes, and last a line
    of the counts and the solver seconds of each kind."""
    context = multiprocessing.get_context("spawn")
    verdicts: list[str] = []
    seconds = {"base": 0.0, "step": 0.0, "lemma": 0.0}
    pool = ProcessPoolExecutor(jobs, mp_context=context, initializer=_start,
                               initargs=(kind, smt2, args))  # fmt: skip
    try:
        with log.open("w") as out:
            for query, (verdict, took) in zip(
                queries, pool.map(_decide, queries, chunksize=8), strict=False
            ):  # fmt: skip
                out.write(f"{query} {verdict} {took:.2f}\n")
                out.flush()
                verdicts.append(verdict)
                seconds[query.kind] += took
                if verdict != "unsat":
                    break
            out.write(
                f"{len(verdicts)} of {len(queries)} queries decided, "
                f"{sum(v == 'unsat' for v in verdicts)} unsat; solver seconds: "
                + ", ".join(f"{k} {t:.1f}" for k, t in seconds.items())
                + f", all {sum(seconds.values()):.1f}\n"
            )
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    return verdicts


def prove(
    folder: Path, kind: type[Induction], smt2: Path, args: tuple, jobs: int = 2
) -> tuple[str, dict[str, int]]:  # fmt: skip
    """Every query of ``kind`` over ``smt2`` (``run``): ('proven' or 'failed', the number of
    queries of each kind), the query not decided unsat in ``folder``/induction_failed.txt.  The ROMs
    are checked first: kept by every step (``Machine.roms``) and the same image in both
    copies (so a power-up state the copies share holds the netlist's words).  A verdict is
    kept for the same netlist, method and design (its class's source: a change of an
    invariant runs the queries again)."""
    text = smt2.read_text()
    design = repr((_METHOD, inspect.getsource(kind), args))
    key = hashlib.sha256(design.encode() + text.encode()).hexdigest()
    problem = kind(text, *args)
    queries = problem.queries()
    counts = {k: sum(1 for q in queries if q.kind == k) for k in ("lemma", "base", "step")}
    cached = known_verdict(folder, key)
    if cached is not None:
        return str(cached), counts
    images = rom_images(text)
    for rom in problem.machine.roms():
        twin = ("gate." + rom[5:]) if rom.startswith("gold.") else ("gold." + rom[5:])
        if images.get(rom) != images.get(twin):
            raise RuntimeError(f"the copies' ROM {rom[5:]} hold different images")
    verdicts = run(kind, text, args, queries, jobs, folder / "induction.log")
    failed = [(q, v) for q, v in zip(queries, verdicts, strict=False) if v != "unsat"]
    (folder / "induction_failed.txt").write_text("".join(f"{q} {v}\n" for q, v in failed))
    verdict = "proven" if len(verdicts) == len(queries) and not failed else "failed"
    keep_verdict(folder, key, verdict)
    return verdict, counts
