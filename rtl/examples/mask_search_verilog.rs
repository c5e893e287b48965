//! Writes the mask search unit's Verilog (both variants, 4×4 and 8×8): `mask_search_verilog DIR`.
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "verilog".into());
    for f in pixelproc_rtl::verilog::write_mask_search_verilog(std::path::Path::new(&dir))? {
        println!("{}", f.display());
    }
    Ok(())
}
