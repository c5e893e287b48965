//! A D flip-flop that synthesis must not merge with an identical one: register
//! duplication for fan-out.
//!
//! rust-hdl's `DFF` and this block behave the same, cycle for cycle. The difference is in
//! the Verilog: the `always` block carries `(* keep *)`, so Yosys's `opt_merge` leaves two
//! copies loaded from the same `d` as two registers. The array uses one copy per multiplier
//! that reads the tile offset (`pixel_array`, `entry_channel`): with a single
//! register, its 16 bits fanned out to every entry multiplier (DSP blocks spread over the
//! die) and that routing was the critical path; a copy per multiplier can sit next to its DSP.
//!
//! Ports (the same names as `DFF`, so `dff_setup!` drives it): `clock` (in), `d` (in),
//! `q` (out, `d` as it was at the last rising edge; 0 at power-up).

use rust_hdl::prelude::*;

/// A register kept as its own cell through synthesis.
#[derive(Clone, Debug, LogicBlock, Default)]
pub struct KeepDff<T: Synth> {
    /// Next value.
    pub d: Signal<In, T>,
    /// Value since the last rising edge.
    pub q: Signal<Out, T>,
    /// Clock.
    pub clock: Signal<In, Clock>,
}

impl<T: Synth> Logic for KeepDff<T> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            self.q.next = self.d.val()
        }
    }

    fn connect(&mut self) {
        self.q.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
initial begin
   q = {:x};
end

(* keep *)
always @(posedge clock) begin
   q <= d;
end
",
            T::default().verilog()
        ))
    }

    fn timing(&self) -> Vec<TimingInfo> {
        vec![TimingInfo {
            name: "keep_dff".into(),
            clock: "clock".into(),
            inputs: vec!["d".into()],
            outputs: vec!["q".into()],
        }]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two copies fed from one `d`, beside a plain `DFF`: all three follow `d` one edge
    /// late, from 0.
    #[derive(LogicBlock, Default)]
    struct Pair {
        clock: Signal<In, Clock>,
        d: Signal<In, Bits<16>>,
        a: KeepDff<Bits<16>>,
        b: KeepDff<Bits<16>>,
        r: DFF<Bits<16>>,
    }

    impl Logic for Pair {
        #[hdl_gen]
        fn update(&mut self) {
            dff_setup!(self, clock, a, b, r);
            self.a.d.next = self.d.val();
            self.b.d.next = self.d.val();
            self.r.d.next = self.d.val();
        }
    }

    #[test]
    fn copies_follow_d_like_a_dff() {
        let mut uut = Pair::default();
        uut.connect_all();
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..500 {
            let v = crate::xorshift64(&mut x) & 0xffff;
            let before = uut.r.q.val();
            uut.d.next = v.to_bits();
            assert!(simulate(&mut uut, 50));
            // Between edges nothing moves.
            for q in [uut.a.q.val(), uut.b.q.val()] {
                assert_eq!(q, before);
            }
            uut.clock.next = Clock { clk: true };
            assert!(simulate(&mut uut, 50));
            for q in [uut.a.q.val(), uut.b.q.val(), uut.r.q.val()] {
                assert_eq!(q.index() as u64, v);
            }
            uut.clock.next = Clock { clk: false };
            assert!(simulate(&mut uut, 50));
        }
    }

    #[test]
    fn verilog_keeps_the_register() {
        let mut uut = Pair::default();
        uut.connect_all();
        let v = generate_verilog(&uut);
        assert!(v.contains("(* keep *)"), "{v}");
    }
}
