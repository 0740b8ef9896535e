//! GPU skinning (issue 29, point 1; `render::skinning`, `skin.wgsl`) against its CPU twin
//! (`mesh::skin::SkinnedMesh::skin` and `skin_normals`): sward's walker
//! (`assets/models/walker.gltf`) placed in a scene with `animation: Some("walk")`, rendered
//! for some frames; the object's vertex buffer read back holds the walk's pose at the
//! renderer's time. Measured on lavapipe: positions within 2.4e-7 m, normals within 1.2e-7
//! of the twin's; bounds 1e-5 m and 1e-5.

mod common;

use glam::Vec3;
use sward::embed::GrassRenderer;
use sward::mesh::skin::SkinnedMesh;
use sward::render::camera::CameraView;
use sward::render::target::Target;
use sward::render::Renderer;
use sward::session::Session;

/// A session, renderer, small target and the scene's camera for `sets` over the default
/// scene.
fn setup(
    gpu: &sward::gpu::Gpu,
    sets: &[String],
    size: (u32, u32),
) -> (Session, GrassRenderer, Target, CameraView) {
    let scene = sward::commands::load(None, sets).expect("scene");
    let session = Session::new(scene, None, Some(gpu)).expect("session");
    let r = common::world(gpu, &session);
    let target = Target::new(gpu, size.0, size.1).expect("target");
    let camera = CameraView::from_scene(&session.scene.camera);
    (session, r, target, camera)
}

fn walker() -> String {
    format!("{}/assets/models/walker.gltf", env!("CARGO_MANIFEST_DIR"))
}

/// The flat 12 m field of the trail tests with `object` (the walker's scene entry) as its
/// only object.
fn flat_walk_sets(object: String) -> Vec<String> {
    vec![
        "terrain.height=Flat".to_string(),
        "terrain.size=12".to_string(),
        "field.tile_size=0".to_string(),
        "field.density=120".to_string(),
        "field.height=(min: 0.4, max: 0.6)".to_string(),
        "colliders=[]".to_string(),
        "wind.directional=None".to_string(),
        format!("objects=[{object}]"),
    ]
}

/// Runs 150 frames of 1/30 s (`before` runs ahead of each) and returns each blade's largest
/// η over them (read every third frame: a pressed blade's η decays in a fraction of a
/// second).
fn most_eta_over_150_frames(
    gpu: &sward::gpu::Gpu,
    r: &mut GrassRenderer,
    target: &Target,
    camera: &CameraView,
    mut before: impl FnMut(&mut Renderer),
) -> Vec<f32> {
    let mut most_eta: Vec<f32> = Vec::new();
    for f in 0..150 {
        before(r);
        sward::commands::world_frame(gpu, r, 1.0 / 30.0, *camera, target).expect("frame");
        if f % 3 == 2 {
            let (_, states) = r.buffers.read(gpu).expect("blades");
            most_eta.resize(states.len(), 0.0);
            for (m, s) in most_eta.iter_mut().zip(&states) {
                *m = m.max(s.rest_eta[3]);
            }
        }
    }
    gpu.check_errors().expect("no GPU error");
    most_eta
}

#[test]
fn the_gpu_poses_the_walker_as_its_cpu_twin() {
    let gpu = common::gpu();
    let sets = vec![
        "field.density=5".to_string(),
        "terrain.size=16".to_string(),
        format!(
            "objects=[(mesh: {:?}, animation: Some(\"walk\"), color: (0.8, 0.3, 0.2))]",
            walker()
        ),
    ];
    let size = (64, 36);
    let (session, mut r, target, camera) = setup(&gpu, &sets, size);
    for _ in 0..7 {
        sward::commands::world_frame(&gpu, &mut r, 1.0 / 30.0, camera, &target).expect("frame");
    }
    gpu.check_errors().expect("no GPU error");
    let posed = r.read_object_vertices(&gpu, 0).expect("read back");
    let (mesh, walk) = session.skins[0].clone().expect("the walker is skinned");
    let joints = mesh.joint_matrices(Some(walk), r.time);
    let positions = mesh.skin(&joints);
    let normals = mesh.skin_normals(&joints);
    assert_eq!(posed.len(), positions.len());
    let (mut worst_p, mut worst_n, mut moved) = (0f32, 0f32, 0f32);
    for (((g, p), n), rest) in posed
        .iter()
        .zip(&positions)
        .zip(&normals)
        .zip(&mesh.positions)
    {
        for k in 0..3 {
            worst_p = worst_p.max((g[k] - p[k]).abs());
            worst_n = worst_n.max((g[3 + k] - n[k]).abs());
            moved = moved.max((p[k] - rest[k]).abs());
        }
    }
    eprintln!(
        "t = {:.3} s: positions within {worst_p:.2e} m, normals within {worst_n:.2e}; \
         the pose moves vertices up to {moved:.3} m from the bind pose",
        r.time
    );
    assert!(moved > 0.1, "the walk did not move the figure ({moved} m)");
    assert!(worst_p < 1e-5, "positions off by {worst_p} m");
    assert!(worst_n < 1e-5, "normals off by {worst_n}");
}

#[test]
fn an_animation_the_file_lacks_is_named() {
    let sets = vec![format!(
        "objects=[(mesh: {:?}, animation: Some(\"run\"))]",
        walker()
    )];
    let scene = sward::commands::load(None, &sets).expect("scene");
    let e = match Session::new(scene, None, None) {
        Ok(_) => panic!("a missing animation was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("objects[0].animation") && e.contains("\"walk\""),
        "{e}"
    );
    // Joint colliders need the skeleton an animation brings.
    let sets = vec![format!(
        "objects=[(mesh: {:?}, collider: Joints)]",
        walker()
    )];
    let e = match sward::commands::load(None, &sets) {
        Ok(_) => panic!("Joints without an animation was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        e.contains("objects[0].collider") && e.contains("Joints needs a skeleton"),
        "{e}"
    );
    // Read as a skinned mesh the file itself is fine.
    assert!(SkinnedMesh::load(std::path::Path::new(&walker())).is_ok());
}

/// The walker's collider spheres follow its joints (`mesh::pack::SphereRig`): the lowest
/// spheres, on the feet, swing forward and back with the walk, so the legs push the grass.
#[test]
fn the_collider_spheres_swing_with_the_legs() {
    let sets = vec![format!(
        "objects=[(mesh: {:?}, animation: Some(\"walk\"), collider: Spheres((count: 48)))]",
        walker()
    )];
    let scene = sward::commands::load(None, &sets).expect("scene");
    let session = Session::new(scene, None, None).expect("session");
    let rig = session.packings[0]
        .as_ref()
        .and_then(|p| p.rig.as_ref())
        .expect("the packing is rigged");
    assert_eq!(
        rig.joint_of.len(),
        session.packings[0].as_ref().unwrap().spheres.len()
    );
    let at = |t: f32| {
        sward::sim::colliders::object_spheres_at(
            &session.scene.objects,
            &session.packings,
            &session.terrain,
            t,
        )
    };
    let (a, b) = (at(0.25), at(0.75));
    // The spheres low on the legs (centre below 0.3 m above the figure's origin).
    let ground = session.terrain.height(0.0, 0.0);
    let swing: Vec<f32> = a
        .iter()
        .zip(&b)
        .filter(|(s, _)| s[1] - ground < 0.3)
        .map(|(s, t)| (s[2] - t[2]).abs())
        .collect();
    let most = swing.iter().copied().fold(0.0, f32::max);
    eprintln!(
        "{} low spheres; the most a foot's sphere moves in z: {most:.3} m",
        swing.len()
    );
    assert!(!swing.is_empty() && most > 0.3, "{swing:?}");
    // The head's spheres stay (within the hips' bob).
    let high = a
        .iter()
        .zip(&b)
        .filter(|(s, _)| s[1] - ground > 1.6)
        .map(|(s, t)| (Vec3::from_slice(&s[..3]) - Vec3::from_slice(&t[..3])).length())
        .fold(0.0, f32::max);
    assert!(high < 0.1, "the head moved {high} m");
}

/// Along `walk.ron`'s loop over the prairie's hills the figure's lowest point (its standing
/// foot) stays on the terrain: at 60 times over a lap the gap between the lowest skinned
/// vertex and the ground under it stays within 0.12 m (measured: 0.072 m on lavapipe),
/// and with the stride the walk keeps pace with the path (two steps per 1.76 m).
#[test]
fn the_walkers_feet_stay_on_the_hills() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/walk.ron");
    let scene = sward::commands::load(Some(&path), &[]).expect("walk.ron");
    let session = Session::new(scene, None, None).expect("session");
    let object = &session.scene.objects[0];
    let (mesh, walk) = session.skins[0].clone().expect("skinned");
    let duration = mesh.animations[walk].duration;
    let sward::scene::Motion::Path { speed, .. } = object.motion.clone() else {
        panic!("the walker follows a path")
    };
    // One stride of ground is one cycle of the walk.
    let t = object.stride / speed;
    let cycle = sward::sim::colliders::animation_time(object, duration, t);
    assert!((cycle - duration).abs() < 1e-4, "{cycle}");
    let mut worst: f32 = 0.0;
    for k in 0..60 {
        let time = k as f32 * 0.37;
        let model = sward::sim::colliders::object_transform(object, &session.terrain, time);
        let at = sward::sim::colliders::animation_time(object, duration, time);
        let posed = mesh.skin(&mesh.joint_matrices(Some(walk), at));
        let gap = posed
            .iter()
            .map(|p| {
                let w = model.transform_point3(Vec3::from(*p));
                w.y - session.terrain.height(w.x, w.z)
            })
            .fold(f32::MAX, f32::min);
        worst = worst.max(gap.abs());
    }
    eprintln!("the lowest foot is at most {worst:.3} m off the ground along the loop");
    assert!(worst < 0.12, "a foot is {worst} m off the ground");
}

/// A walk leaves a trail about as wide as the figure's legs: the walker, with one collider
/// sphere per joint (`collider: Joints`: the thesis's interaction spheres, posed with the
/// walk), crosses a flat field along z = 0; a pressed blade's collision strength eta decays
/// in a fraction of a second, so each blade's largest eta over the walk is kept, and the
/// blades it pressed behind the walker lie in a band around its path. The feet are 0.2 m
/// apart (0.31 m from outer edge to outer edge). Measured on lavapipe: 258 of 5,965 blades
/// behind the walker pressed, 90 % of them within 0.29 m of the path (a trail 0.57 m wide:
/// the feet, the legs and the swinging hands), every blade within 0.15 m of it pressed, none
/// beyond 0.46 m; bounds: a half-width of 0.1 to 0.5 m, nothing pressed beyond 1 m.
#[test]
fn a_walk_leaves_a_trail_as_wide_as_the_legs() {
    let gpu = common::gpu();
    let sets = flat_walk_sets(format!(
        "(mesh: {:?}, animation: Some(\"walk\"), stride: 1.76, collider: Joints, \
         motion: Path(points: [(-5.0, 0.0), (5.0, 0.0)], speed: 1.4, looped: false))",
        walker()
    ));
    let size = (32, 18);
    let (_session, mut r, target, camera) = setup(&gpu, &sets, size);
    // The embedding's sphere budget counts what the frame places (the rigged joints and the
    // scene's colliders) without placing them.
    assert_eq!(
        r.scene_sphere_count(),
        r.frame_spheres().len() - r.dynamic_spheres.len()
    );
    assert!(r.scene_sphere_count() >= 9, "one sphere per joint");
    // 5 s: the walker covers 7 m, from x = -5 to x = 2.
    let most_eta = most_eta_over_150_frames(&gpu, &mut r, &target, &camera, |_| {});
    let (blades, _) = r.buffers.read(&gpu).expect("blades");
    // Behind the walker, away from where it started.
    let behind = |b: &sward::field::blade::Blade| (-3.5..0.5).contains(&b.v0_dir[0]);
    let pressed: Vec<f32> = blades
        .iter()
        .zip(&most_eta)
        .filter(|(b, &eta)| behind(b) && eta > 0.02)
        .map(|(b, _)| b.v0_dir[2].abs())
        .collect();
    let total = blades.iter().filter(|b| behind(b)).count();
    assert!(
        pressed.len() > 100,
        "{} of {total} blades pressed",
        pressed.len()
    );
    let mut sorted = pressed.clone();
    sorted.sort_by(f32::total_cmp);
    // The band holding 90 % of the pressed blades, each side of the path.
    let half = sorted[(sorted.len() * 9) / 10];
    let widest = sorted.last().copied().unwrap_or(0.0);
    let share_within = |d: f32| {
        let all = blades
            .iter()
            .filter(|b| behind(b) && b.v0_dir[2].abs() < d)
            .count();
        let hit = pressed.iter().filter(|&&z| z < d).count();
        hit as f32 / all.max(1) as f32
    };
    eprintln!(
        "{} of {total} blades behind the walker pressed; 90 % within {half:.2} m of the path \
         (a trail {:.2} m wide); {:.0} % of the blades within 0.15 m of it pressed; the \
         farthest {widest:.2} m away",
        pressed.len(),
        2.0 * half,
        100.0 * share_within(0.15)
    );
    assert!(
        (0.1..=0.5).contains(&half),
        "the trail's half-width is {half} m"
    );
    assert!(
        share_within(0.15) > 0.3,
        "the path itself is barely pressed"
    );
    assert!(widest < 1.0, "a blade {widest} m from the path was pressed");
}

/// Walk mode's steering reaches the grass (issue 29, point 2): the window's [`Walker`]
/// takes over the figure standing at (0, −4) facing +z, W walks it 5 s (accelerating to
/// 1.4 m/s: 6.8 m), and each frame its pose goes to the renderer as the window hands it
/// over (`Renderer::pose_object`). The blades it pressed lie along its walk (x = 0), none
/// beyond 1 m of it, and none more than 0.6 m ahead of where it stopped (its reach).
/// Measured on lavapipe: 500 blades pressed, 90 % within 0.28 m of x = 0, the farthest
/// 0.48 m; the walker ended at z = 2.83, the farthest pressed blade at z = 3.32.
#[test]
fn a_steered_walker_presses_the_grass_where_it_walks() {
    use sward_app::app::walker::{WalkInput, Walker};
    let gpu = common::gpu();
    let sets = flat_walk_sets(format!(
        "(mesh: {:?}, animation: Some(\"walk\"), stride: 1.76, collider: Joints, \
         translation: (0.0, 0.0, -4.0))",
        walker()
    ));
    let size = (32, 18);
    let (_session, mut r, target, camera) = setup(&gpu, &sets, size);
    let mut w = Walker::take(&r.scene, &r.terrain, r.time, |i| r.animation_duration(i))
        .expect("the figure is animated");
    assert!((w.facing() - glam::Vec2::Y).length() < 1e-4);
    let walk = WalkInput {
        forward: 1.0,
        ..WalkInput::default()
    };
    let most_eta = most_eta_over_150_frames(&gpu, &mut r, &target, &camera, |r| {
        w.step(walk, 1.0 / 30.0);
        r.pose_object(w.object, Some(w.pose(&r.terrain)))
            .expect("pose");
    });
    // A pose past the scene's objects, or with a NaN, is refused.
    assert!(r.pose_object(1, Some(w.pose(&r.terrain))).is_err());
    let mut bad = w.pose(&r.terrain);
    bad.origin.x = f32::NAN;
    assert!(r.pose_object(0, Some(bad)).is_err());
    let (blades, _) = r.buffers.read(&gpu).expect("blades");
    let pressed: Vec<[f32; 2]> = blades
        .iter()
        .zip(&most_eta)
        .filter(|(_, &eta)| eta > 0.02)
        .map(|(b, _)| [b.v0_dir[0], b.v0_dir[2]])
        .collect();
    let mut off: Vec<f32> = pressed.iter().map(|p| p[0].abs()).collect();
    off.sort_by(f32::total_cmp);
    let half = off.get(off.len() * 9 / 10).copied().unwrap_or(f32::MAX);
    let farthest_ahead = pressed.iter().map(|p| p[1]).fold(f32::MIN, f32::max);
    eprintln!(
        "{} blades pressed, 90 % within {half:.2} m of x = 0, the farthest {:.2} m; the \
         walker ended at z = {:.2}, the farthest pressed blade at z = {farthest_ahead:.2}",
        pressed.len(),
        off.last().copied().unwrap_or(0.0),
        w.position.y
    );
    assert!(pressed.len() > 100, "{} blades pressed", pressed.len());
    assert!(
        (0.05..=0.5).contains(&half),
        "the trail's half-width is {half}"
    );
    assert!(off.last().copied().unwrap_or(0.0) < 1.0, "{off:?}");
    assert!(
        (w.position.y - 2.8).abs() < 0.1,
        "the walker ended at {}",
        w.position
    );
    assert!(
        farthest_ahead < w.position.y + 0.6,
        "grass ahead of it was pressed"
    );
}
