#!/usr/bin/env python3
"""Turns Yosys `stat` outputs of the core at several widths into a markdown table.

    resources_report.py OUT.md CONFIG TOOLS COMMAND DIR...

Each DIR holds `stat.txt` (Yosys stat after synth_ecp5), `time` (the synthesis run time)
and its width in its name (`..._n<W>`), and where nextpnr-ecp5 packed it `pack.log` and
`pack_time`. Besides the cell counts, the table gives the logic share of an LFE5U-85F
estimated from synthesis (each TRELLIS_COMB slot holds one LUT4, a CCU2C takes two; the
85F has 83,640 of them and 83,640 flip-flops) and, where packed, nextpnr's own count of
TRELLIS_COMB slots (which also holds the wide multiplexers and the LUT RAM's slots). The
per-processor cost is the slope between the smallest and the largest width; the largest
N that fits is the largest that packed (measured) and, from the slope, extrapolated
(stated as such).
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
    return w, counts, t, packed(d)


def packed(d):
    """nextpnr's packed counts {cell: (used, available)} and run time, or (None, error,
    time) when packing failed, or None when it was not run."""
    try:
        log = open(f"{d}/pack.log").read()
        t = open(f"{d}/pack_time").read().strip()
    except OSError:
        return None
    used = {
        m.group(1): (int(m.group(2)), int(m.group(3)))
        for m in re.finditer(r"^Info:\s+(TRELLIS_COMB|TRELLIS_FF|TRELLIS_RAMW):\s+(\d+)/\s*(\d+)", log, re.M)
    }
    err = re.search(r"^ERROR: (.*)$", log, re.M)
    if err or "TRELLIS_COMB" not in used:
        return (None, err.group(1).strip() if err else "no utilisation in the log", t)
    # `--pack-only` reports an over-full device and finishes; placement would fail.
    over = [f"{c} {u:,} of {a:,}" for c, (u, a) in sorted(used.items()) if u > a]
    if over:
        return (None, "needs " + ", ".join(over), t)
    return (used, None, t)


def pack_cells(p):
    if p is None:
        return "not packed", "", ""
    used, err, t = p
    if used is None:
        return f"**does not fit**: {err}", "", t
    cu, ca = used["TRELLIS_COMB"]
    fu, fa = used["TRELLIS_FF"]
    return f"{cu:,} ({100 * cu / ca:.1f} %)", f"{fu:,} ({100 * fu / fa:.1f} %)", t


def main():
    out, cfg, tools, command, dirs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
    rows = sorted(parse(d) for d in dirs)
    lines = [
        f"# ECP5 resources of pixelproc_top per array width ({cfg})",
        "",
        "Written by `synth/resources_ecp5.sh` (see `docs/fpga.md`); do not edit by hand.",
        "Yosys `synth_ecp5` (flattened), then nextpnr-ecp5's packing into the LFE5U-85F's",
        "slices (`--pack-only`, out of context: no placement or routing). \"logic of 85F\" is",
        "the synthesis estimate (one TRELLIS_COMB slot per LUT4, two per CCU2C, against",
        "83,640); \"packed COMB\" and \"packed FF\" are nextpnr's counts after packing, which",
        "also hold the wide multiplexers and the LUT RAM. A width that packs fits the device's",
        "cells; whether it places and routes (and at what clock) is the flow reports' matter.",
        "",
        f"| item | value |",
        "|---|---|",
        f"| tools | {tools} |",
        f"| command | `{command}` |",
        "",
        "| N | LUT4 | CCU2C | PFUMX | L6MUX21 | FF | DP16KD | MULT18X18D | DPR16X4 | logic of 85F | FF of 85F | packed COMB | packed FF | synthesis time | packing time |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for w, c, t, p in rows:
        comb = c["LUT4"] + 2 * c["CCU2C"]
        pc, pf, pt = pack_cells(p)
        lines.append(
            f"| {w} | {c['LUT4']:,} | {c['CCU2C']:,} | {c['PFUMX']:,} | {c['L6MUX21']:,} | {c['TRELLIS_FF']:,} | "
            f"{c['DP16KD']} | {c['MULT18X18D']} | {c['TRELLIS_DPR16X4']} | {100 * comb / COMB_85F:.1f} % | "
            f"{100 * c['TRELLIS_FF'] / FF_85F:.1f} % | {pc} | {pf} | {t} | {pt} |"
        )
    fits = [w for w, _, _, p in rows if p is not None and p[0] is not None]
    fails = [w for w, _, _, p in rows if p is not None and p[0] is None]
    if fits or fails:
        lines += [""]
        if fits:
            lines.append(f"Largest N measured that packs into an LFE5U-85F: **{max(fits)}**"
                         + (f"; the smallest measured that does not: {min(fails)}." if fails else "."))
        else:
            lines.append(f"No width measured packs; the smallest measured that does not: {min(fails)}.")
    if len(rows) >= 2 and rows[-1][0] > rows[0][0]:
        (w0, c0, _, _), (w1, c1, _, _) = rows[0], rows[-1]
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
            f"{per['TRELLIS_FF']:.1f} FF ({comb_per:.1f} TRELLIS_COMB slots estimated from synthesis). Fixed part (the entry pipeline, "
            f"FIFOs, controller and shading step): {fixed_comb:,.0f} slots, {fixed_ff:,.0f} FF.",
        ]
        packed_rows = [(w, p[0]) for w, _, _, p in rows if p is not None and p[0] is not None]
        if len(packed_rows) >= 2 and packed_rows[-1][0] > packed_rows[0][0]:
            (pw0, u0), (pw1, u1) = packed_rows[0], packed_rows[-1]
            pc = (u1["TRELLIS_COMB"][0] - u0["TRELLIS_COMB"][0]) / (pw1 - pw0)
            pfix = u0["TRELLIS_COMB"][0] - pc * pw0
            n_packed = int((u0["TRELLIS_COMB"][1] - pfix) // pc)
            lines += [
                "",
                f"Packed, each processor takes {pc:.1f} TRELLIS_COMB slots (slope from N = {pw0} to N = {pw1}; "
                f"the synthesis estimate leaves out the wide multiplexers' slots). Largest N on an LFE5U-85F "
                f"**extrapolated** from that slope with every slot used: {n_packed} (a placer needs headroom; "
                f"nothing this size was placed). From the synthesis estimate alone it would be "
                f"{min(n_comb, n_ff)}.",
            ]
        else:
            lines += [
                "",
                f"Largest N on an LFE5U-85F, **extrapolated** from that slope with every slot used (a "
                f"placer needs headroom; nothing this size was placed): {min(n_comb, n_ff)} by "
                f"{'logic' if n_comb <= n_ff else 'flip-flops'} (logic alone: {n_comb}, flip-flops alone: {n_ff}).",
            ]
    open(out, "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
