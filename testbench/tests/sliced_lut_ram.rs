//! The exported Verilog of `pixelproc_rtl::lut_ram::SlicedLutRam` (4 slices of unequal
//! width) in Icarus Verilog, clock by clock against its RustHDL simulation, which is
//! itself checked against a plain array. A functional comparison cannot see the slices
//! (every slice's address copy holds the same value), so a second phase writes distinct
//! addresses into the copies of each slice through hierarchical references and checks
//! that every slice reads and writes its own bits at its own copy. Then each of a list of
//! wiring mistakes in the Verilog (a slice reading or writing at another slice's address,
//! slices swapped in the read word, a slice reading the unregistered address, a write
//! copy loaded from the read address, a slice writing another slice's bits) must make
//! the comparison fail. Last, Yosys's ECP5 synthesis of the block must keep every copy
//! (`(* keep *)`): removing the attribute must lose them.
//!
//! Needs iverilog (and yosys for the last part). A missing tool prints `SKIPPED: ...`, and
//! fails under `CI=true`.

use pixelproc_rtl::lut_ram::{slice_bounds, SlicedLutRam};
use pixelproc_rtl::verilog::rename_top;
use pixelproc_sim::rng::Lcg64;
use pixelproc_testbench::external::{icarus_run, mutant, skip_or_fail, tool_available};
use rust_hdl::prelude::*;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Data bits (7 nibbles: slices of 4, 8, 8 and 8 bits), address bits, slices.
const W: usize = 28;
const A: usize = 3;
const SLICES: usize = 4;
const WORDS: usize = 1 << A;
const CLOCKS: usize = 3000;
type Ram = SlicedLutRam<Bits<W>, A>;

fn mask(lo: usize, hi: usize) -> u64 {
    ((1u64 << (hi - lo)) - 1) << lo
}

/// The exported Verilog of the 4-slice RAM, module `sliced_ram`.
fn ram_verilog() -> String {
    let mut ram = Ram::new(SLICES);
    ram.connect_all();
    rename_top(&generate_verilog(&ram), "sliced_ram")
}

/// One clock of the random phase: inputs, and `read_data` expected after the edge.
struct Step {
    we: bool,
    nwa: u64,
    wd: u64,
    nra: u64,
    expect: u64,
}

/// Random writes and reads through the RustHDL simulation, checked against a plain
/// array; returns the steps and the array's contents at the end.
fn random_phase() -> (Vec<Step>, [u64; WORDS]) {
    let mut uut = Ram::new(SLICES);
    uut.connect_all();
    let mut model = [0u64; WORDS];
    let mut wa = 0usize;
    let mut rng = Lcg64(0x9e37_79b9_7f4a_7c15);
    let mut steps = Vec::with_capacity(CLOCKS);
    for i in 0..CLOCKS {
        // The top bits: an LCG's low bits have short periods.
        let x = rng.step() >> 16;
        let (mut we, mut nwa, nra) = (x & 1 == 1, (x >> 1) & 7, (x >> 4) & 7);
        // The Verilog memories start undefined: the first clocks write every word.
        if i <= WORDS {
            (we, nwa) = (i > 0, (i % WORDS) as u64);
        }
        let wd = (x >> 8) & mask(0, W);
        uut.write_enable.next = we;
        uut.next_write_address.next = nwa.to_bits();
        uut.write_data.next = wd.to_bits();
        uut.next_read_address.next = nra.to_bits();
        uut.clock.next = Clock { clk: true };
        assert!(simulate(&mut uut, 50));
        uut.clock.next = Clock { clk: false };
        assert!(simulate(&mut uut, 50));
        if we {
            model[wa] = wd;
        }
        let ra = nra as usize;
        wa = nwa as usize;
        let expect = uut.read_data.val().to_u64();
        assert_eq!(expect, model[ra], "RustHDL against the array, clock {i}");
        steps.push(Step {
            we,
            nwa,
            wd,
            nra,
            expect,
        });
    }
    (steps, model)
}

/// The Icarus testbench: the random phase from `stim.hex`/`expect.hex` (compared once
/// every word has been written: the Verilog memories start undefined), then the
/// per-slice phase, statements generated here from the array contents `mem`.
fn testbench(mem: [u64; WORDS]) -> String {
    let bounds = slice_bounds(W, SLICES);
    let names: Vec<_> = (0..SLICES).map(Ram::slice_names).collect();
    let mut mem = mem;
    let mut body = String::new();
    let check = |body: &mut String, what: &str, expect: u64| {
        let _ = writeln!(
            body,
            "    #1 if (read_data !== {W}'h{expect:x}) begin $display(\"MISMATCH {what}: read_data %h, expected %h\", read_data, {W}'h{expect:x}); errors = errors + 1; end"
        );
    };
    // Reads: each slice's read copy set to its own address.
    for r in 0..WORDS {
        let mut expect = 0;
        for (s, &(lo, hi)) in bounds.iter().enumerate() {
            let a = (r + 3 * s) % WORDS;
            let _ = writeln!(body, "    dut.{} = {A}'d{a};", names[s].0);
            expect |= mem[a] & mask(lo, hi);
        }
        check(&mut body, &format!("slice read round {r}"), expect);
    }
    // Writes: each slice's write copy set to its own address, one write at an edge (the
    // copies load their next values at that edge: `next_write_address` 0, not used).
    let mut rng = Lcg64(0x2545_f491_4f6c_dd1d);
    for r in 0..WORDS {
        let wd = (rng.step() >> 16) & mask(0, W);
        for (s, &(lo, hi)) in bounds.iter().enumerate() {
            let a = (r + 5 * s + 1) % WORDS;
            let _ = writeln!(body, "    dut.{} = {A}'d{a};", names[s].1);
            mem[a] = (mem[a] & !mask(lo, hi)) | (wd & mask(lo, hi));
        }
        let _ = writeln!(
            body,
            "    write_enable = 1'b1; write_data = {W}'h{wd:x}; next_write_address = {A}'d0;\n    #1 clock = 1; #1 clock = 0;\n    write_enable = 1'b0;"
        );
    }
    // Read every word back through the ports.
    for (a, &word) in mem.iter().enumerate() {
        let _ = writeln!(
            body,
            "    next_read_address = {A}'d{a};\n    #1 clock = 1; #1 clock = 0;"
        );
        check(&mut body, &format!("slice write, word {a}"), word);
    }
    let stim_w = 2 * A + 1 + W;
    format!(
        "\
module tb;
    reg clock = 1'b0;
    reg write_enable = 1'b0;
    reg [{wm}:0] write_data = {W}'d0;
    reg [{am}:0] next_write_address = {A}'d0;
    reg [{am}:0] next_read_address = {A}'d0;
    wire [{wm}:0] read_data;
    reg [{sm}:0] stim [0:{cm}];
    reg [{wm}:0] expected [0:{cm}];
    integer t;
    integer errors;
    sliced_ram dut(.clock(clock), .write_enable(write_enable), .write_data(write_data),
        .next_write_address(next_write_address), .next_read_address(next_read_address),
        .read_data(read_data));
    initial begin
    $readmemh(\"stim.hex\", stim);
    $readmemh(\"expect.hex\", expected);
    errors = 0;
    for (t = 0; t < {CLOCKS}; t = t + 1) begin
        {{next_read_address, next_write_address, write_enable, write_data}} = stim[t];
        // The inputs of the next clock do not change the read yet.
        #1 if (t > {WORDS} + 1 && read_data !== expected[t - 1]) begin
            if (errors < 5) $display(\"MISMATCH before edge %0d: read_data %h, expected %h\", t, read_data, expected[t - 1]);
            errors = errors + 1;
        end
        #4 clock = 1'b1;
        #5 clock = 1'b0;
        if (t > {WORDS} && read_data !== expected[t]) begin
            if (errors < 5) $display(\"MISMATCH clock %0d: read_data %h, expected %h\", t, read_data, expected[t]);
            errors = errors + 1;
        end
    end
{body}    if (errors == 0) $display(\"PASS clocks={CLOCKS}\");
    else $display(\"FAIL errors=%0d\", errors);
    $finish;
    end
endmodule
",
        wm = W - 1,
        am = A - 1,
        sm = stim_w - 1,
        cm = CLOCKS - 1,
    )
}

/// Compiles `ram` (the RAM's Verilog) with the testbench and runs it; the simulator's
/// output.
fn run(dir: &Path, ram: &str, tb: &str) -> String {
    std::fs::write(dir.join("ram.v"), ram).unwrap();
    std::fs::write(dir.join("tb.v"), tb).unwrap();
    icarus_run(dir, &[dir.join("tb.v"), dir.join("ram.v")], &[])
}

fn passed(text: &str) -> bool {
    text.lines().any(|l| l == format!("PASS clocks={CLOCKS}")) && !text.contains("MISMATCH")
}

#[test]
fn sliced_lut_ram_verilog_matches_and_wiring_mistakes_are_caught() {
    if !tool_available("iverilog") {
        skip_or_fail("iverilog").unwrap();
        return;
    }
    assert_eq!(
        slice_bounds(W, SLICES),
        vec![(0, 4), (4, 12), (12, 20), (20, 28)]
    );
    let (steps, mem) = random_phase();
    let dir = tempfile::tempdir().unwrap();
    let (mut stim, mut expect) = (String::new(), String::new());
    for s in &steps {
        let line = (((s.nra << A | s.nwa) << 1 | s.we as u64) << W) | s.wd;
        let _ = writeln!(stim, "{line:x}");
        let _ = writeln!(expect, "{:x}", s.expect);
    }
    std::fs::write(dir.path().join("stim.hex"), stim).unwrap();
    std::fs::write(dir.path().join("expect.hex"), expect).unwrap();
    let ram = ram_verilog();
    let tb = testbench(mem);
    let text = run(dir.path(), &ram, &tb);
    assert!(passed(&text), "the exported RAM failed:\n{text}");

    // Wiring mistakes the comparison must catch: (what, text in the RAM, replacement).
    let mutants: [(&str, &str, &str); 8] = [
        (
            "slice 1 reads at slice 0's read address",
            "rd_1 = mem_1[ra_1];",
            "rd_1 = mem_1[ra_0];",
        ),
        (
            "slice 3 reads at slice 2's read address",
            "rd_3 = mem_3[ra_3];",
            "rd_3 = mem_3[ra_2];",
        ),
        (
            "slice 2 writes at slice 3's write address",
            "mem_2[wa_2] <=",
            "mem_2[wa_3] <=",
        ),
        (
            "slices 1 and 2 swapped in the read word",
            "{rd_3, rd_2, rd_1, rd_0}",
            "{rd_3, rd_1, rd_2, rd_0}",
        ),
        (
            "slice 0 reads the unregistered address",
            "rd_0 = mem_0[ra_0];",
            "rd_0 = mem_0[next_read_address];",
        ),
        (
            "slice 2's write copy loaded from the read address",
            "wa_2 <= next_write_address;",
            "wa_2 <= next_read_address;",
        ),
        (
            "slice 3 writes slice 2's bits",
            "mem_3[wa_3] <= write_data[27:20];",
            "mem_3[wa_3] <= write_data[19:12];",
        ),
        (
            "slice 1's read copy never loaded",
            "ra_1 <= next_read_address;",
            "ra_1 <= ra_1;",
        ),
    ];
    for (what, from, to) in mutants {
        let text = run(dir.path(), &mutant(&ram, what, from, to), &tb);
        assert!(
            !passed(&text) && text.contains("MISMATCH"),
            "{what}: the comparison did not fail:\n{text}"
        );
        let first = text.lines().find(|l| l.contains("MISMATCH")).unwrap_or("");
        println!("caught: {what}: {first}");
    }

    // Synthesis keeps the copies: 2 × SLICES × A flip-flops (they are all the block's
    // registers), and without `(* keep *)` Yosys merges them.
    if !tool_available("yosys") {
        skip_or_fail("yosys").unwrap();
        return;
    }
    let ffs = |verilog: &str| -> usize {
        std::fs::write(dir.path().join("synth.v"), verilog).unwrap();
        let out = Command::new("yosys")
            .current_dir(dir.path())
            .args([
                "-q",
                "-p",
                "read_verilog synth.v; synth_ecp5 -top sliced_ram; tee -q -o stat.txt stat",
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "yosys failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(dir.path().join("stat.txt")).unwrap();
        let count = |cell: &str| -> usize {
            text.lines()
                .filter_map(|l| {
                    let mut w = l.split_whitespace();
                    (w.next() == Some(cell)).then(|| w.next()?.parse::<usize>().ok())?
                })
                .sum()
        };
        // The memories are LUT RAM: one DPR16X4 per nibble (8 words).
        assert_eq!(count("TRELLIS_DPR16X4"), W / 4, "{text}");
        count("TRELLIS_FF")
    };
    assert_eq!(ffs(&ram), 2 * SLICES * A);
    let unkept = ram.replace("(* keep *) ", "");
    assert!(
        ffs(&unkept) < 2 * SLICES * A,
        "the copies survive without keep"
    );
}
