//! Every way to run a render builds its tracer in one place (`JobTracer::new`), so the
//! figure, turntable and report-thumbnail paths honour the BVH leaf budget and the BVH
//! settings (`[bvh]`) as a single render does: a budget below the estimate is refused before
//! anything is built, and which budget suffices depends on the subdivision criterion given.

mod common;

use smoothlab::mesh::Mesh;
use smoothlab::render::RenderSettings;
use smoothlab::render::{Geometry, RenderJob};
use smoothlab::schemes;
use smoothlab::surface::Surface;
use smoothlab::testing::app::FigureSpec;
use smoothlab::testing::app::render_figure;
use smoothlab::testing::app::{Animation, render_animation};
use smoothlab::testing::render::SubdivisionCriterion;
use smoothlab::testing::render::estimate_leaves;
use smoothlab::testing::report::page::{ThumbnailOptions, render_thumbnails};

/// The hb surface of the icosahedron.
fn icosahedron() -> (Mesh, Surface) {
    let mesh = smoothlab::testing::mesh(smoothlab::mesh::generate::icosahedron());
    let surface = schemes::build("hb", &mesh, &[]).expect("hb");
    (mesh, surface)
}

/// The coarsest and the finest criterion `[bvh] flatness` allows, and a leaf budget between
/// their estimates: enough for the coarse BVH, too few for the fine one.
fn criteria(surface: &Surface) -> (SubdivisionCriterion, SubdivisionCriterion, u64) {
    let coarse = SubdivisionCriterion {
        flatness: 1.0,
        ..SubdivisionCriterion::default()
    };
    let fine = SubdivisionCriterion {
        flatness: 1e-4,
        ..SubdivisionCriterion::default()
    };
    let (few, many) = (
        estimate_leaves(surface, &coarse),
        estimate_leaves(surface, &fine),
    );
    let budget = few.ceil() as u64;
    assert!(many > budget as f64, "fine {many} vs coarse {few}");
    (coarse, fine, budget)
}

fn exact(criterion: SubdivisionCriterion, max_leaves: u64) -> Geometry {
    Geometry::Exact {
        criterion,
        max_leaves,
    }
}

/// The error of a refused BVH names the budget's key.
fn assert_budget_refused<T: std::fmt::Debug>(result: smoothlab::Result<T>) {
    let err = result.expect_err("over the leaf budget").to_string();
    assert!(err.contains("bvh.max_leaves"), "{err}");
}

#[test]
fn turntables_honour_the_bvh_budget_and_settings() {
    let (mesh, surface) = icosahedron();
    let (coarse, fine, budget) = criteria(&surface);
    let dir = common::scratch("render_paths", "turntable");
    let pngs = [dir.join("t-000.png"), dir.join("t-001.png")];
    let gif = dir.join("t.gif");
    let animation = Animation::Turntable {
        frames: 2,
        axis: None,
    };
    let job = |geometry| RenderJob {
        settings: RenderSettings {
            width: 16,
            height: 16,
            spp: 1,
            progress: false,
            ..RenderSettings::default()
        },
        geometry,
        ..RenderJob::default()
    };
    let run = |geometry| render_animation(&job(geometry), &animation, &surface, &mesh, &pngs, &gif);
    assert_budget_refused(run(exact(fine, budget)));
    assert!(!pngs[0].exists(), "nothing is rendered before the check");
    let stats = run(exact(coarse, budget)).expect("coarse BVH within the budget");
    assert!(
        stats.leaves > 0 && stats.leaves <= budget,
        "{}",
        stats.leaves
    );
}

#[test]
fn figures_honour_the_bvh_section() {
    let (_, surface) = icosahedron();
    let (_, _, budget) = criteria(&surface);
    let spec = |bvh: &str| {
        format!(
            "mesh = \"icosahedron\"\noutput = \"x\"\nsize = [16, 16]\nspp = 1\n\
             [bvh]\n{bvh}\nmax_leaves = {budget}\n[[schemes]]\nname = \"hb\"\n\
             [[modes]]\nname = \"zebra\"\n[[modes]]\nname = \"curvature\"\n"
        )
    };
    let figure = |bvh: &str| {
        let job = FigureSpec::parse(&spec(bvh))
            .expect("spec")
            .job(std::path::Path::new(""))
            .expect("job");
        render_figure(&job)
    };
    assert_budget_refused(figure("flatness = 1e-4"));
    let coarse = figure("flatness = 1.0").expect("coarse BVH within the budget");
    for cell in &coarse.cells {
        assert!(cell.stats.leaves > 0 && cell.stats.leaves <= budget);
    }
    let err = FigureSpec::parse(&spec("flatness = 7.0"))
        .expect("spec")
        .job(std::path::Path::new(""))
        .expect_err("flatness out of range")
        .to_string();
    assert!(err.contains("bvh.flatness"), "{err}");
}

#[test]
fn report_thumbnails_honour_the_bvh_budget_and_settings() {
    let (mesh, surface) = icosahedron();
    let (coarse, fine, budget) = criteria(&surface);
    let dir = common::scratch("render_paths", "thumbnails");
    std::fs::create_dir_all(dir.join("thumbs")).expect("thumbs folder");
    let surfaces = vec![("hb".to_string(), surface)];
    let thumbnails = |geometry| {
        let options = ThumbnailOptions {
            size: 16,
            spp: 1,
            geometry,
        };
        render_thumbnails("icosahedron", &mesh, &surfaces, &dir, &options)
    };
    assert_budget_refused(thumbnails(exact(fine, budget)));
    thumbnails(exact(coarse, budget)).expect("coarse BVH within the budget");
}
