//! Vector files (`$readmemh`) and the Verilog testbench that drives the exported mask
//! search unit (seed 000) with them.

use super::Schedule;
use crate::TbError;
use pixelproc_rtl::mask_search::{Variant, Z_BITS};
use std::path::Path;

/// Bits packed LSB first into 64-bit limbs; printed as hex, most significant first.
#[derive(Default)]
struct Packer {
    limbs: Vec<u64>,
    n: usize,
}

impl Packer {
    fn push(&mut self, v: u64, w: usize) {
        for i in 0..w {
            if self.n.is_multiple_of(64) {
                self.limbs.push(0);
            }
            if (v >> i) & 1 == 1 {
                let l = self.n / 64;
                self.limbs[l] |= 1 << (self.n % 64);
            }
            self.n += 1;
        }
    }
    fn hex(&self, digits: usize, out: &mut String) {
        for d in (0..digits).rev() {
            let bit = 4 * d;
            let l = bit / 64;
            let v = if l < self.limbs.len() {
                (self.limbs[l] >> (bit % 64)) & 0xF
            } else {
                0
            };
            out.push(char::from_digit(v as u32, 16).unwrap_or('0'));
        }
        out.push('\n');
    }
}

/// Width of the result part of an expect line for `b`-bit masks.
fn result_bits(b: usize) -> usize {
    1 + 1 + 5 + b + 17 + 4 * Z_BITS
}

/// Width of the step part (iterative only).
fn step_bits(b: usize) -> usize {
    1 + 1 + 5 + b + b + 4
}

fn stim_bits(b: usize) -> usize {
    1 + 1 + b + 2 + 3 * 48
}

/// Writes `stim.hex` and `expect.hex` for a schedule (layouts in the testbench Verilog of
/// [`testbench_verilog`]); returns the number of vectors.
pub fn write_vectors(
    dir: &Path,
    variant: Variant,
    b: usize,
    sched: &Schedule,
) -> Result<usize, TbError> {
    let sd = stim_bits(b).div_ceil(4);
    let ed = (result_bits(b)
        + if variant == Variant::Iterative {
            step_bits(b)
        } else {
            0
        })
    .div_ceil(4);
    let mut stim = String::with_capacity(sched.inputs.len() * (sd + 1));
    let mut exp = String::with_capacity(sched.inputs.len() * (ed + 1));
    let zm = (1u64 << Z_BITS) - 1;
    for (v, e) in sched.inputs.iter().zip(&sched.expect) {
        let mut p = Packer::default();
        p.push(v.rst as u64, 1);
        p.push(v.valid as u64, 1);
        p.push(v.mask, b);
        p.push(v.corner as u64, 2);
        for f in v.plane {
            p.push(f, 48);
        }
        p.hex(sd, &mut stim);
        let mut q = Packer::default();
        let r = &e.result;
        q.push(r.valid as u64, 1);
        q.push(r.hit as u64, 1);
        q.push(r.steps as u64, 5);
        q.push(r.and_result, b);
        q.push(r.rom as u64, 17);
        for z in r.z {
            q.push(z as u64 & zm, Z_BITS);
        }
        if variant == Variant::Iterative {
            let s = &e.step;
            q.push(e.ready as u64, 1);
            q.push(s.active as u64, 1);
            q.push(s.line as u64, 5);
            q.push(s.search_mask, b);
            q.push(s.and_result, b);
            q.push(s.zero as u64, 1);
            q.push(s.moved as u64, 1);
            q.push(s.hit as u64, 1);
            q.push(s.done as u64, 1);
        }
        q.hex(ed, &mut exp);
    }
    std::fs::write(dir.join("stim.hex"), stim)?;
    std::fs::write(dir.join("expect.hex"), exp)?;
    Ok(sched.inputs.len())
}

/// The iterative unit's step ports in the testbench: declarations, connections, and the
/// head of the `got` concatenation.
fn step_ports(b: usize) -> (String, String, String) {
    (
        format!(
            "    wire ready, active, zero, moved, hit, done;\n    wire [4:0] line;\n    wire [{m}:0] search_mask, and_result;\n",
            m = b - 1
        ),
        ", .ready(ready), .active(active), .line(line), .search_mask(search_mask), .and_result(and_result), .zero(zero), .moved(moved), .hit(hit), .done(done)".to_string(),
        "done, hit, moved, zero, and_result, search_mask, line, active, ready, ".to_string(),
    )
}

/// The vector testbench for module `dut` (`b`-bit masks) over `cycles` vectors.
///
/// `stim.hex`, LSB first: `rst`, `in_valid`, `in_mask[b]`, `in_corner[2]`, `in_zc[48]`,
/// `in_sx[48]`, `in_sy[48]`. `expect.hex`, LSB first: `out_valid`, `out_hit`,
/// `out_steps[5]`, `out_and[b]`, `out_rom[17]`, `out_z1`, `out_z2`, `out_zmin`,
/// `out_zmax` (53 each); iterative then `ready`, `active`, `line[5]`, `search_mask[b]`,
/// `and_result[b]`, `zero`, `moved`, `hit`, `done`. After each rising edge every step port
/// and `out_valid` is compared, the other result ports when `out_valid` is expected.
pub fn testbench_verilog(dut: &str, variant: Variant, b: usize, cycles: usize) -> String {
    let rb = result_bits(b);
    let iter = variant == Variant::Iterative;
    let eb = rb + if iter { step_bits(b) } else { 0 };
    let sb = stim_bits(b);
    let (step_decl, step_conn, step_cat) = if iter {
        step_ports(b)
    } else {
        (String::new(), String::new(), String::new())
    };
    let step_cmp = if iter {
        format!("got[{}:{rb}] !== expv[t][{}:{rb}] || ", eb - 1, eb - 1)
    } else {
        String::new()
    };
    let drive = format!(
        "            rst = stim[t][0];
            in_valid = stim[t][1];
            in_mask = stim[t][{mb}:2];
            in_corner = stim[t][{cb}:{cb0}];
            in_zc = stim[t][{z0}+47:{z0}];
            in_sx = stim[t][{z0}+95:{z0}+48];
            in_sy = stim[t][{z0}+143:{z0}+96];
",
        mb = b + 1,
        cb = b + 3,
        cb0 = b + 2,
        z0 = b + 4,
    );
    let mismatch = format!(
        "t >= 1 && ({step_cmp}got[0] !== expv[t][0] || (expv[t][0] && got[{rb1}:0] !== expv[t][{rb1}:0]))",
        rb1 = rb - 1,
    );
    let tail = crate::sim_tools::vector_loop("tb_mask_search", &drive, &mismatch);
    format!(
        r#"// Vector testbench for {dut}: drives stim.hex, checks the outputs against expect.hex.
`timescale 1ns/1ps
module tb_mask_search;
    localparam integer NCYC = {cycles};
    reg clock = 1'b0;
    reg [{sb1}:0] stim [0:NCYC-1];
    reg [{eb1}:0] expv [0:NCYC-1];
    reg rst, in_valid;
    reg [{b1}:0] in_mask;
    reg [1:0] in_corner;
    reg [47:0] in_zc, in_sx, in_sy;
    wire out_valid, out_hit;
    wire [4:0] out_steps;
    wire [{b1}:0] out_and;
    wire [16:0] out_rom;
    wire [52:0] out_z1, out_z2, out_zmin, out_zmax;
{step_decl}    wire [{eb1}:0] got = {{{step_cat}out_zmax, out_zmin, out_z2, out_z1, out_rom, out_and, out_steps, out_hit, out_valid}};
    integer t;
    {dut} dut (.clock(clock), .rst(rst), .in_valid(in_valid), .in_mask(in_mask),
        .in_corner(in_corner), .in_zc(in_zc), .in_sx(in_sx), .in_sy(in_sy),
        .out_valid(out_valid), .out_hit(out_hit), .out_steps(out_steps), .out_and(out_and),
        .out_rom(out_rom), .out_z1(out_z1), .out_z2(out_z2), .out_zmin(out_zmin),
        .out_zmax(out_zmax){step_conn});
{tail}"#,
        sb1 = sb - 1,
        eb1 = eb - 1,
        b1 = b - 1,
    )
}
