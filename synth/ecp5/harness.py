#!/usr/bin/env python3
"""Writes a pin-level test harness around the exported core top, for place and route on
real pins instead of out of context.

    python3 synth/ecp5/harness.py EXPORT.v TOP OUT.v

The core's ports need 348 pins, more than the CABGA381 package has, so the harness
keeps three: `clock` (placed on a PCLK pin by the LPF, so nextpnr drives every register
through the global clock network), `si` and `so`. Every other input of the core comes
from one shift register loaded from `si`; every output goes into a multiple-input
signature register (each bit: its output XOR its neighbour's last value) whose last bit
drives `so`. So no input is constant and no output is unobserved: synthesis keeps the
whole core, and the harness adds only flip-flop-to-flip-flop paths of one LUT.

The port list is read from the export (`module TOP(a, b, ...);` and its `input`/`output`
declarations), so the harness follows any configuration of the core.
"""
import re
import sys


def ports(text, top):
    m = re.search(r"^module %s\((.*?)\);(.*?)^endmodule" % re.escape(top), text, re.S | re.M)
    if not m:
        sys.exit("harness.py: no module %s in the export" % top)
    names = [n.strip() for n in m.group(1).split(",")]
    decl = {}
    pat = r"^\s*(input|output)\s+(?:wire|reg)\s*(?:\[(\d+):0\])?\s*(\w+)\s*;"
    for d, w, n in re.findall(pat, m.group(2), re.M):
        decl[n] = (d, int(w) + 1 if w else 1)
    missing = [n for n in names if n not in decl]
    if missing or "clock" not in decl:
        sys.exit("harness.py: ports without a declaration (or no clock): %s" % missing)
    return names, decl


def harness(names, decl, top):
    ins = [(n, decl[n][1]) for n in names if decl[n][0] == "input" and n != "clock"]
    outs = [(n, decl[n][1]) for n in names if decl[n][0] == "output"]
    ni, no = sum(w for _, w in ins), sum(w for _, w in outs)
    lines = [
        "module %s_harness(input wire clock, input wire si, output wire so);" % top,
        "    reg [%d:0] sh;" % (ni - 1),
        "    always @(posedge clock) sh <= {sh[%d:0], si};" % (ni - 2),
    ]
    o = 0
    for n, w in ins:
        lines.append("    wire [%d:0] %s = sh[%d:%d];" % (w - 1, n, o + w - 1, o))
        o += w
    for n, w in outs:
        lines.append("    wire [%d:0] %s;" % (w - 1, n))
    conns = ", ".join(".%s(%s)" % (n, n) for n in names if n != "clock")
    lines.append("    %s core(.clock(clock), %s);" % (top, conns))
    lines.append("    wire [%d:0] all_out = {%s};" % (no - 1, ", ".join(n for n, _ in outs)))
    lines.append("    reg [%d:0] misr;" % (no - 1))
    lines.append(
        "    always @(posedge clock) misr <= all_out ^ {misr[%d:0], misr[%d]};" % (no - 2, no - 1)
    )
    lines.append("    assign so = misr[%d];" % (no - 1))
    lines.append("endmodule")
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: harness.py EXPORT.v TOP OUT.v")
    src, top, out = sys.argv[1:]
    names, decl = ports(open(src).read(), top)
    with open(out, "w") as f:
        f.write(harness(names, decl, top))


if __name__ == "__main__":
    main()
