//! The shading unit's tests: table writes, and whole pixels against the golden formula.

use super::*;
use pixelproc_formats::core_stream::{shade_addr, shade_rgb};
use pixelproc_formats::regs::ProcState;

fn edge(u: &mut ShadeUnit) {
    u.clock.next = Clock { clk: true };
    assert!(simulate(u, 50));
    u.clock.next = Clock { clk: false };
    assert!(simulate(u, 50));
}

fn word(s: &ProcState) -> Bits<READOUT_W> {
    let w = s.pack_readout();
    let mut b: Bits<READOUT_W> = (w as u64).to_bits();
    b.set_bits::<{ READOUT_W - 64 }>(64, ((w >> 64) as u64).to_bits());
    b
}

/// A table write lands [`TW_DELAY`] = 1 edge late, in every bank: with the write on
/// `tw_*` before edge `E`, pixels of that entry entering stage 1 at `E` and `E + 1`
/// (on the inputs before `E − 1` and `E`: stage 0 comes first) are shaded with the old
/// entry, from `E + 2` on with the new one; and the write
/// reaches only its own word (a pixel of the same low address in the next bank keeps
/// its entry).
#[test]
fn table_write_lands_one_edge_later() {
    let mut u = ShadeUnit::new(true);
    u.connect_all();
    let (old, new, other) = ((100u32, 30u32), (300u32, 200u32), (256u32, 0u32));
    let px = |nclass: u8| ProcState {
        zb: 5000,
        rgb: 0xc8_7b_40,
        sh: 0x20_10_05,
        mask: 5,
        count: 9,
        nclass,
        ..Default::default()
    };
    let set = |u: &mut ShadeUnit, en: bool, a: u32, (f, g): (u32, u32)| {
        u.tw_en.next = en;
        u.tw_addr.next = (a as u64).to_bits();
        u.tw_data.next = ((g as u64) << FACTOR_BITS | f as u64).to_bits();
    };
    for bank in 0..BANKS as u8 {
        // Bank `bank` holds normal classes 8·bank ..= 8·bank + 7; take a different low
        // address in each bank, and its neighbour in the next bank.
        let nc = 8 * bank + bank % 8;
        let nb = 8 * ((bank + 1) % BANKS as u8) + bank % 8;
        let a = shade_addr(nc, 5, 9);
        let b = shade_addr(nb, 5, 9);
        set(&mut u, true, a, old);
        edge(&mut u);
        set(&mut u, true, b, other);
        edge(&mut u);
        set(&mut u, false, 0, (0, 0));
        u.in_valid.next = false;
        for _ in 0..2 {
            edge(&mut u);
        }
        // Edge E − 1: the first pixel; edge E: the new write and the second pixel; then
        // one more pixel of the entry, one of the neighbour, and the pipeline drains.
        let seq = [nc, nc, nc, nb];
        let want = [old, old, new, other];
        let mut got = Vec::new();
        for k in 0..seq.len() + LATENCY {
            if k == 1 {
                set(&mut u, true, a, new);
            } else {
                set(&mut u, false, 0, (0, 0));
            }
            u.in_valid.next = k < seq.len();
            u.in_word.next = word(&px(seq[k.min(seq.len() - 1)]));
            u.in_meta.next = 0u64.to_bits();
            edge(&mut u);
            if u.out_valid.val() {
                got.push(u.out_word.val());
            }
        }
        assert_eq!(got.len(), seq.len());
        for (k, ((nc, (f, g)), w)) in seq.iter().zip(want).zip(got).enumerate() {
            let mut s = px(*nc);
            s.rgb = shade_rgb(s.rgb, s.sh, f, g);
            assert_eq!(w, word(&s), "bank {bank}, pixel {k}");
        }
    }
}

/// Every channel value against a spread of shade registers, factors and drop weights,
/// through the banked table (entries in twelve banks; factors up to 511, where the clamp
/// at 255 acts), equals `shade_rgb`; background pixels and the unshaded unit pass
/// colours through.
#[test]
fn shades_like_the_formula() {
    for shading in [true, false] {
        let mut u = ShadeUnit::new(shading);
        u.connect_all();
        let entries = [
            (0u32, 0u32),
            (1, 0),
            (77, 0),
            (128, 0),
            (255, 0),
            (256, 0),
            (256, 256),
            (256, 128),
            (256, 1),
            (200, 100),
            (511, 0),
            (300, 511),
        ];
        for (i, (f, g)) in entries.iter().enumerate() {
            u.tw_en.next = true;
            // Normal classes 0, 20, 40, …: twelve different banks, one low address (bank
            // isolation).
            u.tw_addr.next = (shade_addr((20 * i) as u8, 5, 3) as u64).to_bits();
            u.tw_data.next = ((*g as u64) << FACTOR_BITS | *f as u64).to_bits();
            edge(&mut u);
        }
        u.tw_en.next = false;
        let mut want = Vec::new();
        for v in (0..=255u32).step_by(3) {
            for (i, (f, g)) in entries.iter().enumerate() {
                let s = ProcState {
                    zb: if v % 7 == 0 { Z_FAR } else { v * 1000 },
                    rgb: v << 16 | (255 - v) << 8 | (v * 5 % 256),
                    sh: (v / 2) << 16 | (v * 7 % 256) << 8 | (255 - v / 3),
                    mask: 5,
                    count: 3,
                    nclass: (20 * i) as u8,
                    ..Default::default()
                };
                let mut out = s;
                if shading && s.zb != Z_FAR {
                    out.rgb = shade_rgb(s.rgb, s.sh, *f, *g);
                }
                want.push(out);
                u.in_valid.next = true;
                u.in_word.next = word(&s);
                u.in_meta.next = 2u64.to_bits();
                edge(&mut u);
                if want.len() >= LATENCY {
                    assert!(u.out_valid.val());
                    assert_eq!(u.out_word.val(), word(&want[want.len() - LATENCY]));
                }
            }
        }
    }
}
