# SPDX-License-Identifier: Apache-2.0
"""The netlist surgery of ``make mutants``' proofs (sim/mutation_proof.py), on RTLIL text: the
ROM tables cut out of a design (``cut_roms``: each read port's address made an output and its
word an input, so that the original and the mutant read the same table without a SAT model
of its words), its multipliers cut likewise (``cut_products``), internal wires shown as
output ports for the invariants (``probed``; the invariant syntax, ``invariant_wires``,
``invariant_verilog``) and as what they show under a condition (``observed``).

Size: each function rewrites one kind of cell or wire; none runs Yosys.
"""

from __future__ import annotations

import re


def _sig_chunks(spec: str) -> list[str]:
    """The chunks of the RTLIL signal ``spec`` (a wire, a slice ``\\w [3:0]`` or ``\\w [5]``, a
    constant ``N'bits``, or ``{ ... }`` of those), most significant first."""
    spec = spec.strip()
    if spec.startswith("{"):
        spec = spec[1:-1]
    chunks: list[str] = []
    for token in spec.split():
        if token.startswith("[") and chunks:
            chunks[-1] += f" {token}"
        else:
            chunks.append(token)
    return chunks


def _const_bits(spec: str, widths: dict[str, int]) -> list[str | None]:
    """The bits of the RTLIL signal ``spec``, least significant first: '0' or '1' where it is
    that constant, None where it is a wire (or an undefined constant bit)."""
    bits: list[str | None] = []
    for chunk in reversed(_sig_chunks(spec)):
        const = re.fullmatch(r"(\d+)'([01xz]*)", chunk)
        if const:
            bits += [b if b in "01" else None for b in reversed(const.group(2))]
            continue
        sliced = re.fullmatch(r"(\S+) \[(\d+)(?::(\d+))?\]", chunk)
        if sliced:
            hi, lo = int(sliced.group(2)), int(sliced.group(3) or sliced.group(2))
            bits += [None] * (hi - lo + 1)
        else:
            bits += [None] * widths[chunk]
    return bits


def _constant_reads(block: str, params: dict, conns: dict, widths: dict[str, int]) -> dict:
    """{port: its word as RTLIL constant} for each asynchronous read port of the ROM cell
    ``block`` whose address is a constant (a port wired to one word, as the core's read of
    n = 1's a): the word of the cell's ``INIT`` at that address, where it is defined."""
    ports, abits, width = int(params["RD_PORTS"]), int(params["ABITS"]), int(params["WIDTH"])
    clocked = params["RD_CLK_ENABLE"].split("'", 1)[1][::-1]  # port 0 first
    size, offset = int(params["SIZE"]), int(params.get("OFFSET", "0"))
    init = re.search(r"^\s*parameter \\INIT (?:(\d+)'([01x]+)|(\d+))$", block, re.M)
    if init is None:
        return {}
    if init.group(3) is not None:  # a value of 32 bits or fewer is written as a decimal
        words = format(int(init.group(3)), f"0{size * width}b")[::-1]
    else:
        words = init.group(2)[::-1]  # bit 0 first
    addr = _const_bits(conns["RD_ADDR"], widths)
    found = {}
    for i in range(ports):
        bits = addr[i * abits : (i + 1) * abits]
        if (clocked + "0" * ports)[i] != "0" or None in bits:
            continue
        index = int("".join(reversed(bits)), 2) - offset  # type: ignore[arg-type]
        if not 0 <= index < size:
            continue
        word = words[index * width : (index + 1) * width][::-1]
        if "x" not in word:
            found[i] = f"{width}'{word}"
    return found


def cut_roms(il: str) -> str:
    """The RTLIL ``il`` with every ROM (a ``$mem_v2`` without write ports) cut out: its read
    address (and enable) become output ports, its read data an input port.  Equivalence through
    the cut is proven for any read data, the same in both designs whenever their addresses are
    (proven, as outputs): sound, and SAT never sees a table.  A read port whose address is a
    constant (``_constant_reads``) reads its word instead: the table's word there is part of the
    design (the core reads n = 1's a so, and its diffuse path is right only for that word)."""
    widths = {
        name: int(width or 1)
        for width, name in re.findall(r"^\s*wire (?:width (\d+) )?(?:\w+ \d+ )?(\S+)$", il, re.M)
    }
    lines = il.split("\n")
    out: list[str] = []
    extra_wires: list[str] = []
    k = 0
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.strip().startswith("cell $mem_v2 "):
            block = [line]
            while lines[i].strip() != "end":
                i += 1
                block.append(lines[i])
            params = dict(re.findall(r"^\s*parameter \\(\w+) (.*)$", "\n".join(block), re.M))
            conns = dict(re.findall(r"^\s*connect \\(\w+) (.*)$", "\n".join(block), re.M))
            if params.get("WR_PORTS") != "0":
                out.extend(block)
                i += 1
                continue
            while out and out[-1].strip().startswith("attribute "):
                out.pop()  # the cell's attributes go with it
            ports = int(params["RD_PORTS"])
            abits, width = int(params["ABITS"]) * ports, int(params["WIDTH"]) * ports
            name = f"\\mutation_rom{k}"
            extra_wires.append(f"  wire width {abits} output {{port}} {name}_addr")
            extra_wires.append(f"  wire width {width} input {{port}} {name}_data")
            out.append(f"  connect {name}_addr {conns['RD_ADDR']}")
            fixed = _constant_reads("\n".join(block), params, conns, widths)
            if fixed:
                step = int(params["WIDTH"])
                parts = [
                    fixed.get(p, f"{name}_data [{(p + 1) * step - 1}:{p * step}]")
                    for p in reversed(range(ports))
                ]
                out.append(f"  connect {conns['RD_DATA']} {{ {' '.join(parts)} }}")
            else:
                out.append(f"  connect {conns['RD_DATA']} {name}_data")
            if not re.fullmatch(r"\d+'1+", conns["RD_EN"]):
                extra_wires.append(f"  wire width {ports} output {{port}} {name}_en")
                out.append(f"  connect {name}_en {conns['RD_EN']}")
            k += 1
        else:
            out.append(line)
        i += 1
    if not extra_wires:
        return il
    text = "\n".join(out)
    port = max(int(n) for n in re.findall(r"^\s*wire .*(?:input|output) (\d+) ", text, re.M))
    numbered = []
    for w in extra_wires:
        port += 1
        numbered.append(w.format(port=port))
    head, rest = text.split("\nmodule ", 1)
    first, body = rest.split("\n", 1)
    return f"{head}\nmodule {first}\n" + "\n".join(numbered) + "\n" + body


def module_parts(il: str, top: str) -> tuple[str, str, str]:
    """The RTLIL ``il`` split around module ``top``: what comes before its ``module`` line, its
    body, and what comes after its ``end``."""
    head, rest = il.split(f"\nmodule \\{top}\n", 1)
    body, tail = rest.split("\nend\n", 1)
    return head, body, tail


def add_ports(text: str, decls: list[str]) -> str:
    """The RTLIL ``text`` (one module) with the wires ``decls`` (each with ``{port}`` where its
    port number goes) declared at its top, numbered after its last port."""
    port = max(int(n) for n in re.findall(r"^\s*wire .*(?:input|output) (\d+) ", text, re.M))
    numbered = [d.format(port=port + 1 + k) for k, d in enumerate(decls)]
    head, rest = text.split("\nmodule ", 1)
    first, body = rest.split("\n", 1)
    return f"{head}\nmodule {first}\n" + "\n".join(numbered) + "\n" + body


# The prefix of the ports that stand for a cut product (``cut_products``)
PRODUCT = "mutation_mul"


def cut_products(il: str) -> str:
    """The RTLIL ``il`` with every multiplier (a ``$mul`` cell of two signals) cut out, as
    ``cut_roms`` cuts a ROM: its operands ``{A, B}`` become an output port
    ``mutation_mul<k>_in``, its product an input port ``mutation_mul<k>_y`` (k in the order
    of the cells' names, the same in the original and in a mutant).  The from-reset miter
    (``miter_verilog``) gives both copies the same product wherever their operands agree
    and any value where they do not: every behaviour of the two real designs is still one of
    the miter's (sound), and the proof never multiplies.  What it cannot show is an
    equivalence that needs the product's value."""
    # each cell with the attributes before it, which go with it
    found = r"^((?:[ \t]*attribute [^\n]*\n)*[ \t]*cell \$mul (\S+)\n.*?^\s*end)$"
    cells = sorted(
        (c for c in re.findall(found, il, re.M | re.S) if not _by_constant(c[0])),
        key=lambda c: c[1],
    )
    if not cells:
        return il
    decls = []
    for k, (block, _name) in enumerate(cells):
        params = dict(re.findall(r"^\s*parameter \\(\w+) (\S+)$", block, re.M))
        conns = dict(re.findall(r"^\s*connect \\(\w+) (.*)$", block, re.M))
        a, b, y = (int(params[f"{x}_WIDTH"]) for x in "ABY")
        name = f"\\{PRODUCT}{k}"
        decls += [
            f"  wire width {a + b} output {{port}} {name}_in",
            f"  wire width {y} input {{port}} {name}_y",
        ]
        il = il.replace(
            block,
            f"  connect {name}_in {{ {conns['A']} {conns['B']} }}\n  connect {conns['Y']} {name}_y",
            1,
        )
    return add_ports(il, decls)


# The prefix of the output ports that show an internal wire to an invariant (``probed``)
PROBE = "mutation_probe_"
# A wire of an invariant: ``gold:name`` or ``gate:name`` (a named wire of the flattened design,
# dots for its hierarchy, a generate block's index before a dot: g_increment[2].u_increment.q),
# a Verilog bit select may follow; or, as Verilog escapes a name, ``gold:\name`` up to the
# next white space, for a name that ends in an index (a memory's word once mapped to
# registers: ``gold:\u_fifo.mem[3] ``)
_INVARIANT_WIRE = re.compile(
    r"\b(gold|gate):(?:\\(\S+)(?=\s)|([A-Za-z_]\w*(?:(?:\[\d+\])?\.[A-Za-z_]\w*)*))"
)


def probe_name(wire: str) -> str:
    """The port ``probed`` gives the wire ``wire`` (a plain identifier: its dots made double
    underscores, a generate index ``[i]`` made ``_i_``)."""
    return PROBE + re.sub(r"\[(\d+)\]", r"_\1_", wire).replace(".", "__")


def invariant_wires(invariants: tuple[str, ...]) -> list[str]:
    """The wires the invariants read (``gold:name``, ``gate:name``), each once."""
    return list(
        dict.fromkeys(e or w for inv in invariants for _, e, w in _INVARIANT_WIRE.findall(inv))
    )


def invariant_verilog(invariant: str) -> str:
    """The invariant with each ``gold:name`` / ``gate:name`` made the miter's wire of that
    copy's probe (``gold_mutation_probe_name``)."""
    return _INVARIANT_WIRE.sub(
        lambda m: f"{m.group(1)}_{probe_name(m.group(2) or m.group(3))}", invariant
    )


def probed(il: str, top: str, wires: list[str]) -> str:
    """The RTLIL ``il`` with an output port ``probe_name(w)`` showing each wire ``w`` of
    ``wires`` (as the flip-flop's readers see it: after ``shared_power_up``, the power-up state
    in the first cycle)."""
    head, body, tail = module_parts(il, top)
    widths = {
        name: int(width or 1)
        for width, name in re.findall(
            r"^\s*wire (?:width (\d+) )?(?:(?:offset \d+|upto|signed) )*\\(\S+)$", body, re.M
        )
    }
    decls, conns = [], []
    for w in wires:
        if w not in widths:
            raise ValueError(f"an invariant reads {w}, which {top} has no wire of")
        decls.append(f"  wire width {widths[w]} output {{port}} \\{probe_name(w)}")
        conns.append(f"  connect \\{probe_name(w)} \\{w}")
    text = f"{head}\nmodule \\{top}\n{body}\n" + "\n".join(conns) + "\nend\n" + tail
    return add_ports(text, decls)


def _by_constant(block: str) -> bool:
    """The ``$mul`` cell ``block`` has a constant operand (a scaled index, as a banked ROM's
    word select: wires and a shift, no multiplier; cut, its product would be any value, and
    a select out of range reads x, a different free value in each copy)."""
    conns = dict(re.findall(r"^\s*connect \\(\w+) (.*)$", block, re.M))
    return any(re.fullmatch(r"\d+'[01]+", conns[x].strip()) for x in "AB")


def product_cuts(il: str) -> list[tuple[int, int]]:
    """(operand bits, product bits) of each multiplier ``cut_products`` cuts out of the RTLIL
    ``il``, in its order (product k: ``mutation_mul<k>_*``)."""
    cells = sorted(re.findall(r"^\s*cell \$mul (\S+)\n(.*?)^\s*end$", il, re.M | re.S))
    found = []
    for _name, block in cells:
        if _by_constant(block):
            continue
        params = dict(re.findall(r"^\s*parameter \\(\w+) (\S+)$", block, re.M))
        found.append((int(params["A_WIDTH"]) + int(params["B_WIDTH"]), int(params["Y_WIDTH"])))
    return found


def roms_filled(il: str) -> str:
    """The RTLIL ``il`` with each ROM (a ``$mem_v2`` without write ports) that holds fewer
    words than its address reaches (a table of 2000 words on 11 address bits) given the rest
    as 0 words, so that mapped to logic it reads a word at every address, not ``x``: for a
    proof in which the table is read only at the addresses the unit gives it."""

    def filled(m: re.Match[str]) -> str:
        block = m.group(0)
        params = dict(re.findall(r"^\s*parameter \\(\w+) (\S+)$", block, re.M))
        if params.get("WR_PORTS") != "0" or params.get("OFFSET", "0") != "0":
            return block
        width, size, words = int(params["WIDTH"]), int(params["SIZE"]), 1 << int(params["ABITS"])
        init = re.search(r"^(\s*parameter \\INIT )(\d+)'([01x]+)$", block, re.M)
        if size >= words or init is None or int(init.group(2)) != width * size:
            return block
        bits = "0" * (width * (words - size)) + init.group(3)
        block = block.replace(init.group(0), f"{init.group(1)}{len(bits)}'{bits}", 1)
        return re.sub(r"^(\s*parameter \\SIZE )\d+$", rf"\g<1>{words}", block, count=1, flags=re.M)

    return re.sub(r"^\s*cell \$mem_v2 \S+\n.*?^\s*end$", filled, il, flags=re.M | re.S)


def observed(il: str, top: str, wires: list[str], condition: str) -> str:
    """The RTLIL ``il`` with a wire ``<w>__while_<condition>`` = ``condition ? w : 0`` for
    each wire ``w`` of ``wires``: what ``w`` shows while ``condition`` holds."""
    widths = dict(
        (name, int(width or 1))
        for width, name in re.findall(r"^\s*wire (?:width (\d+) )?(?:\w+ \d+ )?(\\\S+)$", il, re.M)
    )
    decls, cells = [], []
    for k, w in enumerate(wires):
        name = f"\\{w}"
        if name not in widths:
            continue
        n = widths[name]
        obs = f"{name}__while_{condition}"
        decls.append(f"  wire width {n} {obs}")
        cells += [
            f"  cell $mux $mutation_observe{k}",
            f"    parameter \\WIDTH {n}",
            f"    connect \\A {n}'{'0' * n}",
            f"    connect \\B {name}",
            f"    connect \\S \\{condition}",
            f"    connect \\Y {obs}",
            "  end",
        ]
    head, rest = il.split(f"\nmodule \\{top}\n", 1)
    body, tail = rest.rsplit("\nend\n", 1)
    return (
        f"{head}\nmodule \\{top}\n" + "\n".join(decls) + "\n" + body + "\n"
        + "\n".join(cells) + "\nend\n" + tail
    )  # fmt: skip


def rom_reads(il: str) -> list[tuple[int, int, int, bool]]:
    """(read ports, address bits, data bits, asynchronous) of each ROM ``cut_roms`` cuts out
    of the RTLIL ``il``, in its order (ROM k: ``mutation_rom<k>_*``)."""
    found = []
    for block in re.findall(r"^\s*cell \$mem_v2 \S+\n(.*?)^\s*end$", il, re.M | re.S):
        params = dict(re.findall(r"^\s*parameter \\(\w+) (.*)$", block, re.M))
        if params.get("WR_PORTS") != "0":
            continue
        asynchronous = re.fullmatch(r"\d+'0+", params["RD_CLK_ENABLE"]) is not None
        found.append((int(params["RD_PORTS"]), int(params["ABITS"]), int(params["WIDTH"]),
                      asynchronous))  # fmt: skip
    return found
