//! Bit-field tables for the packed words of seed 001 (Matsumoto): the span word of
//! section 3 and the processor readout word. A packed word is described once, as a list
//! of [`Field`]s (name, least significant bit, width), and everything that packs, unpacks or slices the word
//! (the golden model's `pack`/`unpack`, the RTL's decode, the external testbench) reads
//! the same table. `docs/formats.md` prints the tables; a test checks the document
//! against them.
//!
//! Fields are laid out LSB first with [`Field::first`] and [`Field::then`], so a table
//! has no gaps and no overlaps by construction.

/// One named bit field of a packed word.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field {
    /// Name, as `docs/formats.md` spells it.
    pub name: &'static str,
    /// Position of the field's least significant bit.
    pub lsb: usize,
    /// Width in bits (1 ..= 64).
    pub width: usize,
}

impl Field {
    /// The field at bit 0.
    pub const fn first(name: &'static str, width: usize) -> Field {
        Field {
            name,
            lsb: 0,
            width,
        }
    }

    /// The field directly above `self`.
    pub const fn then(self, name: &'static str, width: usize) -> Field {
        Field {
            name,
            lsb: self.end(),
            width,
        }
    }

    /// One past the field's most significant bit (the next free bit).
    pub const fn end(self) -> usize {
        self.lsb + self.width
    }

    /// Position of the field's most significant bit.
    pub const fn msb(self) -> usize {
        self.end() - 1
    }

    /// The low `width` bits set.
    pub const fn mask(self) -> u64 {
        if self.width >= 64 {
            u64::MAX
        } else {
            (1u64 << self.width) - 1
        }
    }

    /// Reads the field from a word stored as little-endian 64-bit limbs (limb 0 holds
    /// bit 0).
    pub fn get(self, limbs: &[u64]) -> u64 {
        let mut v = 0u64;
        for b in 0..self.width {
            let at = self.lsb + b;
            if (limbs[at / 64] >> (at % 64)) & 1 == 1 {
                v |= 1u64 << b;
            }
        }
        v
    }

    /// ORs the low `width` bits of `v` into the field (the field must be zero before).
    pub fn put(self, limbs: &mut [u64], v: u64) {
        let v = v & self.mask();
        for b in 0..self.width {
            if (v >> b) & 1 == 1 {
                let at = self.lsb + b;
                limbs[at / 64] |= 1u64 << (at % 64);
            }
        }
    }

    /// As [`Field::get`], for a word of at most 128 bits held in a `u128`.
    pub fn get_u128(self, word: u128) -> u64 {
        self.get(&[word as u64, (word >> 64) as u64])
    }

    /// As [`Field::put`], for a word of at most 128 bits held in a `u128`.
    pub fn put_u128(self, word: &mut u128, v: u64) {
        let mut l = [*word as u64, (*word >> 64) as u64];
        self.put(&mut l, v);
        *word = ((l[1] as u128) << 64) | l[0] as u128;
    }
}

/// Bits used by a table (one past the top field's most significant bit).
pub const fn table_end(fields: &[Field]) -> usize {
    let mut end = 0;
    let mut i = 0;
    while i < fields.len() {
        if fields[i].end() > end {
            end = fields[i].end();
        }
        i += 1;
    }
    end
}

/// Parses the first Markdown table after the first line of `doc` that starts with
/// `heading`, whose
/// first column is `bits` (`msb:lsb` or a single bit) and whose second column is a
/// backquoted field name; rows whose name is not backquoted (reserved bits) are skipped.
/// Returns `(name, lsb, width)` per row, in document order.
pub fn parse_doc_table(doc: &str, heading: &str) -> Vec<(String, usize, usize)> {
    let mut rows = Vec::new();
    let mut lines = doc
        .lines()
        .skip_while(|l| !l.trim().starts_with(heading))
        .skip(1);
    let mut in_table = false;
    for line in lines.by_ref() {
        let t = line.trim();
        if !t.starts_with('|') {
            if in_table {
                break;
            }
            continue;
        }
        in_table = true;
        let cells: Vec<&str> = t.trim_matches('|').split('|').map(str::trim).collect();
        if cells.len() < 2 || !cells[1].starts_with('`') {
            continue;
        }
        let name = cells[1].trim_matches('`').to_string();
        let (msb, lsb) = match cells[0].split_once(':') {
            Some((m, l)) => (m.parse::<usize>(), l.parse::<usize>()),
            None => (cells[0].parse::<usize>(), cells[0].parse::<usize>()),
        };
        if let (Ok(msb), Ok(lsb)) = (msb, lsb) {
            rows.push((name, lsb, msb + 1 - lsb));
        }
    }
    rows
}

/// The table as `(name, lsb, width)` rows, for comparison with [`parse_doc_table`].
pub fn table_rows(fields: &[Field]) -> Vec<(String, usize, usize)> {
    fields
        .iter()
        .map(|f| (f.name.to_string(), f.lsb, f.width))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_chain_without_gaps() {
        let a = Field::first("a", 3);
        let b = a.then("b", 64);
        assert_eq!((b.lsb, b.msb(), b.end()), (3, 66, 67));
        assert_eq!(table_end(&[a, b]), 67);
        let mut l = [0u64; 2];
        b.put(&mut l, u64::MAX);
        a.put(&mut l, 5);
        assert_eq!((a.get(&l), b.get(&l)), (5, u64::MAX));
        let mut w = 0u128;
        b.put_u128(&mut w, 1);
        assert_eq!(w, 1 << 3);
        assert_eq!(b.get_u128(w), 1);
    }

    #[test]
    fn doc_tables_parse() {
        let doc = "## T\n\ntext\n\n| bits | field |\n|---|---|\n| 2:0 | `a` |\n| 3 | `b` |\n| 7:4 | — |\n\n| 9:8 | `c` |\n";
        assert_eq!(
            parse_doc_table(doc, "## T"),
            vec![("a".to_string(), 0, 3), ("b".to_string(), 3, 1)]
        );
    }
}
