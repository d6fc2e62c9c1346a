//! One rule for paths in scene files and figure specs: every relative path in the file (mesh,
//! output, environment) is relative to the file's folder, wherever smoothlab runs from; a
//! command-line `-o` is relative to the working directory.

use std::path::Path;
use std::process::{Command, Output};

mod common;

fn run_in(dir: &Path, args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_smoothlab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run smoothlab");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn write_icosahedron(path: &Path) {
    let mesh = smoothlab::testing::mesh(smoothlab::mesh::generate::icosahedron());
    std::fs::write(path, mesh.to_obj("icosahedron")).expect("obj");
}

#[test]
fn scene_output_is_relative_to_the_scene_file_and_o_to_the_working_directory() {
    let dir = common::scratch("scene_paths", "scene");
    let sub = dir.join("scenes");
    std::fs::create_dir_all(&sub).expect("folder");
    write_icosahedron(&sub.join("ico.obj"));
    std::fs::write(
        sub.join("zebra.toml"),
        "mesh = \"ico.obj\"\n[scheme]\nname = \"pn\"\n[render]\nmode = \"zebra\"\n\
         size = [16, 16]\nspp = 1\noutput = \"../out/zebra\"\n",
    )
    .expect("scene");
    // Run from a folder the scene is not in: the output lands beside the scene's folder.
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(&elsewhere).expect("folder");
    run_in(&elsewhere, &["render", "../scenes/zebra.toml"]);
    assert!(dir.join("out/zebra.png").is_file(), "relative to the scene");
    assert!(dir.join("out/zebra.exr").is_file());
    assert!(
        !elsewhere.join("out").exists(),
        "not relative to the working directory"
    );
    // `-o` on the command line: relative to the working directory.
    run_in(&elsewhere, &["render", "../scenes/zebra.toml", "-o", "cli"]);
    assert!(elsewhere.join("cli.png").is_file());
    assert!(!sub.join("cli.png").exists());
}

#[test]
fn figure_output_is_relative_to_the_spec_file() {
    let dir = common::scratch("scene_paths", "figure");
    let sub = dir.join("specs");
    std::fs::create_dir_all(&sub).expect("folder");
    write_icosahedron(&sub.join("ico.obj"));
    std::fs::write(
        sub.join("fig.toml"),
        "mesh = \"ico.obj\"\noutput = \"figures/grid\"\nsize = [16, 16]\nspp = 1\nexr = false\n\
         [[schemes]]\nname = \"flat\"\n[[modes]]\nname = \"zebra\"\n",
    )
    .expect("spec");
    run_in(&dir, &["figure", "specs/fig.toml"]);
    assert!(
        sub.join("figures/grid.png").is_file(),
        "relative to the spec"
    );
    assert!(!dir.join("figures").exists());
}
