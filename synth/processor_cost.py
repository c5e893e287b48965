#!/usr/bin/env python3
"""Splits a synthesised core's per-processor cost into what each part of a processor does.

    processor_cost.py TOP.json WIDTH OUT.md COMMAND TOOLS

TOP.json is Yosys's `synth_ecp5 -json` netlist of `pixelproc_top` (flattened) with WIDTH
processors. Every flip-flop of processor p carries a net name `array.procs$p.<register>...`
(the names of rtl/src/pixel_processor.rs and its parity block), and falls in one part:

- token: the token register (`tok_*`: header, Z, dZ, three intensities, three dI, the
  `<=` flag) and the adders and range steps that make the next processor's token;
- decision: stage B (`b_*`): the registered depth compares and selects, the decoded
  command flags, the depth, colour and class about to be written;
- state: ZB, RGB, NCLASS, the shade register and its WON flag, stage C (`zb_r`, `rgb_r`,
  `nclass_r`, `sh_r`, `won_r`, `w_c`, `rgb_c`, `ncl_c`);
- shadow flags: the span-parity block (DSF, FSF, COUNT, MASK);
- readout: the line capture and the select (`cap_r`, `rdsel_r`).

A combinational cell (LUT4, CCU2C, PFUMX, L6MUX21) belongs to the flip-flops its outputs
reach through other combinational cells: to one part when they all are that part's,
shared equally otherwise (a LUT feeding a decision and a state register counts half to
each). Cells reaching no processor's flip-flop are the array's readout gather (those
reaching its readout group registers `rd_g`, from the processors' readout words), shown
per processor (divided by WIDTH), or the fixed part. The report's processor is an interior
one (the mean of processors 1 .. WIDTH-2; WIDTH >= 3). A flip-flop Yosys merged from
registers of two processors that hold the same value (the token's attribute and stage B
of the processor before) counts once, to the earlier processor's register. The split is
Yosys's netlist before nextpnr's packing.
"""
import collections
import json
import re
import sys

PARTS = ["token", "decision", "state", "shadow flags", "readout"]
COMB = {"LUT4": "LUT4", "CCU2C": "CCU2C", "PFUMX": "MUX", "L6MUX21": "MUX"}
KINDS = ["LUT4", "CCU2C", "MUX", "FF"]
STATE = {"zb_r", "rgb_r", "nclass_r", "sh_r", "won_r", "w_c", "rgb_c", "ncl_c"}
PROC = re.compile(r"^array\.procs\$(\d+)\.([A-Za-z_][A-Za-z0-9_]*)[.$]")
# A register of the array's readout gather (its group and line registers), not of a processor.
GATHER = re.compile(r"^array[.$]rd_g\$")


def part_of(reg):
    """The part of a processor register (its name within the processor), or None."""
    if reg.startswith("tok_"):
        return "token"
    if reg.startswith("b_"):
        return "decision"
    if reg in STATE:
        return "state"
    if reg == "parity":
        return "shadow flags"
    if reg in ("cap_r", "rdsel_r"):
        return "readout"
    return None


def main(path, width, out, command, tools):
    if not width.isdigit() or int(width) < 3:
        raise SystemExit(f"processor_cost.py: WIDTH must be an integer of at least 3, got '{width}'")
    width = int(width)
    try:
        m = json.load(open(path))["modules"]["pixelproc_top"]
    except (OSError, ValueError, KeyError) as e:
        raise SystemExit(f"processor_cost.py: {path} is not a Yosys JSON netlist of pixelproc_top ({e})")
    names = collections.defaultdict(list)
    for n, v in sorted(m["netnames"].items()):
        for b in v["bits"]:
            if isinstance(b, int):
                names[b].append(n)
    # The sinks of each net bit: (cell, port).
    sinks = collections.defaultdict(list)
    for c, v in m["cells"].items():
        for p, bits in v["connections"].items():
            if v["port_directions"].get(p) == "input":
                for b in bits:
                    if isinstance(b, int):
                        sinks[b].append(c)
    # Each flip-flop's owner: ("proc", index, part) or ("gather",) or ("fixed",).
    owner = {}
    unclassified = collections.Counter()
    for c, v in m["cells"].items():
        if v["type"] != "TRELLIS_FF":
            continue
        q = v["connections"]["Q"][0]
        own = None
        # A register's own output (`reg.q`) names it; another name of the same net (a
        # sub-block's input it feeds) only when there is none. A name of a register's
        # input (`reg.d`: the flip-flop feeds that register, as the array's entry stage
        # feeds processor 0's token) never does.
        mine = [n for n in names.get(q, []) if PROC.match(n) and not re.search(r"[.$]d$", n)]
        mine.sort(key=lambda n: (not re.search(r"[.$]q$", n), n))
        if mine:
            k, reg = PROC.match(mine[0]).groups()
            part = part_of(reg)
            if part is None:
                unclassified[reg] += 1
                part = "unclassified"
            own = ("proc", int(k), part)
        if own is None:
            own = ("gather",) if any(GATHER.match(n) for n in names.get(q, [])) else ("fixed",)
        owner[c] = own
    found = {o[1] for o in owner.values() if o[0] == "proc"}
    if found != set(range(width)):
        raise SystemExit(f"processor_cost.py: the netlist has processors {min(found, default=0)}.."
                         f"{max(found, default=-1)} ({len(found)}), not the {width} given")
    # Forward reach of every combinational cell to flip-flops (memoised over the DAG).
    reach = {}

    def reached(c):
        if c in reach:
            return reach[c]
        reach[c] = frozenset()  # a combinational loop would stop here
        got = set()
        v = m["cells"][c]
        for p, bits in v["connections"].items():
            if v["port_directions"].get(p) != "output":
                continue
            for b in bits:
                if not isinstance(b, int):
                    continue
                for s in sinks[b]:
                    t = m["cells"][s]["type"]
                    if t == "TRELLIS_FF":
                        got.add(owner[s])
                    elif t in COMB:
                        got |= reached(s)
                    else:
                        got.add(("fixed",))
        reach[c] = frozenset(got)
        return reach[c]

    sys.setrecursionlimit(100000)
    # Cells per (processor, part), and per array-level owner ("gather", "fixed").
    per = collections.defaultdict(collections.Counter)
    for c, v in m["cells"].items():
        t = v["type"]
        if t == "TRELLIS_FF":
            o = owner[c]
            per[o[1:] if o[0] == "proc" else o[0]]["FF"] += 1
        elif t in COMB:
            r = reached(c)
            procs = [o[1:] for o in r if o[0] == "proc"]
            if procs:
                for p in procs:
                    per[p][COMB[t]] += 1 / len(procs)
            elif ("gather",) in r:
                per["gather"][COMB[t]] += 1
            else:
                per["fixed"][COMB[t]] += 1
    total = collections.Counter()
    for c, v in m["cells"].items():
        k = "FF" if v["type"] == "TRELLIS_FF" else COMB.get(v["type"])
        if k:
            total[k] += 1
    # An interior processor (1 .. N-2): processor 0's token comes from the entry stage, and
    # the last one's token goes nowhere (synthesis removes what only it would feed).
    interior = range(1, width - 1)
    rows = PARTS + (["unclassified"] if unclassified else [])
    cost = {p: {k: sum(per[(i, p)][k] for i in interior) / len(interior) for k in KINDS} for p in rows}
    cost["gather"] = {k: per["gather"][k] / width for k in KINDS}
    rows.append("gather")
    with open(out, "w") as f:
        f.write(f"# ECP5 cost of one pixel processor by part (N = {width}, shadows)\n\n")
        f.write("Written by `synth/processor_cost.sh` (see `docs/fpga.md`); do not edit by hand.\n"
                "Yosys `synth_ecp5` (flattened) of the core; a processor's flip-flops fall in a part by\n"
                "their register's name, its LUT4, CCU2C and wide multiplexers by the flip-flops they\n"
                "feed (split equally where they feed several parts). The readout gather is the\n"
                "array's OR of the processors' readout words into its group registers. Before\n"
                "nextpnr's packing: a slot here is one LUT4, and a CCU2C takes two.\n\n")
        f.write("| item | value |\n|---|---|\n")
        f.write(f"| tools | {tools} |\n| command | `{command}` |\n\n")
        f.write(f"One interior processor (the mean of processors {interior.start} to {interior.stop - 1}; "
                "processor 0's token comes from the entry stage, the last one's goes nowhere), and its "
                "share of the array's readout gather (the gather's cells divided by N):\n\n")
        f.write("| part | LUT4 | CCU2C | PFUMX + L6MUX21 | FF | logic slots (LUT4 + 2 × CCU2C) | share of the slots |\n")
        f.write("|---|---:|---:|---:|---:|---:|---:|\n")
        slots = {p: cost[p]["LUT4"] + 2 * cost[p]["CCU2C"] for p in rows}
        all_slots = sum(slots.values())
        sums = collections.Counter()
        for p in rows:
            name = "readout gather (the array's OR tree, per processor)" if p == "gather" else p
            cnt = cost[p]
            sums.update(cnt)
            f.write(f"| {name} | {cnt['LUT4']:.1f} | {cnt['CCU2C']:.1f} | {cnt['MUX']:.1f} | "
                    f"{cnt['FF']:.1f} | {slots[p]:.1f} | {100 * slots[p] / all_slots:.0f} % |\n")
        f.write(f"| **processor, all parts** | **{sums['LUT4']:.1f}** | **{sums['CCU2C']:.1f}** | "
                f"**{sums['MUX']:.1f}** | **{sums['FF']:.1f}** | **{all_slots:.1f}** | 100 % |\n\n")
        fixed = per["fixed"]
        f.write(f"Outside the processors, in the whole core (entry pipeline, FIFOs, controller, "
                f"shading step): "
                f"{fixed['LUT4']:.0f} LUT4, {fixed['CCU2C']:.0f} CCU2C, {fixed['MUX']:.0f} wide "
                f"multiplexers, {fixed['FF']:.0f} FF. Whole netlist: {total['LUT4']} LUT4, "
                f"{total['CCU2C']} CCU2C, {total['MUX']} PFUMX + L6MUX21, {total['FF']} FF.\n")
        if unclassified:
            f.write("\nProcessor registers in no part (a name this script does not know): "
                    + ", ".join(f"`{k}` ({v})" for k, v in sorted(unclassified.items())) + "\n")
    if unclassified:
        print("unclassified processor registers: " + ", ".join(sorted(unclassified)), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 6:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    sys.exit(main(*sys.argv[1:]))
