"""Command line: ``python -m model <command>`` (also installed as ``shading``).

Commands:
  demo            the main job (for now: the divider's Table 1, its trade table, one RTL run)
  roms            regenerate every ROM image under rtl/rom/ from the model
  divider-table   the article's Table 1, recomputed from the formula (markdown)
  divider-trade   worst error and cycles for N = 4..20 over k = 1..2047 (markdown)
"""

from __future__ import annotations

import argparse
import sys

from model import divider, specular


def divider_table1(recip_bits: int = 8, dividend: int = 255) -> list[dict]:
    """Table 1 of the article, recomputed: terms, error and relative error for k = 2..16."""
    cfg = divider.DividerConfig(a_width=9, k_width=5, recip_bits=recip_bits)
    rows = []
    for k in range(2, 17):
        approx = divider.divide(dividend, k, cfg) / 2.0**recip_bits
        exact = dividend / k
        rows.append(
            {
                "k": k,
                "terms": "+".join(f"1/{2**j}" for j in divider.reciprocal_terms(k, recip_bits)),
                "error": approx - exact,
                "relative_pct": 100.0 * (approx - exact) / exact,
            }
        )
    return rows


def format_table1() -> str:
    rows = divider_table1()
    lines = ["| k | terms | error | relative % |", "|---|---|---|---|"]
    lines += [
        f"| {r['k']} | {r['terms']} | {r['error']:+.4f} | {r['relative_pct']:+.2f} |" for r in rows
    ]
    worst = max(rows, key=lambda r: abs(r["error"]))
    mean_rel = sum(abs(r["relative_pct"]) for r in rows) / len(rows)
    lines.append("")
    lines.append(
        f"max |error| {abs(worst['error']):.4f} at k = {worst['k']}; "
        f"mean |relative error| over k = 2..16: {mean_rel:.2f} %"
    )
    return "\n".join(lines)


def format_trade(k_max: int = 2047, bits: range = range(4, 21)) -> str:
    lines = [
        f"| N | worst abs error (255/k) | at k | worst rel error | at k | k with r = 0 "
        f"| cycles max | cycles mean | (k = 1..{k_max}) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for n in bits:
        r = divider.trade_row(n, k_max)
        lines.append(
            f"| {n} | {r.worst_abs_error:.4f} | {r.worst_abs_k} | {100 * r.worst_rel_error:.3f} % "
            f"| {r.worst_rel_k} | {r.useless_k} | {r.cycles_max} | {r.cycles_mean:.2f} | |"
        )
    lines.append("")
    lines.append(
        f"exact restoring divider, default widths: {divider.cycles_exact()} cycles for every k"
    )
    return "\n".join(lines)


def write_roms() -> None:
    for path in divider.write_roms() + specular.write_roms():
        print(f"wrote {path}")


def demo() -> int:
    print("== Shift-add divider: the article's Table 1 recomputed (N = 8, dividend 255) ==")
    print(format_table1())
    cfg6 = divider.DividerConfig(a_width=9, k_width=5, recip_bits=6)
    approx = divider.divide(255, 7, cfg6) / 64
    print(
        f"\nworked example, k = 7, N = 6: 1/7 ~ "
        f"{' + '.join(f'1/{2**j}' for j in divider.reciprocal_terms(7, 6))}: "
        f"255/7 = {255 / 7:.4f} vs {approx:.4f} (error {255 / 7 - approx:.4f}, "
        f"{100 * (255 / 7 - approx) / (255 / 7):.2f} %)"
    )
    print("\n== The trade: reciprocal bits N against error and cycles ==")
    print(format_trade())
    print("\n== One RTL run: divider_shift under Icarus, every result against the model ==")
    try:
        from sim.runner import hdl_parameters, run_bench
    except ImportError as exc:  # the dev extra (cocotb) is not installed
        print(f"not run: {exc}; `make demo` installs it")
        return 1
    cfg = divider.ARTICLE
    params = hdl_parameters(cfg, ROM_FILE=divider.rom_path(cfg))
    records = run_bench(
        "divider_shift", "sim.tb_divider", "divider_demo", params, cfg, testcase="test_extremes"
    )
    compared = sum(r["compared"] for r in records)
    errors = sum(r["errors"] for r in records)
    print(
        f"divider_shift (N = 8): {compared} quotients compared with the model, {errors} mismatches"
    )
    return 0 if errors == 0 else 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="shading", description=__doc__.split("\n")[0])
    parser.add_argument("command", choices=["demo", "roms", "divider-table", "divider-trade"])
    args = parser.parse_args(argv)
    if args.command == "demo":
        return demo()
    if args.command == "roms":
        write_roms()
    elif args.command == "divider-table":
        print(format_table1())
    elif args.command == "divider-trade":
        print(format_trade())
    return 0


if __name__ == "__main__":
    sys.exit(main())
