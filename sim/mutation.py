# SPDX-License-Identifier: Apache-2.0
"""Mutation testing of the RTL with Yosys's ``mutate`` pass, the method of YosysHQ's mcy
(``make mutants``, ``python -m sim.mutation``).

For each design (the three units and the shading core) at its default configuration:

1. **The list.**  Yosys reads the files the top's ``.f`` list names
   (``model.hw.sources.source_list``) with the parameters of the design's committed vector set,
   ``prep -flatten`` makes one module of it, and ``mutate -list LIST_SIZE -seed SEED`` picks
   the mutations (inverted, constant or cross-wired bits of cell ports; Yosys's own sampler,
   which spreads them over wires, cells and source lines), written to
   ``out/mutants/<design>/mutations.txt``.
2. **One netlist for all.**  Every mutation of the list is applied to the same netlist with
   ``mutate -ctrl mutsel W <id>`` (as mcy's ``create_mutated.sh -c`` does for a batch): an
   input ``mutsel`` selects mutation ``id`` (1 to LIST_SIZE) at run time, 0 is the original
   design.  ``write_verilog`` gives ``<top>_mutants``; a wrapper module named ``<top>``, with
   the top's parameters (unused: the netlist is built for the set's) and ports, drives
   ``mutsel`` from the plusarg ``+MUTANT=<id>``.  So the committed bench
   (``sim/vectors/tb_<unit>.v``, ``tb_shading_core.v``) builds unchanged around it, once, under
   Verilator, and each mutant costs one run of that binary.
3. **The checks.**  Each mutant runs the design's checks in order until one fails (it is
   *killed* by that check): first the committed vector set (the replay ``sim/gate.py`` makes on
   netlists; for the core ``sim/vectors/core_default`` with the FuseSoC target's idles and
   stalls), then, for the mutants that set leaves alive, stronger ones: longer soaks of the
   unit's default configuration with other seeds (``sim.vector_sets.write_stimulus``, the
   protocol model's prediction of every output in every cycle), for the core the set again at
   full rate and with other stalls, and random spans of every length.  Mutant 0 must pass every
   check, or the flow itself is wrong and the run stops.
4. **Equivalence.**  A mutant every check passes goes to a formal equivalence check
   (``equivalence``): the mutated design against the original, ROM tables cut out
   (``cut_roms``), every matched named wire asserted equal (``equiv_make -make_assert``) and
   the asserts proven by ``sat -tempinduct`` (base case from the same all-zero state with
   rst_n low in the first cycle, induction step from any state); for the few those leave, a
   miter of the two from reset (the same power-up state), the outputs compared as the
   design's ``contract`` defines them, proven by ABC's ``pdr`` (sim/mutation_proof.py), then
   the same with the multipliers cut and with the invariants of sim/mutation_invariants.py
   asserted alongside (each stage's registers equal in the two copies while its valid bit is
   set, a mutation's own), and for a mutation inside a BRDF form's datapath that window with
   the tables' words and the multipliers kept, unrolled and swept over every n and address
   (``Design.window``), and for a mutation of the core's Gouraud saturation an induction in
   z3 over both netlists with the accumulator's range as an invariant, the reciprocal ROM's
   words kept (``Design.induction``, sim/mutation_accumulator.py).  A proven mutant is
   *equivalent* (no test can kill it); one neither killed nor proven is a *survivor*.

Writes out/mutants/<design>/ (the list, the netlist, the wrapper, the builds, result.json) and
prints one table: mutants, killed (by which check), proven equivalent, survivors.
``--record docs/mutants.json`` also writes the record the docs quote and ``--docs
docs/verification.md`` puts its table there (``make mutants``).
``--sample N`` runs N mutants per design spread evenly over the list (``sample``), the quick
tier's subset (tests/test_mutation.py).  ``--ids`` runs the mutants named, ``--survivors`` the
last result's survivors, and ``--merge`` puts their new outcomes into the design's last
result.json (``merge``: after a proof is added, only the survivors need to run again);
``--reset-proof-only`` gives them the proofs from reset, the window and the induction alone
(their checks and the other proofs already found nothing).

Size: about 680 lines: the list, the netlist, the benches, the checks' order and the record
are one flow, ``make mutants``, whose parts only it runs.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import shutil
import sys
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path

from model.hw.sources import source_list
from model.units import brdf
from sim import core_run, mutation_invariants, units, vector_run, vector_sets
from sim.mutation_accumulator import accumulator_equivalence
from sim.mutation_brdf import BRDF_LONG_CHECKS, brdf_window
from sim.mutation_checks import (
    CORE_CONFIG,
    CTRL,
    SIM,
    Bench,
    Check,
    core_checks,
    parameter_names,
    passes,
    ports,
    unit_checks,
    wrapper,
)
from sim.mutation_proof import (
    PDR_TIMEOUT,
    Contract,
    equivalence,
    mutate_field,
    run_yosys,
    unbuildable,
)
from sim.mutation_report import table, write_docs
from sim.mutation_window import Window, window_equivalence

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "out" / "mutants"
RECORD = ROOT / "docs" / "mutants.json"
SEED = 2026
LIST_SIZE = 300


@dataclass(frozen=True)
class Design:
    """A design under mutation: its name (the record's, ``out/mutants/<name>/``), its top
    (``rtl/<top>.f``) and its committed vector set, whose parameters it is built with (the
    BRDF unit is one design per form: each form's datapath is its own module)."""

    name: str
    top: str
    vector_set: str
    # the second proof method (a register matched as what it shows while busy_reg is 1): the
    # divider and the Gouraud unit (tried on the specular unit's survivors, it proved none)
    busy_proof: bool = False

    @property
    def is_core(self) -> bool:
        return self.top == "shading_core"

    @property
    def contract(self) -> Contract:
        """What the from-reset proof compares: a unit's busy, valid, flags and strobes in every
        cycle after reset and its data outputs (the protocol model's "data" kind) from a
        result on; the core's ``s_axis_tready`` and ``m_axis_tvalid`` in every cycle and its
        pixel beat while ``m_axis_tvalid``."""
        if self.is_core:
            return Contract(
                "m_axis_tvalid", ("m_axis_tdata", "m_axis_tlast", "m_axis_tuser"), False
            )
        spec = units.spec(vector_sets.SETS[self.vector_set][0])
        return Contract("valid", tuple(p.name for p in spec.outputs if p.kind == "data"), True)

    @property
    def window(self) -> Window | None:
        """The fifth proof's window: a BRDF form's datapath (``brdf_window``), or None."""
        if self.top != "brdf_unit":
            return None
        return brdf_window(vector_sets.SETS[self.vector_set][0])

    @property
    def induction(self) -> Callable[[Path, Path, str, int], str | None] | None:
        """The sixth proof: the core's, for a mutation of a Gouraud value's saturation
        (sim/mutation_accumulator.py, an induction in z3 with the accumulator's range), or
        None."""
        return accumulator_equivalence if self.is_core else None


DESIGNS: dict[str, Design] = {
    d.name: d
    for d in (
        Design("divider_shift", "divider_shift", "divider_default", busy_proof=True),
        Design("gouraud_segment", "gouraud_segment", "gouraud_default", busy_proof=True),
        Design("specular_unit", "specular_unit", "specular_default"),
        *(Design(f"brdf_unit_{form}", "brdf_unit", f"brdf_{form}") for form in brdf.RTL_FORMS),
        Design("shading_core", "shading_core", "core_default"),
    )
}


@dataclass(frozen=True)
class Mutation:
    """One line of ``mutate -list``: its id (``mutsel`` value) and the command."""

    id: int
    command: str

    def field(self, name: str) -> str:
        return mutate_field(self.command, name)

    @property
    def mode(self) -> str:
        return self.field("mode")

    @property
    def src(self) -> str:
        """The first source location the mutation names (file:line)."""
        return self.field("src").split(".")[0] + (
            ":" + self.field("src").split(":")[1].split(".")[0] if ":" in self.field("src") else ""
        )

    def ctrl_command(self, width: int) -> str:
        return self.command.replace("mutate ", f"mutate -ctrl {CTRL} {width} {self.id} ", 1)


@dataclass(frozen=True)
class Netlist:
    """A design's mutation list and its netlist with every mutation behind ``mutsel``."""

    design: Design
    folder: Path
    mutations: tuple[Mutation, ...]
    verilog: Path  # the wrapper and the netlist, one file
    design_il: Path  # the prepared original (RTLIL), for the equivalence checks
    width: int
    inputs_digest: str  # of the prepared netlist (netlist_digest)
    list_digest: str  # of the mutation list
    seconds: float


@dataclass(frozen=True)
class Outcome:
    """What became of one mutant: killed by a check, proven equivalent, or surviving."""

    id: int
    command: str
    killed_by: str | None
    equivalent: str | None = None  # how it was proven

    @property
    def survivor(self) -> bool:
        return self.killed_by is None and self.equivalent is None


@dataclass(frozen=True)
class DesignReport:
    design: str
    seed: int
    mutants: int
    killed: dict[str, int]  # check name -> mutants it killed first
    equivalent: tuple[Outcome, ...]
    survivors: tuple[Outcome, ...]
    outcomes: tuple[Outcome, ...]
    inputs_digest: str
    list_digest: str
    prepare_s: float
    build_s: float
    run_s: float
    equiv_s: float
    proved: bool = True  # the survivors of the checks went to the proofs

    @property
    def killed_total(self) -> int:
        return sum(self.killed.values())


def set_parameters(design: Design) -> dict[str, str]:
    """NAME -> Verilog value of the parameters the design is built with: its committed set's
    (ROM images as absolute paths), RESET_ALL = 0 for a unit (its default)."""
    if design.is_core:
        params = core_run.parameters(CORE_CONFIG)
        return {
            k: (f'"{v}"' if isinstance(v, str | Path) else str(int(v))) for k, v in params.items()
        }
    _, params = vector_sets.set_parameters(vector_run.VECTOR_DIR / design.vector_set)
    params.pop("CYCLES")
    return {**params, "RESET_ALL": "0"}


def netlist_digest(design_il: str) -> str:
    """A digest of what a design's list is made from: the prepared netlist (``prep -flatten``'s
    RTLIL, the ROM images' words and the parameters in it, every cell's source line in its
    attributes), the seed and the list's size.  Yosys's comment lines (its version) are left
    out.  An edit that leaves the netlist as it was (a unit's file whose module the design does
    not elaborate, a comment) leaves the record current; any change of a cell, a wire or a
    source line makes it stale."""
    digest = hashlib.sha256(repr((SEED, LIST_SIZE)).encode())
    for line in design_il.splitlines():
        if not line.startswith("#"):
            digest.update(line.encode() + b"\n")
    return digest.hexdigest()[:16]


def quick_sample(rec: dict, n: int) -> list[int]:
    """``n`` ids spread evenly over the mutants a design's record says are killed, but by the
    BRDF unit's exhaustive check and its one-pixel lines (``BRDF_LONG_CHECKS``: 4M to 25M
    cycles each, ``make mutants`` runs them)."""
    killed = sorted(
        int(i) for i, check in rec["killed_by"].items() if check not in BRDF_LONG_CHECKS
    )
    n = min(n, len(killed))
    return [killed[(k * len(killed)) // n] for k in range(n)]


def prepare_list(design: Design, src: Path) -> str:
    """Step 1 of the module's doc in the folder ``src`` (made afresh): the sources and ROM
    images copied there, the prepared netlist (``design.il``) and the mutation list
    (``mutations.txt``); returns the netlist's digest (``netlist_digest``)."""
    if src.exists():
        shutil.rmtree(src)
    (src / "rom").mkdir(parents=True)
    sources = source_list(design.top)
    # The WebAssembly Yosys reaches files by paths relative to its folder (sim/gate.py): the
    # sources and ROM images are copied there.
    for path in sources:
        shutil.copyfile(path, src / path.name)
    chparams = {}
    for name, value in set_parameters(design).items():
        if name.endswith("ROM_FILE"):
            rom = Path(value.strip('"'))
            shutil.copyfile(rom, src / "rom" / rom.name)
            value = f'"rom/{rom.name}"'
        chparams[name] = value
    sets = " ".join(f"-set {k} {v}" for k, v in chparams.items())
    files = " ".join(p.name for p in sources)
    top = design.top
    run_yosys(
        f"read_verilog -defer {files}\nwrite_rtlil abstract.il\nchparam {sets} {top}\n"
        f"hierarchy -top {top}\nprep -flatten -top {top}\nwrite_rtlil design.il\n"
        f"mutate -list {LIST_SIZE} -seed {SEED} -o mutations.txt -s sources.txt\n",
        src,
        "prepare",
    )
    return netlist_digest((src / "design.il").read_text())


def prepare(design: Design, out: Path = OUT) -> Netlist:
    """The mutation list and the netlist with all of it (step 1 and 2 of the module's doc)."""
    t0 = time.monotonic()
    folder = out / design.name
    src = folder / "src"
    top = design.top
    inputs = prepare_list(design, src)
    lines = [ln for ln in (src / "mutations.txt").read_text().splitlines() if ln.strip()]
    mutations = tuple(Mutation(i, ln.strip()) for i, ln in enumerate(lines, 1))
    width = len(mutations).bit_length()
    script = ["read_rtlil design.il"]
    # a mutation of an asynchronous ROM port's enable or reset cannot be written (Yosys requires
    # them constant) and changes nothing (the cell never reads them): its mutsel value selects
    # the original, and the proofs say why (mutation_proof.unread_port)
    design_text = (src / "design.il").read_text()
    script += [m.ctrl_command(width) for m in mutations
               if not unbuildable(design_text, m.command)]  # fmt: skip
    # splitnets: one wire per bit.  A mutation of one bit of a vector reassigns that bit from
    # a multiplexer fed by the vector's other bits, which Verilator, ordering whole vectors,
    # takes for a combinational loop and settles by iterating every cycle; split, each bit is
    # scheduled once (the core's bench runs about 1.5 times as fast).
    script += ["opt_clean", "splitnets", f"rename {top} {top}_mutants",
               "write_verilog -noattr mutants_netlist.v"]  # fmt: skip
    run_yosys("\n".join(script) + "\n", src, "mutate")
    netlist = (src / "mutants_netlist.v").read_text()
    text = "`timescale 1ns / 1ps\n" + wrapper(
        top,
        parameter_names((src / "abstract.il").read_text(), top),
        ports(netlist, f"{top}_mutants"),
        width,
    )
    verilog = folder / f"{top}_mutants.v"
    verilog.write_text(text + netlist)
    shutil.copyfile(src / "mutations.txt", folder / "mutations.txt")
    list_digest = hashlib.sha256("\n".join(m.command for m in mutations).encode()).hexdigest()
    return Netlist(
        design,
        folder,
        mutations,
        verilog,
        src / "design.il",
        width,
        inputs,
        list_digest[:16],
        time.monotonic() - t0,
    )


def build(net: Netlist) -> Bench:
    """The design's bench around the netlist, built once under Verilator."""
    d = net.design
    if d.is_core:
        command, folder, seconds = core_run.build(
            core_run.parameters(CORE_CONFIG), SIM, rtl=[net.verilog]
        )
        return Bench(tuple(command), folder, seconds)
    params = {**set_parameters(d), "RESET_MODES": "1"}  # the instance with RESET_ALL = 0
    params.pop("RESET_ALL")
    b = vector_run.build(d.top, params, SIM, net.folder / "build", rtl=net.verilog)
    if not b.ok:
        raise RuntimeError(f"the mutant bench of {d.top} did not build:\n{b.log[-3000:]}")
    return Bench(tuple(b.command), b.folder, b.seconds)


def checks_of(net: Netlist) -> list[Check]:
    """The design's checks, in the order a mutant meets them."""
    if net.design.is_core:
        return core_checks(net.folder)
    return unit_checks(net.design.vector_set, net.folder)


def sample(n_mutations: int, n: int) -> list[int]:
    """``n`` mutant ids spread evenly over 1..n_mutations (the quick tier's subset)."""
    n = min(n, n_mutations)
    return sorted({1 + (k * n_mutations) // n for k in range(n)})


def run_design(
    design: Design, ids: list[int] | None = None, jobs: int = 2, out: Path = OUT,
    prove: bool = True, pdr_timeout: float = PDR_TIMEOUT, reset_proof_only: bool = False,
) -> DesignReport:  # fmt: skip
    """Every mutant of ``design`` (or those of ``ids``) through its checks and the proofs;
    ``reset_proof_only``: ``ids`` (survivors of an earlier run, whose checks and other proofs
    found nothing) through the proofs from reset alone, nothing built."""
    net = prepare(design, out)
    t0 = time.monotonic()
    bench = None if reset_proof_only else build(net)
    build_s = time.monotonic() - t0
    checks = checks_of(net)
    work = net.folder / "work"
    work.mkdir(exist_ok=True)
    t0 = time.monotonic()
    by_id = {m.id: m for m in net.mutations}
    alive = list(ids if ids is not None else by_id)
    killed_by: dict[int, str] = {}
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        for check in [] if reset_proof_only else checks:
            if not alive:  # a sample all killed: the checks after are not needed
                break
            if check.writer is not None:
                check.writer()
            # the original passes every check a mutant meets: so each can pass as well as fail
            if not passes(bench, check, 0, work):
                raise RuntimeError(f"{design.name}: the original (mutant 0) fails {check.name}")
            results = list(pool.map(lambda i, c=check: passes(bench, c, i, work), alive))
            for i, ok in zip(alive, results, strict=True):
                if not ok:
                    killed_by[i] = check.name
            alive = [i for i, ok in zip(alive, results, strict=True) if ok]
            print(f"  {design.name}: {check.name}: {len(alive)} alive", file=sys.stderr, flush=True)
    run_s = time.monotonic() - t0
    t0 = time.monotonic()
    proven: dict[int, str] = {}
    design_text = net.design_il.read_text() if prove and alive else ""
    window = design.window

    def proof(i: int) -> str | None:
        """The method that proves mutant ``i`` equivalent: the four of ``equivalence``, then
        for a design with a window the fifth (``window_equivalence``), for the core the
        sixth (``Design.induction``); or None."""
        folder, command = net.folder / "equiv" / str(i), by_id[i].command
        how = equivalence(
            folder, design.top, net.design_il, command, design.busy_proof,
            contract=design.contract, pdr_timeout=pdr_timeout, earlier=not reset_proof_only,
            invariants=mutation_invariants.invariants(design.name, command, design_text),
            stronger=mutation_invariants.stronger(design.name, design_text),
        )  # fmt: skip
        if how is None and window is not None:
            how = window_equivalence(folder, design.top, net.design_il, command, window)
        if how is None and design.induction is not None:
            how = design.induction(folder, net.design_il, command, jobs)
        return how

    if prove:
        with ThreadPoolExecutor(max_workers=jobs) as pool:
            for i, how in zip(alive, pool.map(proof, alive), strict=True):
                if how:
                    proven[i] = how
    equiv_s = time.monotonic() - t0
    chosen = ids if ids is not None else list(by_id)
    outcomes = tuple(
        Outcome(i, by_id[i].command, killed_by.get(i), proven.get(i)) for i in sorted(chosen)
    )
    killed = {c.name: sum(1 for o in outcomes if o.killed_by == c.name) for c in checks}
    report = DesignReport(
        design.name,
        SEED,
        len(outcomes),
        killed,
        tuple(o for o in outcomes if o.equivalent),
        tuple(o for o in outcomes if o.survivor),
        outcomes,
        net.inputs_digest,
        net.list_digest,
        net.seconds,
        build_s,
        run_s,
        equiv_s,
        prove,
    )
    (net.folder / "result.json").write_text(json.dumps(asdict(report), indent=2) + "\n")
    return report


def record(reports: list[DesignReport]) -> dict:
    """The record ``make mutants`` writes (docs/mutants.json): per design what became of
    every mutant, the digests of what the list was made from, the times."""
    return {
        "generated_by": "make mutants (python -m sim.mutation --record docs/mutants.json)",
        "seed": SEED,
        "list_size": LIST_SIZE,
        "designs": {
            r.design: {
                "vector_set": DESIGNS[r.design].vector_set,
                "inputs_digest": r.inputs_digest,
                "list_digest": r.list_digest,
                "mutants": r.mutants,
                "proved": r.proved,
                "killed": r.killed,
                "equivalent": [asdict(o) for o in r.equivalent],
                "survivors": [asdict(o) for o in r.survivors],
                "killed_by": {str(o.id): o.killed_by for o in r.outcomes if o.killed_by},
                "seconds": {
                    "list": round(r.prepare_s, 1),
                    "build": round(r.build_s, 1),
                    "runs": round(r.run_s, 1),
                    "proofs": round(r.equiv_s, 1),
                },
            }
            for r in reports
        },
    }


def details(reports: list[DesignReport]) -> str:
    """Per design: the kills by check, the times, every equivalent mutant and survivor."""
    lines = []
    for r in reports:
        kills = ", ".join(f"{n}: {k}" for n, k in r.killed.items())
        lines.append(
            f"{r.design}: {r.mutants} mutants (seed {r.seed}), killed {r.killed_total} ({kills}), "
            f"equivalent {len(r.equivalent)}, survivors {len(r.survivors)}; "
            f"list {r.prepare_s:.1f} s, build {r.build_s:.1f} s, runs {r.run_s:.1f} s, "
            f"proofs {r.equiv_s:.1f} s"
        )
        for o in r.equivalent:
            lines.append(f"  equivalent {o.id}: {o.command}  [{o.equivalent}]")
        for o in r.survivors:
            lines.append(f"  SURVIVOR {o.id}: {o.command}")
    return "\n".join(lines) + "\n"


def load_report(path: Path) -> DesignReport:
    """A design's report from the result.json ``run_design`` wrote."""
    d = json.loads(path.read_text())
    outcomes = {
        k: tuple(Outcome(**o) for o in d[k]) for k in ("equivalent", "survivors", "outcomes")
    }
    return DesignReport(**{**d, **outcomes})


def report_from_record(rec: dict, name: str, commands: list[str]) -> DesignReport:
    """A design's report as the record (docs/mutants.json) holds it, for a checkout without the
    run's result.json: every mutant's outcome (``commands``: the list, line i = mutant i), the
    digests and the seconds."""
    d = rec["designs"][name]
    outcomes = {int(i): Outcome(int(i), commands[int(i) - 1], check)
                for i, check in d["killed_by"].items()}  # fmt: skip
    for o in (*d["equivalent"], *d["survivors"]):
        outcomes[o["id"]] = Outcome(**o)
    ordered = tuple(outcomes[i] for i in sorted(outcomes))
    sec = d["seconds"]
    return DesignReport(
        name, rec["seed"], d["mutants"], dict(d["killed"]),
        tuple(o for o in ordered if o.equivalent), tuple(o for o in ordered if o.survivor),
        ordered, d["inputs_digest"], d["list_digest"], sec["list"], sec["build"], sec["runs"],
        sec["proofs"], d["proved"],
    )  # fmt: skip


def merge(full: DesignReport, part: DesignReport) -> DesignReport:
    """``full`` (a run of a design's whole list) with the outcomes of ``part`` (a later run of
    some of its mutants, e.g. the survivors given to a new proof) in place of its own for
    those mutants: the kills counted again, the seconds of both runs' checks and proofs added
    up (the list and the build are the full run's).  The merge is proved (its survivors went to
    the proofs) when the later run was and it covered every survivor of the full run, whether
    or not the full run gave them to the proofs itself (``--no-prove`` first, then
    ``--survivors --merge``)."""
    if (part.list_digest, part.inputs_digest) != (full.list_digest, full.inputs_digest):
        raise ValueError(f"{full.design}: the two runs are of different lists")
    part_ids = [o.id for o in part.outcomes]
    by_id = {o.id: o for o in full.outcomes} | {o.id: o for o in part.outcomes}
    outcomes = tuple(by_id[i] for i in sorted(by_id))
    names = list(dict.fromkeys([*full.killed, *part.killed]))
    return DesignReport(
        full.design,
        full.seed,
        len(outcomes),
        {n: sum(1 for o in outcomes if o.killed_by == n) for n in names},
        tuple(o for o in outcomes if o.equivalent),
        tuple(o for o in outcomes if o.survivor),
        outcomes,
        full.inputs_digest,
        full.list_digest,
        full.prepare_s,
        full.build_s,
        full.run_s + part.run_s,
        full.equiv_s + part.equiv_s,
        part.proved and (full.proved or {o.id for o in full.survivors} <= set(part_ids)),
    )


def _last_result(result: Path, record_path: Path | None, name: str) -> DesignReport:
    """The design's last result.json, or (a fresh checkout) its outcomes in the record
    ``--record`` names, which ``--merge`` then rewrites."""
    if result.exists():
        return load_report(result)
    if record_path is None or not record_path.exists():
        raise SystemExit(
            f"{result} does not exist: run the design's whole list first, or give --record "
            "with the record to merge into (docs/mutants.json)"
        )
    commands = prepare(DESIGNS[name], result.parent.parent).mutations
    return report_from_record(
        json.loads(record_path.read_text()), name, [m.command for m in commands]
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m sim.mutation", description=__doc__.split("\n")[0]
    )
    parser.add_argument("--design", nargs="+", choices=list(DESIGNS), default=list(DESIGNS))
    parser.add_argument("--sample", type=int, help="N mutants per design, spread evenly")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--record", type=Path, help="write the record (docs/mutants.json)")
    parser.add_argument("--docs", type=Path, help="put the table into (docs/verification.md)")
    parser.add_argument(
        "--no-prove", action="store_true", help="survivors of the checks are not given to proofs"
    )
    parser.add_argument(
        "--collect", action="store_true", help="report the designs' last results, run nothing"
    )
    parser.add_argument("--ids", type=int, nargs="+", help="run only these mutants")
    parser.add_argument(
        "--survivors", action="store_true", help="run only the last result's survivors"
    )
    parser.add_argument(
        "--merge",
        action="store_true",
        help="merge the run's outcomes into the design's last result.json (merge)",
    )
    parser.add_argument(
        "--pdr-timeout", type=float, default=PDR_TIMEOUT, help="seconds of each pdr proof"
    )
    parser.add_argument(
        "--reset-proof-only",
        action="store_true",
        help="with --merge: the last result's survivors among the mutants run only the proofs "
        "from reset and the window (their checks and other proofs are in it)",
    )
    args = parser.parse_args(argv)
    if args.reset_proof_only and not args.merge:
        parser.error("--reset-proof-only needs --merge")
    reports = []
    t0 = time.monotonic()
    for name in args.design:
        result = args.out.resolve() / name / "result.json"
        if args.collect:
            reports.append(load_report(result))
            continue
        ids = sample(LIST_SIZE, args.sample) if args.sample else args.ids
        last = None
        if args.merge or args.survivors:
            last = _last_result(result, args.record, name)
        if args.survivors:
            ids = [o.id for o in last.survivors]
        if args.reset_proof_only:
            alive = {o.id for o in last.survivors}
            ids = [i for i in (ids or sorted(alive)) if i in alive]
        report = run_design(
            DESIGNS[name], ids, args.jobs, args.out.resolve(), not args.no_prove,
            args.pdr_timeout, args.reset_proof_only,
        )  # fmt: skip
        if args.merge:
            report = merge(last, report)
            result.write_text(json.dumps(asdict(report), indent=2) + "\n")
        reports.append(report)
        print(details(reports[-1:]), end="", flush=True)
    print(table(record(reports)), end="")
    print(f"mutation testing: {time.monotonic() - t0:.1f} s")
    rec = record(reports)
    if args.record:
        # the designs not run keep what the record says of them
        if args.record.exists():
            kept = json.loads(args.record.read_text())["designs"]
            designs = {**kept, **rec["designs"]}
            rec["designs"] = {n: designs[n] for n in DESIGNS if n in designs}
        args.record.write_text(json.dumps(rec, indent=2) + "\n")
    if args.docs:
        write_docs(rec, args.docs)
    return 1 if any(r.survivors for r in reports) else 0


if __name__ == "__main__":
    sys.exit(main())
