//! The Rust API makes every backend the C API can (`Scene::with_backend` with a GL loader),
//! on headless Mesa (llvmpipe): GL_SELECT in a compatibility context, GL_COMPUTE in a core
//! and a compatibility one, AUTO (the CPU on a software renderer). Each GL scene answers
//! what a CPU scene answers for the same frames, and both equal the independent exact
//! oracle; the refusals (no loader, GL_SELECT on a core profile) are GlUnavailable with a
//! message.
mod common;

use common::backends::gl_support::{gl_loader, Ctx, Profile};
use common::{brute_force_exact, place, wave, TestMesh};
use glcollide::{Backend, BackendRequest, ErrorKind, GlLoader, Positions, Scene, SceneConfig};

/// A 16 x 16 sheet of quads over [0, 1]^2 at z = 0, and a 6 x 6 one turned and pushed
/// through it.
fn meshes() -> (TestMesh, TestMesh) {
    let grid = |n: u32| {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pos.push([i as f32 / n as f32, j as f32 / n as f32, 0.0]);
            }
        }
        let mut idx = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                idx.extend([v, v + 1, v + n + 2, v + n + 1]);
            }
        }
        TestMesh { pos, idx, k: 4 }
    };
    (grid(16), grid(6))
}

/// One frame: the sheet's positions and the small mesh's.
type Frame = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// Pairs (sheet polygon, small polygon) per frame, through `scene`.
fn run(scene: &mut Scene, frames: &[Frame]) -> Vec<Vec<(u32, u32)>> {
    let (a, b) = meshes();
    let ia = scene
        .create_mesh(Positions::from_points(&a.pos), &a.idx, a.k)
        .unwrap();
    let ib = scene
        .create_mesh(Positions::from_points(&b.pos), &b.idx, b.k)
        .unwrap();
    let out = frames
        .iter()
        .map(|(pa, pb)| {
            scene
                .update_positions(ia, 0, Positions::from_points(pa))
                .unwrap();
            scene
                .update_positions(ib, 0, Positions::from_points(pb))
                .unwrap();
            let c = scene.query(ia).unwrap();
            assert!(c.iter().all(|c| c.other_mesh == ib));
            c.iter()
                .map(|c| (c.reference_polygon, c.other_polygon))
                .collect()
        })
        .collect();
    scene.release_gl();
    out
}

fn frames() -> Vec<Frame> {
    let (a, b) = meshes();
    (0..4)
        .map(|f| {
            let t = f as f32 * 0.3;
            (
                wave(&a.pos, 0.02, 6.0, t),
                place(&b.pos, [0.5, 0.45, 0.01 * f as f32], 0.7 + t),
            )
        })
        .collect()
}

fn config() -> SceneConfig {
    SceneConfig {
        threads: 1,
        ..SceneConfig::default()
    }
}

/// A scene of `request` through the test's EGL loader.
fn gl_scene(request: BackendRequest) -> glcollide::Result<Scene> {
    let loader: GlLoader<'_> = &gl_loader;
    // SAFETY: the caller made a context current on this thread; the loader serves it.
    unsafe { Scene::with_backend(config(), request, Some(loader)) }
}

#[test]
fn every_backend_from_rust_gives_the_cpu_answer_and_the_oracles() {
    let frames = frames();
    let cpu = run(&mut Scene::new(config()).unwrap(), &frames);
    let (a, b) = meshes();
    for (f, (pa, pb)) in frames.iter().enumerate() {
        let ra = TestMesh {
            pos: pa.clone(),
            ..a.clone()
        };
        let rb = TestMesh {
            pos: pb.clone(),
            ..b.clone()
        };
        assert_eq!(
            cpu[f],
            brute_force_exact(&ra, &rb),
            "frame {f}: CPU vs oracle"
        );
    }
    assert!(
        cpu.iter().map(Vec::len).sum::<usize>() > 20,
        "too few contacts to mean much"
    );
    for (profile, requests) in [
        (
            Profile::Compat,
            &[BackendRequest::GlSelect, BackendRequest::GlCompute][..],
        ),
        (Profile::Core, &[BackendRequest::GlCompute][..]),
    ] {
        let _ctx = Ctx::new(profile);
        for &request in requests {
            let mut s = gl_scene(request).unwrap();
            let want = match request {
                BackendRequest::GlSelect => Backend::GlSelect,
                _ => Backend::GlCompute,
            };
            assert_eq!(s.backend(), want);
            assert_eq!(run(&mut s, &frames), cpu, "{request:?} in {profile:?}");
        }
        // AUTO on a software renderer: the CPU (faster there), the same answer.
        let mut s = gl_scene(BackendRequest::Auto).unwrap();
        assert_eq!(s.backend(), Backend::Cpu);
        assert_eq!(run(&mut s, &frames), cpu);
    }
}

#[test]
fn gl_backends_from_rust_refuse_with_a_reason() {
    // SAFETY: no loader is given.
    let e = unsafe { Scene::with_backend(config(), BackendRequest::GlCompute, None) }
        .err()
        .unwrap();
    assert_eq!(e.kind, ErrorKind::GlUnavailable);
    assert!(e.message.contains("needs a GL loader"), "{}", e.message);
    // SAFETY: no loader is given.
    let s = unsafe { Scene::with_backend(config(), BackendRequest::Auto, None) }.unwrap();
    assert_eq!(s.backend(), Backend::Cpu);
    let _ctx = Ctx::new(Profile::Core);
    let e = gl_scene(BackendRequest::GlSelect).err().unwrap();
    assert_eq!(e.kind, ErrorKind::GlUnavailable);
    assert!(e.message.contains("core-profile"), "{}", e.message);
    // A bad configuration is refused before any GL is touched.
    let bad = SceneConfig {
        epsilon: -1.0,
        ..config()
    };
    let loader: GlLoader<'_> = &gl_loader;
    // SAFETY: a context is current on this thread; the loader serves it.
    let e = unsafe { Scene::with_backend(bad, BackendRequest::GlCompute, Some(loader)) }
        .err()
        .unwrap();
    assert_eq!(e.kind, ErrorKind::InvalidArgument);
}

/// The continuous query on the GL backends: answered on the CPU from the positions they
/// keep, the CPU scene's answer to the bit (a blade through two quads between frames).
#[test]
fn the_gl_backends_answer_the_continuous_query_as_the_cpu() {
    use glcollide::Positions;
    let build = |s: &mut Scene| {
        let quads = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [0., 1., 0.],
            [0., 0., 0.5],
            [1., 0., 0.5],
            [1., 1., 0.5],
            [0., 1., 0.5],
        ];
        s.create_mesh(Positions::from_points(&quads), &[0, 1, 2, 3, 4, 5, 6, 7], 4)
            .unwrap();
        let up = [[0.4, 0.4, 1.0], [0.6, 0.4, 1.0], [0.5, 0.6, 1.5]];
        let blade = s
            .create_mesh(Positions::from_points(&up), &[0, 1, 2], 3)
            .unwrap();
        s.set_target_transform(blade, &[1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., -2.])
            .unwrap();
        s.query_continuous()
            .unwrap()
            .iter()
            .map(|i| (i.polygon_a, i.polygon_b, i.toi.to_bits(), i.at_start))
            .collect::<Vec<_>>()
    };
    let cpu = build(&mut Scene::new(config()).unwrap());
    assert_eq!(cpu.len(), 2, "{cpu:?}");
    for (profile, request) in [
        (Profile::Compat, BackendRequest::GlSelect),
        (Profile::Core, BackendRequest::GlCompute),
    ] {
        let _ctx = Ctx::new(profile);
        let mut s = gl_scene(request).unwrap();
        assert_eq!(build(&mut s), cpu, "{request:?}");
    }
}
