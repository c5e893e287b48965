#!/usr/bin/env python3
"""Turns a nextpnr --report JSON (and the run's facts) into the markdown results file.

    pnr_report.py REPORT.json OUT.md TITLE KEY=VALUE...

KEY=VALUE pairs (device, config, seed, synth_s, pnr_s, tools, command, note) become the
table at the top. Then: Fmax per clock (achieved vs constraint), utilisation (every BEL
type used), and each clock's critical path in words: where it starts and ends, its logic
levels, the logic and routing share, and the nets it goes through.
"""
import json
import re
import sys


def clean(name):
    """A readable net or cell name: the Verilog hierarchy, no Yosys suffixes."""
    # Cut the suffixes Yosys and nextpnr append to mapped cells and their nets
    # (`_SB_LUT4_O_26_I3_…`, `_LUT4_Z_4_B`, `_CCU2C_COUT…`, `_DFFLC`), keeping a bus index.
    idx = re.search(r"(\[\d+\])$", name)
    cut = re.split(r"_(SB_|LUT4|CCU2C|L6MUX|PFUMX|DFFLC|SLICE|TRELLIS|COMB|DOB|DOA|RDATA|RAM$)", name)[0]
    name = cut + (idx.group(1) if idx and not cut.endswith(idx.group(1)) else "")
    name = re.sub(r"\$(abc|auto|techmap|flatten)\$[^ ]*", "", name)
    return name.strip(".$ ") or "(internal)"


def path_words(cp):
    segs = cp.get("path", [])
    logic = sum(s["delay"] for s in segs if s["type"] in ("logic", "clk-to-q", "setup"))
    route = sum(s["delay"] for s in segs if s["type"] == "routing")
    levels = sum(1 for s in segs if s["type"] == "logic")
    nets = []
    for s in segs:
        if s["type"] == "routing" and s.get("net"):
            n = clean(s["net"])
            if not nets or nets[-1] != n:
                nets.append(n)
    start = clean(segs[0]["from"]["cell"]) if segs else "?"
    end = clean(segs[-1]["to"]["cell"]) if segs else "?"
    total = logic + route
    shown = nets if len(nets) <= 12 else nets[:6] + ["…"] + nets[-5:]
    return (
        f"from `{start}` to `{end}`: {total:.2f} ns, {levels} logic levels; "
        f"{logic:.2f} ns in cells (clock-to-out, LUTs/carry, setup) and {route:.2f} ns "
        f"routing ({100 * route / total if total else 0:.0f} %). Nets on the way: "
        + " → ".join(f"`{n}`" for n in shown)
    )


def main():
    rep = json.load(open(sys.argv[1]))
    out, title = sys.argv[2], sys.argv[3]
    facts = dict(a.split("=", 1) for a in sys.argv[4:])
    lines = [f"# {title}", "", "Written by the flow script (see `docs/fpga.md`); do not edit by hand.", ""]
    lines += ["| item | value |", "|---|---|"]
    for k, v in facts.items():
        lines.append(f"| {k} | {v} |")
    lines += ["", "## Fmax", "", "| clock | achieved | constraint | met |", "|---|---:|---:|---|"]
    for clk, f in rep.get("fmax", {}).items():
        ach, con = f.get("achieved", 0), f.get("constraint", 0)
        lines.append(f"| `{clk}` | {ach:.2f} MHz | {con:.2f} MHz | {'yes' if ach >= con else 'no'} |")
    lines += ["", "## Utilisation", "", "| resource | used | available | % |", "|---|---:|---:|---:|"]
    for bel, u in sorted(rep.get("utilization", {}).items()):
        if u.get("used", 0):
            lines.append(f"| {bel} | {u['used']} | {u['available']} | {100 * u['used'] / max(u['available'], 1):.1f} |")
    lines += ["", "## Critical path", ""]
    for cp in rep.get("critical_paths", []):
        lines.append(f"- clock `{cp.get('from', '?')}` → `{cp.get('to', '?')}`: {path_words(cp)}")
    open(out, "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
