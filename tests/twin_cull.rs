//! The GPU cull passes against the CPU predicate: the same blades (read back after a frame),
//! the same uniforms and depth pyramid; the visible set per level of detail, every counter
//! and the physics update list must agree. The late pass (grass hides grass) is checked
//! the same way: its decisions and the seen flags against `reference::late_pass`, and its
//! frame against the one drawn without it. `TWIN_CULL_PNG=path` saves the frame to look at.

mod common;

use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::scene::{HeightSource, Scene};
use sward::session::Session;
use sward::sim::layout::{
    CullCounters, CHUNK_THINNED, CHUNK_THROTTLED, DRAW_BATCH, LOD_LEVELS, SEEN_NO, SEEN_YES,
};
use sward::sim::reference::thin_order::update_chunks;
use sward::sim::reference::{
    cull_blade, early_seen, grass_hidden, late_pass, list_from_last, list_order, patch_spheres,
    patch_update, wave_of, CullOutcome, Late, Pyramid,
};

/// Blades whose outcome may differ between GPU and CPU: only those within float rounding
/// of a threshold. Allowed: 1 in 1000, at least 2.
fn allowed_mismatch(n: usize) -> usize {
    (n / 1000).max(2)
}

const SIZE: (u32, u32) = (96, 64);

/// `blades`: a flat field of that many blades, or `None` for the scene's own terrain. The
/// early pass only: the pyramid read back after the frame must be the one it tested
/// against, so grass occlusion (which rebuilds it) is off here.
fn run(
    mut scene: Scene,
    blades: Option<usize>,
    camera: impl Fn(&Session) -> CameraView,
) -> CullCounters {
    scene.culling.grass_occlusion = false;
    // Multisampled (the default, said here because it matters): the pyramid then keeps
    // its own level 0, so reading it back after the frame gives what the cull saw (with
    // one sample its level 0 is the frame's depth, which the draw fills after the cull).
    scene.render.msaa = 4;
    let gpu = common::gpu();
    let session = Session::new(scene, blades, Some(&gpu)).expect("field");
    let camera = camera(&session);
    let target = Target::new(&gpu, SIZE.0, SIZE.1).expect("target");
    let mut r = common::world(&gpu, &session);
    sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
    let counters = r.cull.read_counters(&gpu).expect("counters");
    if let Ok(path) = std::env::var("TWIN_CULL_PNG") {
        let image = target.read_image(&gpu).expect("image");
        sward::output::save_png(std::path::Path::new(&path), &image).expect("png");
    }
    let mut levels = r
        .cull
        .read_visible_levels(&gpu, &r.buffers)
        .expect("visible");
    let cp = *r.last_cull_params();
    for l in &levels {
        assert_in_list_order(l, &cp, &session.field.patches);
    }
    for l in &mut levels {
        l.sort_unstable();
    }
    let (blades, states) = r.buffers.read(&gpu).expect("blades");
    let pyramid_levels: Option<Vec<Vec<f32>>> = (cp.hiz[3] == 1).then(|| read_pyramid(&gpu, &r));
    let pyramid = pyramid_levels.as_ref().map(|levels| Pyramid {
        levels,
        width: SIZE.0,
        height: SIZE.1,
    });

    let mut cpu = CullCounters::default();
    let mut cpu_levels: [Vec<u32>; LOD_LEVELS] = Default::default();
    for (i, b) in blades.iter().enumerate() {
        let patch = &session.field.patches[i / session.field.patch_size as usize];
        match cull_blade(i as u32, b, patch, &cp, pyramid.as_ref()) {
            CullOutcome::Drawn(k) => cpu_levels[k as usize].push(i as u32),
            CullOutcome::Patch => cpu.culled_patch += 1,
            CullOutcome::Orientation => cpu.culled_orientation += 1,
            CullOutcome::Frustum => cpu.culled_frustum += 1,
            CullOutcome::Distance => cpu.culled_distance += 1,
            CullOutcome::Occlusion => cpu.culled_occlusion += 1,
            CullOutcome::Empty => {}
        }
    }
    let mut differ = 0;
    for (gpu_list, cpu_list) in levels.iter().zip(&cpu_levels) {
        differ += gpu_list
            .iter()
            .filter(|i| cpu_list.binary_search(i).is_err())
            .count();
        differ += cpu_list
            .iter()
            .filter(|i| gpu_list.binary_search(i).is_err())
            .count();
    }
    println!(
        "cull twin: gpu drawn {:?} / cpu drawn {:?}, gpu culled {:?} / cpu culled {:?}, visible sets differ in {differ}",
        counters.per_level(),
        cpu_levels.each_ref().map(|l| l.len()),
        [counters.culled_patch, counters.culled_orientation, counters.culled_frustum, counters.culled_distance, counters.culled_occlusion],
        [cpu.culled_patch, cpu.culled_orientation, cpu.culled_frustum, cpu.culled_distance, cpu.culled_occlusion],
    );
    for (k, (draw, list)) in counters.draws.iter().zip(&levels).enumerate() {
        // Blades in whole batches: the instance count is the blade count rounded up.
        assert_eq!(counters.blades[k] as usize, list.len());
        assert_eq!(draw.instance_count, counters.blades[k].div_ceil(DRAW_BATCH));
        assert_eq!(draw.first_index, cp.lod_first_index[k]);
        assert_eq!(draw.index_count, cp.lod_index_count[k]);
    }
    assert_eq!(
        counters.drawn() + counters.culled(),
        blades.len() as u32,
        "every blade is counted once"
    );
    let n = blades.len();
    assert!(differ <= allowed_mismatch(n), "{differ} blades differ");
    let close =
        |a: u32, b: u32| (a as i64 - b as i64).unsigned_abs() as usize <= allowed_mismatch(n);
    assert!(close(counters.culled_patch, cpu.culled_patch));
    assert!(close(counters.culled_orientation, cpu.culled_orientation));
    assert!(close(counters.culled_frustum, cpu.culled_frustum));
    assert!(close(counters.culled_distance, cpu.culled_distance));
    assert!(close(counters.culled_occlusion, cpu.culled_occlusion));

    // The far levels' shading waves: the gusts' bend over the blades drawn early at the
    // edge of the blades' reach (`count_wave`), summed in 1/1024ths. The visible sets may
    // differ in a few blades, and a blade's value may round the other way by one.
    let (mut wave_sum, mut wave_blades) = (0u64, 0u32);
    for &i in cpu_levels.iter().flatten() {
        if let Some(w) = wave_of(&blades[i as usize], &states[i as usize], &cp) {
            wave_sum += u64::from(w);
            wave_blades += 1;
        }
    }
    println!(
        "wave twin: gpu {} over {} blades, cpu {wave_sum} over {wave_blades}",
        counters.wave_sum, counters.wave_blades
    );
    assert!(close(counters.wave_blades, wave_blades));
    let slack = 1024 * allowed_mismatch(n) as u64 + u64::from(wave_blades);
    assert!(
        (u64::from(counters.wave_sum)).abs_diff(wave_sum) <= slack,
        "wave sum {} against {wave_sum}",
        counters.wave_sum
    );

    // The physics list: which patches step this frame, and which of them throttled; and
    // the broad phase's sphere list of each stepped patch.
    let spheres = r.frame_spheres();
    let gpu_lists = r
        .cull
        .read_patch_spheres(&gpu, &r.buffers)
        .expect("patch spheres");
    let mut stepped = 0;
    let mut throttled = 0;
    let mut pairs = 0;
    // The update's chunks, of patches with a collider near and of the others.
    let mut chunks = [Vec::new(), Vec::new()];
    for (p, patch) in session.field.patches.iter().enumerate() {
        let Some(slow) = patch_update(p as u32, patch, &cp) else {
            assert!(update_chunks(p as u32, patch, &cp).is_empty());
            continue;
        };
        stepped += 1;
        throttled += slow as u32;
        let list = patch_spheres(patch, &cp, &spheres);
        chunks[usize::from(list.is_empty())].extend(update_chunks(p as u32, patch, &cp));
        pairs += list.len() as u32;
        assert_eq!(gpu_lists[p], Some(list), "patch {p}: broad-phase list");
    }
    assert_eq!(counters.updated_patches, stepped);
    assert_eq!(counters.throttled_patches, throttled);
    // The update lists: which chunks of 64 blades (in class order) step, at which rate, and
    // with collisions or without.
    chunks.iter_mut().for_each(|c| c.sort_unstable());
    let gpu_chunks = r
        .cull
        .read_update_lists(&gpu, &r.buffers)
        .expect("update lists");
    assert_eq!(gpu_chunks, chunks, "update lists");
    let slow = |c: &&u32| **c & (CHUNK_THROTTLED | CHUNK_THINNED) != 0;
    let all = chunks.concat();
    assert_eq!(counters.updated_chunks as usize, all.len());
    assert_eq!(
        counters.throttled_chunks as usize,
        all.iter().filter(slow).count()
    );
    assert_eq!(counters.collide_chunks as usize, chunks[0].len());
    assert_eq!(counters.free_chunks as usize, chunks[1].len());
    assert_eq!(counters.patch_sphere_pairs, pairs);
    counters
}

fn camera(eye: glam::Vec3, target: glam::Vec3) -> CameraView {
    CameraView {
        eye,
        target,
        fov_y: 50.0,
        near: 0.05,
        far: 100.0,
    }
}

/// The list starts on the camera's side of the field: from the first patch or from the
/// last (`list_from_last`) as the view looks along the patches' order or against it, each
/// list checked against the twin's order (in `run`). Seen from one side and then the
/// other, both orders occur.
#[test]
fn the_list_starts_on_the_cameras_side() {
    let orders = std::cell::Cell::new((false, false));
    for (eye, target) in [
        (
            glam::Vec3::new(-3.0, 1.2, -3.0),
            glam::Vec3::new(2.0, 0.0, 2.0),
        ),
        (
            glam::Vec3::new(3.0, 1.2, 3.0),
            glam::Vec3::new(-2.0, 0.0, -2.0),
        ),
    ] {
        let c = run(Scene::default(), Some(8192), |s| {
            let p = &s.field.patches;
            let centre = |b: &sward::sim::layout::PatchBox| {
                glam::Vec2::new(b.min[0] + b.max[0], b.min[2] + b.max[2])
            };
            let along = centre(&p[p.len() - 1]) - centre(&p[0]);
            let view = glam::Vec2::new(target.x - eye.x, target.z - eye.z);
            let (first, last) = orders.get();
            let from_last = view.dot(along) < 0.0;
            orders.set((first || !from_last, last || from_last));
            camera(eye, target)
        });
        assert!(c.blades.iter().sum::<u32>() > 0, "{c:?}");
    }
    assert_eq!(orders.get(), (true, true), "both orders were listed");
}

#[test]
fn gpu_cull_matches_cpu_predicate_with_every_test_on() {
    let mut scene = Scene::default();
    scene.culling.distance = true;
    scene.culling.max_distance = 6.0;
    scene.culling.distance_levels = 4;
    scene.culling.physics_radius = 1.0;
    // Small thresholds for a 64-pixel-high target, so all three levels occur.
    scene.culling.lod_near_px = 20.0;
    scene.culling.lod_far_px = 8.0;
    scene.field.patch_size = 256;
    // Spheres along the view for the broad phase: some patches list a few, none all.
    scene.colliders = (0..12)
        .map(|k| common::rolling_sphere(-3.0 + k as f32, 0.3, 0.35, 0.0))
        .collect();
    // A camera in the middle of the field looking along +x: the patches behind it fail the
    // box test, blades at the sides the frustum test, far ones the distance test.
    let c = run(scene, Some(8192), |_| {
        camera(
            glam::Vec3::new(0.0, 1.2, 0.0),
            glam::Vec3::new(4.0, 0.0, 1.0),
        )
    });
    // Each test must have culled something here, or this test checks less than it says.
    assert!(
        c.culled_patch > 0
            && c.culled_orientation > 0
            && c.culled_frustum > 0
            && c.culled_distance > 0,
        "{c:?}"
    );
    assert!(c.per_level().iter().all(|&n| n > 0), "{c:?}");
    assert!(c.throttled_patches > 0, "{c:?}");
    assert!(
        c.patch_sphere_pairs > 0 && c.spheres_considered() > 0,
        "{c:?}"
    );
    assert!(c.spheres_considered() <= 12, "{c:?}");
    // Both update lists hold chunks: patches by the spheres collide, the others do not.
    assert!(c.collide_chunks > 0 && c.free_chunks > 0, "{c:?}");
}

#[test]
fn the_update_steps_the_thinned_classes_in_turn_as_the_cpu_lists_them() {
    // Seven distance levels in patches of 256 blades: a patch's local classes are not its
    // index classes (256 mod 7 = 4), so the kept classes wrap around the class order. The
    // camera low over the field, so the patches in view span every distance level.
    let mut scene = Scene::default();
    scene.culling.distance = true;
    scene.culling.max_distance = 7.0;
    scene.culling.distance_levels = 7;
    scene.culling.physics_radius = 0.5;
    scene.field.patch_size = 256;
    scene.colliders.clear();
    let c = run(scene, Some(16384), |_| {
        camera(
            glam::Vec3::new(-4.0, 1.0, 0.0),
            glam::Vec3::new(4.0, 0.0, 0.5),
        )
    });
    // Chunks of patches stepped every frame go at the throttled rate: more than the
    // throttled patches' own chunks.
    let per_patch = 256 / sward::sim::layout::UPDATE_CHUNK;
    assert!(
        c.throttled_chunks > c.throttled_patches * per_patch,
        "{c:?}"
    );
    assert!(c.updated_chunks < c.updated_patches * per_patch, "{c:?}");
}

#[test]
fn hills_hide_the_grass_behind_them() {
    // Steep hills and a camera low in a valley looking along the ground: the occlusion test
    // (patch boxes against the pyramid, then blades) must cull grass behind the hills, as
    // the CPU twin does.
    let mut scene = Scene::default();
    scene.terrain.height = HeightSource::Noise {
        seed: 3,
        amplitude: 5.0,
        wavelength: 8.0,
        octaves: 2,
    };
    scene.terrain.size = 24.0;
    scene.terrain.resolution = 97;
    scene.field.density = 15.0;
    scene.field.patch_size = 64;
    scene.culling.max_distance = 100.0;
    let c = run(scene, None, |s| {
        let ground = |x: f32, z: f32| s.terrain.height(x, z);
        // From the lowest point near the field's edge, level, across the field.
        let x = (0..24)
            .map(|i| -11.5 + i as f32 * 0.25)
            .min_by(|a, b| ground(*a, 0.0).total_cmp(&ground(*b, 0.0)))
            .expect("samples");
        let eye = glam::Vec3::new(x, ground(x, 0.0) + 1.0, 0.0);
        let target = eye + glam::Vec3::new(10.0, 0.0, 0.0);
        camera(eye, target)
    });
    assert!(c.culled_occlusion > 0, "{c:?}");
    assert!(c.culled_occlusion_patch > 0, "{c:?}");
}

#[test]
fn switching_every_test_off_draws_every_blade() {
    let mut scene = Scene::default();
    scene.culling.patches = false;
    scene.culling.orientation = false;
    scene.culling.frustum = false;
    scene.culling.distance = false;
    scene.culling.occlusion = false;
    let c = run(scene, Some(8192), |_| {
        camera(
            glam::Vec3::new(-4.0, 1.2, 0.0),
            glam::Vec3::new(0.0, 0.0, 1.0),
        )
    });
    assert_eq!(c.culled(), 0);
}

/// The whole pyramid of the last frame, read back.
fn read_pyramid(gpu: &sward::gpu::Gpu, r: &sward::render::Renderer) -> Vec<Vec<f32>> {
    r.read_pyramid(gpu)
        .expect("a pyramid when occlusion ran")
        .expect("pyramid levels")
}

#[test]
fn grass_hides_grass_and_the_late_pass_matches_the_cpu() {
    // Dense grass on flat ground seen at a grazing angle: the grass near the camera hides
    // much of what is behind it. Flat ground and no colliders, so the opaque pyramid hides
    // no blade and the early pass is `cull_blade` without occlusion.
    const BIG: (u32, u32) = (192, 128);
    let mut scene = Scene::default();
    scene.terrain.height = HeightSource::Flat;
    scene.colliders.clear();
    scene.field.patch_size = 64;
    scene.culling.distance = false;
    // Multisampled: the pyramid keeps its own level 0 (see `run`).
    scene.render.msaa = 4;
    let gpu = common::gpu();
    let session = Session::new(scene, Some(16384), Some(&gpu)).expect("field");
    let first = camera(
        glam::Vec3::new(-6.0, 0.8, -1.0),
        glam::Vec3::new(4.0, 0.0, 1.0),
    );
    // Frame 3 looks a little further right: some blades seen in frame 1 stay, others come
    // into view and wait for the late test.
    let second = camera(
        glam::Vec3::new(-6.0, 0.8, -0.8),
        glam::Vec3::new(4.0, 0.0, 2.5),
    );
    let target = Target::new(&gpu, BIG.0, BIG.1).expect("target");
    let draw_two = |grass: bool| {
        let mut s = session.scene.clone();
        s.culling.grass_occlusion = grass;
        let r = sward::render::Renderer::new(
            &gpu,
            s,
            session.terrain.clone(),
            &session.field,
            sward::render::target::COLOR_FORMAT,
        )
        .expect("renderer");
        let format = sward::render::target::COLOR_FORMAT;
        let mut r = sward::embed::GrassRenderer::wrap_world(&gpu, r, format);
        let frame = |r: &mut sward::embed::GrassRenderer, c: &CameraView| {
            sward::commands::world_frame(&gpu, r, 1.0 / 30.0, *c, &target).expect("frame")
        };
        // Frame 1 sees every blade (nothing was seen before it); frame 2 finds the ones
        // the others hide; frame 3 culls those.
        frame(&mut r, &first);
        frame(&mut r, &first);
        let seen_before = r.buffers.read_seen(&gpu).expect("seen");
        frame(&mut r, &second);
        (r, seen_before)
    };

    let (r, seen_before) = draw_two(true);
    let with_grass = target.read_image(&gpu).expect("image");
    let c = r.cull.read_counters(&gpu).expect("counters");
    let seen_after = r.buffers.read_seen(&gpu).expect("seen");
    let (blades, _) = r.buffers.read(&gpu).expect("blades");
    let levels = r
        .cull
        .read_visible_levels(&gpu, &r.buffers)
        .expect("visible");
    let cp = *r.last_cull_params();
    let pyramid_levels = read_pyramid(&gpu, &r);
    let pyramid = Pyramid {
        levels: &pyramid_levels,
        width: BIG.0,
        height: BIG.1,
    };
    // The opaque pyramid hid nothing: every occlusion cull is the late pass's.
    assert_eq!(c.culled_occlusion_patch, 0, "{c:?}");
    assert_eq!(c.culled_occlusion, c.culled_occlusion_grass, "{c:?}");

    // The CPU replay: early outcome without occlusion, the seen state machine, the late
    // test against the pyramid read back (opaque objects + early grass).
    let mut early: [Vec<u32>; LOD_LEVELS] = Default::default();
    let mut late: [Vec<u32>; LOD_LEVELS] = Default::default();
    let mut cpu_seen = seen_before.clone();
    let mut hidden = 0u32;
    let mut rechecked_hidden = 0u32;
    for (i, b) in blades.iter().enumerate() {
        let patch = &session.field.patches[i / session.field.patch_size as usize];
        let outcome = cull_blade(i as u32, b, patch, &cp, None);
        if outcome == CullOutcome::Patch {
            continue;
        }
        let (state, drawn_early) = early_seen(outcome, seen_before[i]);
        let level = match outcome {
            CullOutcome::Drawn(k) => k as usize,
            _ => 0,
        };
        if drawn_early {
            early[level].push(i as u32);
        }
        cpu_seen[i] = match late_pass(state, grass_hidden(b, &cp, &pyramid)) {
            Late::Untouched => state,
            Late::Rechecked { seen } => {
                rechecked_hidden += u32::from(!seen);
                if seen {
                    SEEN_YES
                } else {
                    SEEN_NO
                }
            }
            Late::Hidden => {
                hidden += 1;
                SEEN_NO
            }
            Late::Drawn => {
                late[level].push(i as u32);
                SEEN_YES
            }
        };
    }
    let n = blades.len();
    let mut differ = 0;
    for k in 0..LOD_LEVELS {
        let split = c.blades[k] as usize;
        assert_eq!(c.draws[k].instance_count, c.blades[k].div_ceil(DRAW_BATCH));
        assert_eq!(
            c.late_draws[k].instance_count,
            c.late_blades[k].div_ceil(DRAW_BATCH)
        );
        let (mut gpu_early, mut gpu_late) =
            (levels[k][..split].to_vec(), levels[k][split..].to_vec());
        assert_in_list_order(&gpu_early, &cp, &session.field.patches);
        assert_in_list_order(&gpu_late, &cp, &session.field.patches);
        gpu_early.sort_unstable();
        gpu_late.sort_unstable();
        differ += symmetric_difference(&gpu_early, &early[k]);
        differ += symmetric_difference(&gpu_late, &late[k]);
    }
    let seen_differ = seen_after
        .iter()
        .zip(&cpu_seen)
        .filter(|(a, b)| a != b)
        .count();
    println!(
        "late twin: early {:?} late {:?} hidden {} (cpu {hidden}), early blades hidden now {rechecked_hidden}, lists differ in {differ}, seen flags in {seen_differ}",
        early.each_ref().map(|l| l.len()),
        late.each_ref().map(|l| l.len()),
        c.culled_occlusion_grass,
    );
    // Every case of the state machine occurred, or this test checks less than it says.
    assert!(early.iter().any(|l| !l.is_empty()), "nothing drawn early");
    assert!(late.iter().any(|l| !l.is_empty()), "nothing drawn late");
    assert!(
        hidden > n as u32 / 20,
        "grass hid only {hidden} of {n} blades"
    );
    assert!(rechecked_hidden > 0, "no early blade was found hidden");
    assert!(differ <= allowed_mismatch(n), "{differ} blades differ");
    assert!(
        seen_differ <= allowed_mismatch(n),
        "{seen_differ} seen flags differ"
    );
    let close = (c.culled_occlusion_grass as i64 - hidden as i64).unsigned_abs() as usize;
    assert!(close <= allowed_mismatch(n));
    assert_eq!(
        c.drawn() + c.culled(),
        n as u32,
        "every blade is counted once"
    );

    // What the late pass culls is hidden: the frame matches the one drawn without it.
    let (_, _) = draw_two(false);
    let without = target.read_image(&gpu).expect("image");
    let d = sward::compare::compare(&with_grass, &without).expect("same size");
    println!(
        "late twin: frame with grass occlusion vs without: mean {:.3}, failing {:.3} %",
        d.mean,
        d.failing * 100.0
    );
    assert!(
        d.within_tolerance(),
        "mean {} failing {}",
        d.mean,
        d.failing
    );
}

/// A visible list as the GPU wrote it is in `list_order` (patch, then class order; the
/// patches from the last where the view looks that way, `list_from_last`), not in the order
/// its workgroups happened to run: two blades at one depth are then drawn in the same order
/// every frame, and the frame is the same every time.
fn assert_in_list_order(
    list: &[u32],
    cp: &sward::sim::layout::CullParams,
    patches: &[sward::sim::layout::PatchBox],
) {
    let from_last = list_from_last(cp, &patches[0], &patches[patches.len() - 1]);
    let key = |i: &u32| list_order(*i, cp, from_last);
    if let Some(w) = list.windows(2).find(|w| key(&w[0]) >= key(&w[1])) {
        panic!(
            "blade {} ({:?}) listed before blade {} ({:?}), {} blades",
            w[0],
            key(&w[0]),
            w[1],
            key(&w[1]),
            list.len()
        );
    }
}

/// Elements in exactly one of two sorted lists.
fn symmetric_difference(a: &[u32], b: &[u32]) -> usize {
    a.iter().filter(|i| b.binary_search(i).is_err()).count()
        + b.iter().filter(|i| a.binary_search(i).is_err()).count()
}
