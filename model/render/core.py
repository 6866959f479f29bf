# SPDX-License-Identifier: Apache-2.0
"""The streaming shading core (``rtl/shading_core.v``, docs/core.md): its stream formats, the
packer and unpacker the host and the benches share, and the model of what it outputs and when.

**In**: one AXI4-Stream beat per span (``SpanFormat``), every operand the span's ``UnitJobs``
rows hold: position and intervals, the Gouraud start and end register of each channel, the
highlight's registers C, dz, z0, n (with a flag: the span's highlight goes through the
highlight unit: the specular unit, or the BRDF unit of ``PipelineConfig.brdf``), and the
diffuse jobs' registers (with a flag: the diffuse term comes from the unit at n = 1).  The
three diffuse jobs of a span share dz and z0: ``specular.setup_row`` computes them from N and
L alone, only C carries the channel's colour; the packer checks that they agree and carries
them once.

**Out**: one beat per pixel (``PixelFormat``): x, y and RGB888, ``tlast`` on a span's last
pixel and ``tuser`` = 1 on the pixels of a span whose n the highlight unit refuses (its
highlight is then 0, as the unit's ``n_err`` says).

Per pixel the core does what ``pipeline.assemble`` does with the units' outputs: dI from the
divider's quotient (``a * round(2**N / k)``, rounded to the Gouraud ``di`` format), the
Gouraud lane value ``i0 + bias + x dI`` truncated and saturated, the specular unit's
``C cos^k(a |z0 + x dz|)`` (or the BRDF unit's ``unit_line``) for the highlight and the
specular unit's for each channel's diffuse term, then ``min(gouraud + diffuse + specular,
255)``.  ``core_pixels`` computes that from the packed
words through the units' public per-line calls (an implementation apart from the pipeline's
kernels: the tests compare it with the pipeline's image byte for byte).

**Timing**: with every span beat offered back to back and the output always ready, the core
takes one span beat per clock while it has room and gives one pixel per clock; the first pixel
leaves ``latency(cfg)`` clocks after the first span beat is taken, and the last
``latency(cfg) + pixels - 1`` clocks after it.  ``core_cycles`` gives that count; the benches
measure it.  The latency depends on the highlight path: ``LATENCY`` (18) with the patent's
specular unit, more with a BRDF form (``highlight_stages``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from model.render.pipeline import DIFFUSE_N, PipelineConfig, UnitJobs, increment_from_quotient
from model.units import divider, gouraud, specular
from model.units.brdf import unit as brdf_unit

CHANNELS = 3
N_WIDTH = 10
X_WIDTH = 12
Y_WIDTH = 12
OUT_MAX = 255
"""RGB888: each channel saturates at 255 (``pipeline.assemble``'s ``out_max``)."""

SPAN_PIPE = 6
"""Clocks from the cycle a span beat is taken to the cycle its first pixel is issued: stage A
(the input register, ROM 9, the reciprocal ROM, decoder 10, or a BRDF form's word of n), stages
B..E (the divider's operands registered, four partial products, two sums), the span
register."""
SPECULAR_STAGES = 10
"""The patent's highlight path (rtl/shading_specular_pipe.v): S1..S10 from a pixel issued to
its intensity; the diffuse path has the same stages.  A core without a highlight path keeps
them."""
BRDF_FRONT_BACK = 7
"""A BRDF highlight path's stages besides its form's (rtl/shading_brdf_pipe.v): the front
S1..S5 (rtl/brdf_front.v: |zeta| in two steps, the angle-table address, the table's read, the
w gate), x C and the rounding register."""
CORE_FORMS = ("cosine_quadratic", "quadratic", "cubic", "log2", "piecewise")
"""The BRDF forms the core's highlight path takes (rtl/shading_brdf_pipe.v, HIGHLIGHT): every
form of ``brdf.unit.RTL_FORMS``; a form with RTL but not here would have no pipe in the core,
and a configuration with it would be refused by name."""
PIXEL_PIPE = SPECULAR_STAGES + 2
"""Clocks from a pixel issued (in S0, the span register's accumulators) to its beat on
``m_axis`` with the patent's highlight path: the specular stages S1..S10, the sum into the
output FIFO, its output register (``pixel_pipe`` for any configuration)."""
LATENCY = SPAN_PIPE + PIXEL_PIPE
"""Clocks from the cycle the first span beat is taken to the cycle of the first pixel beat,
with the patent's highlight path (``latency`` for any configuration)."""
FIFO_DEPTHS = tuple(1 << b for b in range(4, 13))
"""The output FIFO's legal depths (FIFO_DEPTH): powers of two from 16 to 4096, and above the
pixels in flight (``pixel_pipe``), so that the credit count never stops the issuer while the
output is ready."""
FIFO_DEPTH = 32
"""The output FIFO's depth by default (the RTL's FIFO_DEPTH), where the pixels in flight leave
room in it (``default_fifo_depth``)."""


def _round8(bits: int) -> int:
    return -(-bits // 8) * 8


class BeatFormat:
    """A beat's fields, low bits first: ``fields`` (name, width) in order, what the beat takes
    of them (``bits``), the tdata width (``width``: whole bytes) and ``layout``."""

    x_width: int
    y_width: int

    @property
    def fields(self) -> tuple[tuple[str, int], ...]:
        raise NotImplementedError

    def _check_xy(self) -> None:
        for name in ("x_width", "y_width"):
            value = getattr(self, name)
            if not 1 <= value <= 16:
                raise ValueError(f"{name} = {value} is out of range: legal range is 1..16")

    @property
    def bits(self) -> int:
        """Bits the fields take (the rest of the beat, up to ``width``, is zero)."""
        return sum(w for _, w in self.fields)

    @property
    def width(self) -> int:
        """``tdata`` width: the fields rounded up to whole bytes."""
        return _round8(self.bits)

    def layout(self) -> list[tuple[str, int, int]]:
        """(name, low bit, width) of every field."""
        out, at = [], 0
        for name, w in self.fields:
            out.append((name, at, w))
            at += w
        return out


@dataclass(frozen=True)
class SpanFormat(BeatFormat):
    """The span beat (docs/core.md, "Span beat").  Widths follow the pipeline configuration:
    ``len_width`` of the Gouraud unit for l, the Gouraud register width for the intensities,
    the specular unit's C and z widths."""

    cfg: PipelineConfig
    x_width: int = X_WIDTH
    y_width: int = Y_WIDTH

    def __post_init__(self) -> None:
        self._check_xy()

    @property
    def fields(self) -> tuple[tuple[str, int], ...]:
        g, s = self.cfg.gouraud, self.cfg.specular
        iw, cw, zw = g.i_width, s.c_width, s.z_width
        return (
            ("x", self.x_width),
            ("y", self.y_width),
            ("l", g.len_width),
            ("spec", 1),
            ("diff", 1),
            *((f"i_start{c}", iw) for c in range(CHANNELS)),
            *((f"i_end{c}", iw) for c in range(CHANNELS)),
            ("c", cw),
            ("dz", zw),
            ("z0", zw),
            ("n", N_WIDTH),
            *((f"diff_c{c}", cw) for c in range(CHANNELS)),
            ("diff_dz", zw),
            ("diff_z0", zw),
        )


@dataclass(frozen=True)
class PixelFormat(BeatFormat):
    """The pixel beat: x, y, R, G, B (docs/core.md, "Pixel beat")."""

    x_width: int = X_WIDTH
    y_width: int = Y_WIDTH

    def __post_init__(self) -> None:
        self._check_xy()

    @property
    def fields(self) -> tuple[tuple[str, int], ...]:
        return (("x", self.x_width), ("y", self.y_width), ("r", 8), ("g", 8), ("b", 8))


SIGNED = ("dz", "z0", "diff_dz", "diff_z0")
"""Span fields in two's complement (the rest are unsigned)."""


def pack(layout: list[tuple[str, int, int]], values: dict[str, int]) -> int:
    """One beat from its field values; a value that does not fit its field raises, naming it."""
    word = 0
    for name, lo, w in layout:
        v = int(values.get(name, 0))
        signed = name in SIGNED
        vmin, vmax = (-(1 << (w - 1)), (1 << (w - 1)) - 1) if signed else (0, (1 << w) - 1)
        if not vmin <= v <= vmax:
            raise ValueError(
                f"span field {name} = {v} is out of range: legal range is {vmin}..{vmax} "
                f"({w} bits{', signed' if signed else ''})"
            )
        word |= (v & ((1 << w) - 1)) << lo
    return word


def unpack(layout: list[tuple[str, int, int]], word: int) -> dict[str, int]:
    """The field values of one beat (``SIGNED`` fields sign-extended)."""
    out = {}
    for name, lo, w in layout:
        v = (int(word) >> lo) & ((1 << w) - 1)
        if name in SIGNED and v >> (w - 1):
            v -= 1 << w
        out[name] = v
    return out


def span_beats(jobs: UnitJobs, x_start: np.ndarray, y: np.ndarray, fmt: SpanFormat) -> list[int]:
    """One span beat per span of one object's ``jobs``, in span order (``x_start``, ``y``: the
    spans' first pixel).  The diffuse jobs of a span must share dz and z0."""
    spans = jobs.intervals.size
    if jobs.i_start.shape != (spans, CHANNELS):
        raise ValueError(
            f"i_start has shape {jobs.i_start.shape}: the core takes {CHANNELS} colour channels"
        )
    rows: list[dict[str, int]] = [
        {
            "x": int(x_start[s]),
            "y": int(y[s]),
            "l": int(jobs.intervals[s]),
            **{f"i_start{c}": int(jobs.i_start[s, c]) for c in range(CHANNELS)},
            **{f"i_end{c}": int(jobs.i_end[s, c]) for c in range(CHANNELS)},
        }
        for s in range(spans)
    ]
    for j, s in enumerate(jobs.spec_span):
        rows[s].update(
            spec=1,
            c=int(jobs.spec_c[j]),
            dz=int(jobs.spec_dz[j]),
            z0=int(jobs.spec_z0[j]),
            n=int(jobs.spec_n[j]),
        )
    for j, (s, c) in enumerate(zip(jobs.diff_span, jobs.diff_channel, strict=True)):
        row = rows[s]
        dz, z0 = int(jobs.diff_dz[j]), int(jobs.diff_z0[j])
        if row.get("diff") and (row["diff_dz"], row["diff_z0"]) != (dz, z0):
            raise ValueError(
                f"span {s}: the diffuse jobs' dz, z0 differ between channels "
                f"({row['diff_dz']}, {row['diff_z0']} against {dz}, {z0} in channel {c}): "
                "the core takes one angle per span for the three channels"
            )
        row.update(diff=1, diff_dz=dz, diff_z0=z0)
        row[f"diff_c{c}"] = int(jobs.diff_c[j])
    layout = fmt.layout()
    return [pack(layout, row) for row in rows]


def _diffuse_check(cfg: PipelineConfig) -> None:
    if cfg.specular.n_first > DIFFUSE_N:
        raise ValueError(
            f"specular n_first = {cfg.specular.n_first} is out of range for diffuse spans: "
            f"the diffuse jobs need n = {DIFFUSE_N} (n_first = 1)"
        )


def default_paths(cfg: PipelineConfig) -> tuple[bool, bool]:
    """(highlight path, diffuse path): the paths a core for ``cfg``'s modes is built with."""
    return cfg.specular_mode != "vertex", cfg.diffuse_mode != "gouraud"


def check_core(cfg: PipelineConfig) -> PipelineConfig:
    """``cfg`` if the core can be built for it, else ``ValueError`` naming what it cannot: a
    BRDF highlight of a form without a pipe in the core (``CORE_FORMS``)."""
    if cfg.brdf is not None and cfg.brdf.form not in CORE_FORMS:
        raise ValueError(
            f"brdf form = {cfg.brdf.form!r} is out of range for the shading core: its highlight "
            f"path takes the specular unit or the forms {CORE_FORMS}"
        )
    return cfg


def _highlight_path(cfg: PipelineConfig, specular_path: bool | None) -> bool:
    return default_paths(cfg)[0] if specular_path is None else bool(specular_path)


def highlight_stages(cfg: PipelineConfig | None = None, specular_path: bool | None = None) -> int:
    """The pixel pipeline's stages S1..S(n) of a core for ``cfg`` (default: the default
    configuration): ``SPECULAR_STAGES`` for the patent's highlight path (or none), and for a
    BRDF form ``BRDF_FRONT_BACK`` + the form's (``brdf.unit.form_latency``: 12 for the
    cosine-quadratic, 13 for the quadratic, 14 for the log2, 20 for the cubic, 31 for the
    piecewise form at its default widths).  The diffuse terms wait for the highlight."""
    cfg = check_core(cfg or PipelineConfig())
    if cfg.brdf is None or not _highlight_path(cfg, specular_path):
        return SPECULAR_STAGES
    return BRDF_FRONT_BACK + brdf_unit.form_latency(cfg.brdf)


def pixel_pipe(cfg: PipelineConfig | None = None, specular_path: bool | None = None) -> int:
    """Clocks from a pixel issued to its beat on ``m_axis``: ``highlight_stages``, the FIFO's
    write and its output register."""
    return highlight_stages(cfg, specular_path) + 2


def default_fifo_depth(cfg: PipelineConfig | None = None, specular_path: bool | None = None) -> int:
    """The output FIFO's depth a core for ``cfg`` is built with by default: ``FIFO_DEPTH`` (32),
    or the smallest of ``FIFO_DEPTHS`` above the pixels in flight where those fill it (64 for
    the piecewise form's 33)."""
    in_flight = pixel_pipe(cfg, specular_path)
    return next(d for d in FIFO_DEPTHS if d >= FIFO_DEPTH and d > in_flight)


def latency(cfg: PipelineConfig | None = None, specular_path: bool | None = None) -> int:
    """Clocks from the cycle the first span beat is taken to the cycle of the first pixel beat
    (``SPAN_PIPE`` + ``pixel_pipe``): ``LATENCY`` = 18 with the patent's highlight path."""
    return SPAN_PIPE + pixel_pipe(cfg, specular_path)


def core_pixels(
    words: list[int],
    fmt: SpanFormat,
    specular_path: bool | None = None,
    diffuse_path: bool | None = None,
) -> list[dict[str, int]]:
    """What leaves the core's output port for the span beats ``words``, in order: per pixel
    x, y, r, g, b, ``last`` (tlast) and ``n_err`` (tuser), from the units' public calls, for a
    core built with the given paths (default: ``default_paths``).  A span whose flag asks for a
    path the core lacks gets 0 for that term and tuser = 1, as does a refused n; x counts on
    modulo 2**x_width, as the core's column register does.  With ``cfg.brdf`` set the
    highlight is the BRDF unit's line (``brdf.unit.unit_line``, n outside 1..1000 refused)."""
    cfg = check_core(fmt.cfg)
    paths = default_paths(cfg)
    has_spec = paths[0] if specular_path is None else bool(specular_path)
    has_diff = paths[1] if diffuse_path is None else bool(diffuse_path)
    if has_diff:
        _diffuse_check(cfg)
    x_mask = (1 << fmt.x_width) - 1
    d, g, sp = cfg.divider, cfg.gouraud, cfg.specular
    layout = fmt.layout()
    out: list[dict[str, int]] = []
    for word in words:
        f = unpack(layout, word)
        l_int = f["l"]
        n_px = l_int + 1
        total = np.zeros((n_px, CHANNELS), dtype=np.int64)
        for c in range(CHANNELS):
            di = 0
            if l_int > 0:
                q = divider.divide(f[f"i_end{c}"] - f[f"i_start{c}"], l_int, d)
                di = int(increment_from_quotient(np.array([q]), cfg)[0])
            total[:, c] = gouraud.shade_line(f[f"i_start{c}"], di, n_px, g)
        n_err = 0
        if f["spec"] and not has_spec:
            n_err = 1
        elif f["spec"] and cfg.brdf is not None:
            line, n_err = brdf_unit.unit_line(f["c"], f["dz"], f["z0"], f["n"], l_int, cfg.brdf)
            total += np.asarray(line, dtype=np.int64)[:, None]
        elif f["spec"]:
            line, n_err = specular.unit_line(f["c"], f["dz"], f["z0"], f["n"], l_int, sp)
            total += np.asarray(line, dtype=np.int64)[:, None]
        if f["diff"] and not has_diff:
            n_err = 1
        elif f["diff"]:
            for c in range(CHANNELS):
                total[:, c] += specular.shade_line(
                    f[f"diff_c{c}"], f["diff_dz"], f["diff_z0"], DIFFUSE_N, l_int, sp
                )
        rgb = np.minimum(total, OUT_MAX)
        for x in range(n_px):
            out.append(
                {
                    "x": (f["x"] + x) & x_mask,
                    "y": f["y"],
                    "r": int(rgb[x, 0]),
                    "g": int(rgb[x, 1]),
                    "b": int(rgb[x, 2]),
                    "last": int(x == l_int),
                    "n_err": int(n_err),
                }
            )
    return out


def pixel_word(pix: dict[str, int], fmt: PixelFormat) -> int:
    """The pixel beat's ``tdata`` of one output pixel."""
    return pack(fmt.layout(), pix)


def core_cycles(
    pixels: int, cfg: PipelineConfig | None = None, specular_path: bool | None = None
) -> int:
    """Clocks from the cycle the first span beat is taken to the cycle of the last pixel beat,
    both counted, with the span beats offered back to back and the output always ready, for a
    core of ``cfg`` (default: the default configuration): ``latency(cfg)`` + pixels (the core
    issues one pixel per clock; a span beat waits in stage B while the previous span's pixels
    issue, and moves into the span register with its last one)."""
    if pixels < 1:
        raise ValueError(f"pixels = {pixels} is out of range: legal is >= 1")
    return latency(cfg, specular_path) + pixels


def core_parameters(
    cfg: PipelineConfig,
    fmt: SpanFormat | None = None,
    specular_path: bool | None = None,
    diffuse_path: bool | None = None,
    fifo_depth: int | None = None,
) -> dict[str, object]:
    """The Verilog parameters of ``rtl/shading_core.v`` for ``cfg``: the units' fields in upper
    case (the specular unit's ``LEN_WIDTH`` as ``SPEC_LEN_WIDTH``), the ROM images' paths,
    which paths are built (default: what ``cfg``'s modes use), the highlight's unit
    (``HIGHLIGHT``: "specular", or ``cfg.brdf``'s form with that unit's own fields, its angle
    formats being the specular unit's) and the output FIFO's depth (``default_fifo_depth``).
    A configuration the core cannot build is refused by name (``check_core``; ``fifo_depth``
    one of ``FIFO_DEPTHS`` above ``pixel_pipe``)."""
    check_core(cfg)
    fmt = fmt or SpanFormat(cfg)
    d, g, s = cfg.divider, cfg.gouraud, cfg.specular
    spec = dict(s.hdl_parameters())
    spec["SPEC_LEN_WIDTH"] = spec.pop("LEN_WIDTH")
    paths = default_paths(cfg)
    specular_path = paths[0] if specular_path is None else specular_path
    diffuse_path = paths[1] if diffuse_path is None else diffuse_path
    if diffuse_path:
        _diffuse_check(cfg)
    in_flight = pixel_pipe(cfg, specular_path)
    if fifo_depth is None:
        fifo_depth = default_fifo_depth(cfg, specular_path)
    if fifo_depth not in FIFO_DEPTHS or fifo_depth <= in_flight:
        raise ValueError(
            f"fifo_depth = {fifo_depth} is out of range: legal is a power of two from 16 to "
            f"4096 above the {in_flight} pixels in flight"
        )
    highlight: dict[str, object] = {"HIGHLIGHT": "specular"}
    if cfg.brdf is not None:
        own = brdf_unit.hdl_parameters(cfg.brdf)
        for name in ("FORM", *(f.upper() for f in brdf_unit.ANGLE_FIELDS)):
            own.pop(name)
        highlight = {"HIGHLIGHT": cfg.brdf.form, **own}
    return {
        "X_WIDTH": fmt.x_width,
        "Y_WIDTH": fmt.y_width,
        "SPECULAR": int(bool(specular_path)),
        "DIFFUSE": int(bool(diffuse_path)),
        "FIFO_DEPTH": fifo_depth,
        "A_WIDTH": d.a_width,
        "K_WIDTH": d.k_width,
        "RECIP_BITS": d.recip_bits,
        "RECIP_ROM_FILE": str(divider.rom_path(d)),
        "I_INT": g.i_int,
        "I_FRAC": g.i_frac,
        "LEN_WIDTH": g.len_width,
        **spec,
        **highlight,
    }


@dataclass
class FrameStream:
    """A frame's span beats, objects in shading order, and where each object's pixels are."""

    words: list[int]
    objects: list[int]  # object index of each object's run of beats, in order
    spans: list[int]  # span beats per object, in order
    pixels: list[int]  # pixels per object, in order

    @property
    def total_pixels(self) -> int:
        return sum(self.pixels)


def frame_stream(frame_raster, cfg: PipelineConfig, fmt: SpanFormat | None = None) -> FrameStream:
    """The span beats a host sends the core for ``frame_raster`` (a ``raster.Raster``): every
    object's spans in the order ``shade.shade`` visits them, through ``pipeline.build_jobs``
    (the same jobs the units' model receives)."""
    from model.render import pipeline, shade  # shade imports the pipeline's kernels

    fmt = fmt or SpanFormat(cfg)
    out = FrameStream([], [], [], [])

    def record(spans, ctx):
        jobs = pipeline.build_jobs(spans, ctx, cfg)
        last = spans.x_end.max() if len(spans) else 0
        if last >> fmt.x_width or (spans.y.max() if len(spans) else 0) >> fmt.y_width:
            raise ValueError(
                f"object {ctx.obj}: a pixel at x = {int(last)} or y = {int(spans.y.max())} is "
                f"out of range: the core's beats hold x < 2**{fmt.x_width}, y < 2**{fmt.y_width}"
            )
        out.words.extend(span_beats(jobs, spans.x_start, spans.y, fmt))
        out.objects.append(ctx.obj)
        out.spans.append(len(spans))
        out.pixels.append(spans.n_pixels)
        return np.zeros((spans.n_pixels, CHANNELS), dtype=np.uint8)

    shade.shade(frame_raster, record)
    return out
