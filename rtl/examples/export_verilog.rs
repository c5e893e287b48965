//! Writes the Verilog of every block and a top: `export_verilog DIR WIDTH [noshadow]`.
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let dir = a.get(1).map(String::as_str).unwrap_or("verilog");
    let width = a.get(2).map(|s| s.parse()).transpose()?.unwrap_or(64);
    let shadows = a.get(3).map(|s| s != "noshadow").unwrap_or(true);
    let top = pixelproc_rtl::verilog::TopConfig { width, shadows };
    for f in pixelproc_rtl::verilog::write_verilog_dir(std::path::Path::new(dir), top)? {
        println!("{}", f.display());
    }
    Ok(())
}
