//! Peak memory of one scheme's construction per mesh face, the figure behind each scheme's
//! `bytes_per_face` (the estimate `schemes::build` checks against the memory limit).
//!
//! ```text
//! cargo run --release --example construction_memory -- hb 6 [name=value ...]
//! ```
//! builds `hb` on the unit icosphere of level 6 (81,920 faces) and prints the growth of the
//! process's peak resident memory (`VmHWM`, Linux) during the build, per face. Run one scheme
//! per process: the peak only grows. It then builds the renderer's tracer (the BVH of the surface
//! in its unit frame, default settings) and prints the peak's growth during that build per
//! BVH leaf, the figure behind the BVH's memory estimate (`render::job::check_bvh_size`).

/// The process's peak resident memory in bytes (`VmHWM` of `/proc/self/status`).
fn peak_resident_bytes() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("Linux /proc");
    let line = status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .expect("VmHWM line");
    let kib: f64 = line
        .split_whitespace()
        .nth(1)
        .and_then(|k| k.parse().ok())
        .expect("VmHWM in kB");
    kib * 1024.0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: construction_memory SCHEME LEVEL [name=value ...]";
    let (Some(scheme), Some(level)) = (args.get(1), args.get(2).and_then(|l| l.parse().ok()))
    else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let params: Vec<(String, String)> = args[3..]
        .iter()
        .filter_map(|a| a.split_once('='))
        .map(|(n, v)| (n.to_string(), v.to_string()))
        .collect();
    let sphere = smoothlab::mesh::generate::analytic::sphere(level);
    let mesh = smoothlab::testing::mesh((sphere.positions, sphere.faces));
    let before = peak_resident_bytes();
    let start = std::time::Instant::now();
    let surface = smoothlab::schemes::build(scheme, &mesh, &params).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    let per_face = (peak_resident_bytes() - before) / mesh.face_count() as f64;
    let declared = smoothlab::schemes::find(scheme).map_or(0.0, |s| s.bytes_per_face);
    println!(
        "{scheme} {params:?}: {} faces, {} patches, peak growth {per_face:.0} B/face \
         (declared {declared:.0}), {:.2} s",
        mesh.face_count(),
        surface.patches.len(),
        start.elapsed().as_secs_f64()
    );
    let before = peak_resident_bytes();
    let start = std::time::Instant::now();
    let tracer = smoothlab::render::Tracer::with_default_settings(&surface).unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    });
    let leaves = tracer.bvh.leaves.len();
    println!(
        "tracer: {leaves} leaves, peak growth {:.0} B/leaf, {:.2} s",
        (peak_resident_bytes() - before) / leaves as f64,
        start.elapsed().as_secs_f64()
    );
}
