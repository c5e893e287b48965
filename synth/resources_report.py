#!/usr/bin/env python3
"""Turns Yosys `stat` outputs of the core at several widths into a markdown table.

    resources_report.py OUT.md CONFIG TOOLS COMMAND DIR...

Each DIR holds `stat.txt` (Yosys stat after synth_ecp5), `time` (the synthesis run time)
and its width in its name (`..._n<W>`). Besides the cell counts, the table gives the
logic share of an LFE5U-85F: each TRELLIS_COMB slot holds one LUT4, a CCU2C takes two,
and the 85F has 83,640 of them and 83,640 flip-flops. The per-processor cost is the slope
between the smallest and the largest width; the largest N that fits is extrapolated from
it (stated as such).
"""
import re
import sys

CELLS = ["LUT4", "CCU2C", "PFUMX", "L6MUX21", "TRELLIS_FF", "DP16KD", "MULT18X18D", "TRELLIS_DPR16X4"]
COMB_85F = 83640
FF_85F = 83640


def parse(d):
    text = open(f"{d}/stat.txt").read()
    # The last "=== design hierarchy ===" or the top module's block holds the totals; with a
    # flattened synth_ecp5 there is one module, so the last count of each cell is the total.
    counts = {}
    for c in CELLS:
        m = re.findall(rf"^\s+{c}\s+(\d+)\s*$", text, re.M)
        counts[c] = int(m[-1]) if m else 0
    w = int(re.search(r"_n(\d+)$", d.rstrip("/")).group(1))
    t = open(f"{d}/time").read().strip()
    return w, counts, t


def main():
    out, cfg, tools, command, dirs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
    rows = sorted(parse(d) for d in dirs)
    lines = [
        f"# ECP5 resources of pixelproc_top per array width ({cfg})",
        "",
        "Written by `synth/resources_ecp5.sh` (see `docs/fpga.md`); do not edit by hand.",
        "Synthesis only (Yosys `synth_ecp5`, flattened, no place and route): packing into",
        "slices and routing are not included; the logic share counts one TRELLIS_COMB slot per",
        "LUT4 and two per CCU2C against the LFE5U-85F's 83,640 (and 83,640 flip-flops).",
        "",
        f"| item | value |",
        "|---|---|",
        f"| tools | {tools} |",
        f"| command | `{command}` |",
        "",
        "| N | LUT4 | CCU2C | PFUMX | L6MUX21 | FF | DP16KD | MULT18X18D | DPR16X4 | logic of 85F | FF of 85F | synthesis time |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for w, c, t in rows:
        comb = c["LUT4"] + 2 * c["CCU2C"]
        lines.append(
            f"| {w} | {c['LUT4']:,} | {c['CCU2C']:,} | {c['PFUMX']:,} | {c['L6MUX21']:,} | {c['TRELLIS_FF']:,} | "
            f"{c['DP16KD']} | {c['MULT18X18D']} | {c['TRELLIS_DPR16X4']} | {100 * comb / COMB_85F:.1f} % | "
            f"{100 * c['TRELLIS_FF'] / FF_85F:.1f} % | {t} |"
        )
    if len(rows) >= 2 and rows[-1][0] > rows[0][0]:
        (w0, c0, _), (w1, c1, _) = rows[0], rows[-1]
        dn = w1 - w0
        per = {k: (c1[k] - c0[k]) / dn for k in CELLS}
        comb_per = per["LUT4"] + 2 * per["CCU2C"]
        fixed_comb = (c0["LUT4"] + 2 * c0["CCU2C"]) - comb_per * w0
        fixed_ff = c0["TRELLIS_FF"] - per["TRELLIS_FF"] * w0
        n_comb = int((COMB_85F - fixed_comb) // comb_per)
        n_ff = int((FF_85F - fixed_ff) // per["TRELLIS_FF"])
        lines += [
            "",
            f"Per processor (slope from N = {w0} to N = {w1}): {per['LUT4']:.1f} LUT4, {per['CCU2C']:.1f} CCU2C, "
            f"{per['TRELLIS_FF']:.1f} FF ({comb_per:.1f} TRELLIS_COMB slots). Fixed part (the entry pipeline, "
            f"FIFOs, controller and shading step): {fixed_comb:,.0f} slots, {fixed_ff:,.0f} FF.",
            "",
            f"Largest N on an LFE5U-85F, **extrapolated** from that slope with every slot used (a "
            f"placer needs headroom; nothing this size was placed): {min(n_comb, n_ff)} by "
            f"{'logic' if n_comb <= n_ff else 'flip-flops'} (logic alone: {n_comb}, flip-flops alone: {n_ff}).",
        ]
    open(out, "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
