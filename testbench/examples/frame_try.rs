use pixelproc_sim::plan::{Effects, Overrides};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut ls = pixelproc_sim::scene::load_builtin(&args[1]).unwrap();
    let n: usize = args[2].parse().unwrap();
    if args.len() > 4 { ls.scene.width = args[3].parse().unwrap(); ls.scene.height = args[4].parse().unwrap(); }
    let fx = Effects::resolve(&ls, &Overrides::default()).unwrap();
    let spec = pixelproc_testbench::frame::FrameSpec { array_width: n, debug: true, seed: 5, gap_pct: 20, stall_pct: 20, work: "/tmp/frame_work".into(), cache: "/tmp/frame_work/vc".into() };
    let r = pixelproc_testbench::frame::run_frame_check(&ls, &fx, &spec, pixelproc_testbench::frame::FrameSim::Verilator, &mut |s| eprintln!("{s}")).unwrap();
    println!("identical {} pixels {} cycles {:?} model {:?} free {:?} unbinned {} build {:.1} cached {} run {:.2} mismatch {:?}", r.identical, r.pixels, r.cycles, r.model_cycles, r.free_cycles, r.unbinned_cycles, r.build_seconds, r.build_cached, r.run_seconds, r.mismatch);
}
