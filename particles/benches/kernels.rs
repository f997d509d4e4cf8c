//! Criterion benchmarks of the DEM kernels: one contact-law evaluation per law, the
//! neighbour-list build, and one full time step of a small shaken tray (3D and pinned 2D).
//!
//! Run with `cargo bench -p particles --bench kernels`.

#[path = "../tests/common/mod.rs"]
mod common;

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use particles::contact::{self, ContactGeometry, ContactLaw, NormalLaw, RollingLaw, TangentialLaw};
use particles::neighbor::{NeighborList, NeighborSearch};
use particles::prepare::initial_state;
use particles::scene::{Scene, TimeStep};
use particles::sim::Simulation;
use particles::time_step;
use particles::tray;
use particles::Vec3;

fn geometry() -> ContactGeometry {
    use particles::contact::geometry::Sphere;
    ContactGeometry::pair(
        Sphere {
            x: Vec3::zeros(),
            v: Vec3::new(0.1, -0.02, 0.03),
            w: Vec3::new(10.0, -5.0, 2.0),
            r: 4e-4,
        },
        Sphere {
            x: Vec3::new(6.9e-4, 0.5e-4, -0.2e-4),
            v: Vec3::new(-0.05, 0.01, 0.0),
            w: Vec3::new(-3.0, 4.0, 7.0),
            r: 3e-4,
        },
    )
    .expect("the grains overlap")
}

fn contact_laws(c: &mut Criterion) {
    let hertz = NormalLaw::hertz(1e6 / 0.91, 8.5e-6);
    let laws = [
        (
            "hertz",
            ContactLaw {
                normal: hertz,
                tangential: TangentialLaw::None,
                rolling: RollingLaw::None,
            },
        ),
        (
            "hertz+haff-werner+rolling",
            ContactLaw {
                normal: hertz,
                tangential: TangentialLaw::HaffWerner { gamma_t: 0.007, mu: 0.7 },
                rolling: RollingLaw::BrilliantovPoschel { mu_r: 8.5e-6 },
            },
        ),
        (
            "hertz+cundall-strack",
            ContactLaw {
                normal: hertz,
                tangential: TangentialLaw::CundallStrack { kt: 300.0, mu: 0.7 },
                rolling: RollingLaw::None,
            },
        ),
        (
            "linear",
            ContactLaw {
                normal: NormalLaw::Linear { kn: 500.0, gamma_n: 1e-3 },
                tangential: TangentialLaw::None,
                rolling: RollingLaw::None,
            },
        ),
    ];
    let g = geometry();
    let mut group = c.benchmark_group("contact");
    for (name, law) in laws {
        group.bench_function(name, |b| {
            let mut h = contact::History::default();
            b.iter(|| contact::evaluate(black_box(&law), black_box(&g), &mut h, 1e-6))
        });
    }
    group.finish();
}

/// 400 grains at the thesis packing on 40 mm x 20 mm, jumping or pinned to the floor.
fn scene(jumping: bool) -> Scene {
    common::tray_scene(0.04, 0.02, 400, TimeStep::Seconds(8e-6), 1, |s| {
        s.run.duration = 1.0;
        s.toggles.jumping = jumping;
    })
}

fn tray_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("tray-400");
    for (name, jumping) in [("step 3D", true), ("step pinned 2D", false)] {
        let scene = scene(jumping);
        let setup = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).expect("valid setup")).expect("valid setup");
        let mut sim = Simulation::new(setup, initial_state(&scene).expect("valid sample")).expect("valid start");
        group.bench_function(name, |b| b.iter(|| sim.step().expect("the tray runs")));
    }
    let scene = scene(true);
    let state = initial_state(&scene).expect("valid sample");
    let boundary = tray::setup(&scene, tray::drive(&scene), time_step::for_scene(&scene).expect("valid setup"))
        .expect("valid setup")
        .boundary;
    for skin in [0.0, 0.2e-3, 0.5e-3] {
        let search = NeighborSearch::verlet(skin);
        group.bench_function(format!("neighbour build, skin {skin:e} m"), |b| {
            let mut list = NeighborList::default();
            b.iter(|| list.build(&search, black_box(&state.pos), &state.radius, &boundary))
        });
    }
    group.finish();
}

// No HTML plots: plotters' system-font backend has no font on a headless machine (the suite
// draws its own plots with the shipped font in `analysis::plot`).
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = contact_laws, tray_step
}
criterion_main!(benches);
