//! The search mask generator of the iterative unit (seed 000, JP2569952B2, Fig. 6 block
//! 3): the search mask of a line for a start corner, from a constant table.
//!
//! Line `k` of family `(p, q)` from corner `c` is `search_mask_table(size, family, c)[k]`
//! (`pixelproc_formats::abuffer`); lines past the family's last read 0.

use super::LINE_BITS;
use pixelproc_formats::abuffer::{search_mask_table, Corner, MaskSize, SearchFamily};
use rust_hdl::prelude::*;

/// `table[corner][line]` (combinational).
#[derive(LogicBlock)]
pub struct MaskGen<const B: usize> {
    /// Line index.
    pub line: Signal<In, Bits<LINE_BITS>>,
    /// Start corner code (bit 0 right, bit 1 bottom).
    pub corner: Signal<In, Bits<2>>,
    /// The search mask.
    pub mask: Signal<Out, Bits<B>>,
    k_sm0: Vec<Constant<Bits<B>>>,
    k_sm1: Vec<Constant<Bits<B>>>,
    k_sm2: Vec<Constant<Bits<B>>>,
    k_sm3: Vec<Constant<Bits<B>>>,
    k_line: Vec<Constant<Bits<LINE_BITS>>>,
    k_zero: Constant<Bits<B>>,
    sm: Signal<Local, Bits<B>>,
}

impl<const B: usize> MaskGen<B> {
    /// The table of `family` for `size` (the caller checks `size.bits() == B`).
    pub fn new(size: MaskSize, family: SearchFamily) -> Self {
        let [k_sm0, k_sm1, k_sm2, k_sm3] = Corner::ALL.map(|c| {
            search_mask_table(size, family, c)
                .into_iter()
                .map(|m| Constant::new(m.to_bits()))
                .collect::<Vec<_>>()
        });
        MaskGen {
            line: Default::default(),
            corner: Default::default(),
            mask: Default::default(),
            k_line: (0..k_sm0.len() as u64)
                .map(|k| Constant::new(k.to_bits()))
                .collect(),
            k_sm0,
            k_sm1,
            k_sm2,
            k_sm3,
            k_zero: Constant::new(0u64.to_bits()),
            sm: Default::default(),
        }
    }

    /// Number of lines in the table.
    pub fn lines(&self) -> usize {
        self.k_line.len()
    }
}

impl<const B: usize> Logic for MaskGen<B> {
    #[hdl_gen]
    fn update(&mut self) {
        // A local, so that the port is written once per evaluation (see `SearchBackEnd`).
        self.sm.next = self.k_zero.val();
        for k in 0..self.k_line.len() {
            if self.line.val() == self.k_line[k].val() {
                if self.corner.val().get_bit(1) {
                    if self.corner.val().get_bit(0) {
                        self.sm.next = self.k_sm3[k].val();
                    } else {
                        self.sm.next = self.k_sm2[k].val();
                    }
                } else if self.corner.val().get_bit(0) {
                    self.sm.next = self.k_sm1[k].val();
                } else {
                    self.sm.next = self.k_sm0[k].val();
                }
            }
        }
        self.mask.next = self.sm.val();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_golden_table() {
        let (size, fam) = (MaskSize::S4X4, SearchFamily::DIAGONAL);
        let mut u = MaskGen::<16>::new(size, fam);
        u.connect_all();
        for c in Corner::ALL {
            let t = search_mask_table(size, fam, c);
            for (k, &want) in t.iter().enumerate().chain([(t.len(), &0)]) {
                u.line.next = (k as u64).to_bits();
                u.corner.next = (c.code() as u64).to_bits();
                assert!(simulate(&mut u, 100));
                assert_eq!(u.mask.val().to_u64(), want, "corner {c:?}, line {k}");
            }
        }
    }

    #[test]
    fn verilog_passes_yosys() {
        let u = MaskGen::<16>::new(MaskSize::S4X4, SearchFamily::DIAGONAL);
        crate::mask_search::yosys_check("pixelproc_rtl_mask_gen", u);
    }
}
