//! Light and shadows (issue 16) against CPU references: the sky pass against the CPU twin
//! of Preetham's sky and the tone mappers; the sun's shadow map of a sphere over a plane
//! against a CPU ray cast; a render with shadows on and off differing exactly where the
//! CPU's ray test says the sphere shadows the ground; a ball's shadow moving with it; and
//! every blade shading term changing the picture.

mod common;

use glam::{Mat4, Vec3};
use sward::embed::GrassRenderer;
use sward::render::camera::CameraView;
use sward::render::light::{sky, tone};
use sward::scene::{BladeShadowLookup, HeightSource, Motion, Scene, Shading, Sphere, ToneMapping};
use sward::session::Session;

/// Renders `frames` frames of `scene` at `size` and returns the image and the renderer.
fn render(
    scene: Scene,
    size: (u32, u32),
    frames: u32,
) -> (image::RgbaImage, GrassRenderer, CameraView) {
    render_on(&common::gpu(), scene, size, frames)
}

fn render_on(
    gpu: &sward::gpu::Gpu,
    scene: Scene,
    size: (u32, u32),
    frames: u32,
) -> (image::RgbaImage, GrassRenderer, CameraView) {
    let session = Session::new(scene, None, Some(gpu)).expect("field");
    let camera = CameraView::from_scene(&session.scene.camera);
    let (r, target) = common::draw_frames(gpu, &session, size, frames as usize, false, |_| {});
    (target.read_image(gpu).expect("image"), r, camera)
}

/// The view ray through the centre of pixel (x, y).
fn pixel_ray(inv: Mat4, eye: Vec3, (x, y): (u32, u32), (w, h): (u32, u32)) -> Vec3 {
    let ndc = Vec3::new(
        (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
        1.0,
    );
    (inv.project_point3(ndc) - eye).normalize()
}

fn sky_scene(hours: f32, mapper: ToneMapping) -> Scene {
    let mut s = Scene::default();
    s.render.msaa = 1;
    s.light.time_of_day = Some(hours);
    s.light.tone_mapping = mapper;
    s.light.north = 200.0;
    // Looking 45° up: only sky in view.
    s.camera.eye = (0.0, 5.0, 0.0);
    s.camera.target = (4.0, 15.0, 8.0);
    s
}

/// The sky pass against `PreethamSky::radiance` + tone mapping + sRGB, pixel by pixel (every
/// 7th), away from the sun's disk: within 3/255 (f32 on the GPU against f32 here, through
/// exp, acos and the mappers' rational curves).
#[test]
fn sky_matches_its_cpu_twin() {
    let size = (96, 64);
    for (hours, mapper) in [(11.0, ToneMapping::Aces), (18.5, ToneMapping::Agx)] {
        let scene = sky_scene(hours, mapper);
        let sun = sward::render::light::sun::scene_sun(&scene);
        let preetham = sky::PreethamSky::new(sun, scene.light.turbidity);
        let multiplier = tone::exposure_multiplier(mapper, scene.light.exposure);
        let (image, _, camera) = render(scene.clone(), size, 1);
        let inv = camera.view_proj(size.0 as f32 / size.1 as f32).inverse();
        let mut worst = 0i32;
        let mut checked = 0;
        for y in (0..size.1).step_by(7) {
            for x in (0..size.0).step_by(7) {
                let dir = pixel_ray(inv, camera.eye, (x, y), size);
                if dir.dot(sun) > 0.999 {
                    continue;
                }
                let c = tone::tonemap(preetham.radiance(dir, Vec3::ZERO), mapper, multiplier);
                let want = [tone::srgb8(c.x), tone::srgb8(c.y), tone::srgb8(c.z)];
                let got = image.get_pixel(x, y).0;
                for ch in 0..3 {
                    worst = worst.max((want[ch] as i32 - got[ch] as i32).abs());
                }
                checked += 1;
            }
        }
        assert!(checked > 80, "{checked}");
        assert!(
            worst <= 3,
            "{hours} h {mapper:?}: worst channel difference {worst}/255"
        );
    }
}

/// A flat plane with a sphere above it and no grass in the way (distance culling on, the
/// blades culled at 1 cm: none is drawn or casts), the sun fixed.
fn sphere_over_plane(shadows: bool) -> Scene {
    let mut s = Scene::default();
    s.render.msaa = 1;
    s.terrain.height = HeightSource::Flat;
    s.terrain.size = 16.0;
    s.field.tile_size = 0.0;
    s.field.density = 1.0;
    s.culling.distance = true;
    s.culling.max_distance = 0.01;
    s.render.sun_direction = (0.35, 0.8, 0.25);
    s.light.time_of_day = None;
    s.light.shadows.enabled = shadows;
    s.light.shadows.distance = 30.0;
    s.light.shadows.cascades = 2;
    s.light.shadows.softness = 1.0;
    s.colliders = vec![Sphere {
        center: (0.0, 1.5, 0.0),
        radius: 0.7,
        motion: Motion::Static,
    }];
    s.wind.directional = None;
    s.camera.eye = (0.5, 4.5, 4.5);
    s.camera.target = (-0.5, 0.0, -1.0);
    s.camera.fov_y = 50.0;
    s
}

const CENTRE: Vec3 = Vec3::new(0.0, 1.5, 0.0);
const RADIUS: f32 = 0.7;

/// Distance of `p`'s sun ray from the sphere's surface (negative inside the shadow).
fn shadow_margin(p: Vec3, sun: Vec3) -> f32 {
    let to_c = CENTRE - p;
    let along = to_c.dot(sun);
    if along <= 0.0 {
        return f32::INFINITY;
    }
    (to_c - sun * along).length() - RADIUS
}

/// The first cascade's depth map against the CPU: for every 4th texel, the ray from the
/// sun through the texel's centre meets the sphere at the depth the map holds (within 2 cm
/// of depth along the sun, plus the pipeline's slope bias and the sphere's tessellation,
/// both growing with the slope), except where the sun grazes the sphere; where it misses
/// the sphere the map is still clear, because flat ground shadows nothing
/// (`HeightField::may_shadow`) and is left out of the maps.
#[test]
fn shadow_map_matches_a_cpu_ray_cast() {
    let gpu = common::gpu();
    let (_, r, _) = render_on(&gpu, sphere_over_plane(true), (128, 96), 1);
    let u = *r.light().uniforms();
    assert_eq!(u.shadow[0], 1.0);
    let scene = sphere_over_plane(true);
    let ground = sward::field::HeightField::from_scene(&scene.terrain).unwrap();
    let sun = Vec3::from(scene.render.sun_direction).normalize();
    assert!(!ground.may_shadow(sun.y));
    let (res, depths) = r.light().read_cascade(&gpu, 0).expect("shadow map");
    let vp = Mat4::from_cols_array_2d(&u.cascades[0]);
    let inv = vp.inverse();
    let texel = u.texel_world[0];
    let (mut sphere_hits, mut plane_hits, mut checked) = (0, 0, 0);
    for ty in (0..res).step_by(4) {
        for tx in (0..res).step_by(4) {
            let ndc_x = (tx as f32 + 0.5) / res as f32 * 2.0 - 1.0;
            let ndc_y = 1.0 - (ty as f32 + 0.5) / res as f32 * 2.0;
            let start = inv.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
            let end = inv.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
            let dir = (end - start).normalize();
            // The ray against the sphere, then the plane y = 0.
            let oc = start - CENTRE;
            let b = oc.dot(dir);
            let c = oc.length_squared() - RADIUS * RADIUS;
            let disc = b * b - c;
            let closest = (oc - dir * oc.dot(dir)).length();
            // The silhouette, within 1.5 texels or the drawn sphere's tessellation (1.5 %).
            if (closest - RADIUS).abs() < (1.5 * texel).max(0.015 * RADIUS) {
                continue;
            }
            if disc <= 0.0 {
                let hit = start + dir * (-start.y / dir.y);
                if hit.x.abs().max(hit.z.abs()) <= 7.8 {
                    let got = depths[(ty * res + tx) as usize];
                    assert_eq!(got, 1.0, "texel ({tx}, {ty}): the flat ground was drawn");
                    plane_hits += 1;
                    checked += 1;
                }
                continue;
            }
            sphere_hits += 1;
            let t = -b - disc.sqrt();
            // The pipeline's depth bias (1.5 texels of slope) and a texel of rasterising
            // grow with the surface's slope to the sun.
            let n = (start + dir * t - CENTRE) / RADIUS;
            let slope = 1.0 / n.dot(-dir).max(0.05);
            // Grazing the sphere (over 70° from its normal) the facets' depth departs from
            // the sphere's faster than any texel tolerance: those texels are left out.
            if slope > 3.0 {
                continue;
            }
            let hit = start + dir * t;
            let want = vp.project_point3(hit).z;
            // A point outside the cascade's depth range is outside its slice too.
            if !(0.0..=1.0).contains(&want) {
                continue;
            }
            let got = depths[(ty * res + tx) as usize];
            let depth_range = (end - start).length();
            let err_m = (got - want).abs() * depth_range;
            // The drawn sphere is 16 x 24 facets: up to 0.86 % of the radius inside, along
            // the ray that much over the slope.
            let tessellation = 0.0086 * RADIUS;
            assert!(
                err_m < 0.02 + (3.0 * texel + tessellation) * slope,
                "texel ({tx}, {ty}): {got} vs {want} ({err_m} m, slope {slope}, texel {texel} m)"
            );
            checked += 1;
        }
    }
    assert!(
        sphere_hits > 20 && plane_hits > 1000,
        "{sphere_hits} {plane_hits}"
    );
    assert!(checked > 1000);
}

/// Shadows on against off: the ground darkens exactly where the CPU's ray test puts it in
/// the sphere's shadow. Pixels within 6 cm of the shadow's edge (the filter's soft band)
/// are left out; of the rest, at least 99.5 % agree.
#[test]
fn shadowed_pixels_are_where_the_cpu_says() {
    let size = (160, 120);
    let (on, _, camera) = render(sphere_over_plane(true), size, 1);
    let (off, _, _) = render(sphere_over_plane(false), size, 1);
    let sun = Vec3::new(0.35, 0.8, 0.25).normalize();
    let inv = camera.view_proj(size.0 as f32 / size.1 as f32).inverse();
    let lum = |p: &image::Rgba<u8>| p.0[0] as f32 + p.0[1] as f32 + p.0[2] as f32;
    let (mut agree, mut total, mut shadowed) = (0, 0, 0);
    for y in 0..size.1 {
        for x in 0..size.0 {
            let dir = pixel_ray(inv, camera.eye, (x, y), size);
            // Pixels showing the sphere itself are left out.
            let oc = camera.eye - CENTRE;
            let b = oc.dot(dir);
            if b * b - (oc.length_squared() - (RADIUS + 0.05).powi(2)) > 0.0 {
                continue;
            }
            if dir.y >= -1e-3 {
                continue;
            }
            let p = camera.eye + dir * (-camera.eye.y / dir.y);
            let margin = shadow_margin(p, sun);
            if margin.abs() < 0.06 {
                continue;
            }
            let cpu = margin < 0.0;
            let gpu = lum(on.get_pixel(x, y)) < 0.8 * lum(off.get_pixel(x, y));
            total += 1;
            shadowed += cpu as u32;
            agree += (cpu == gpu) as u32;
        }
    }
    assert!(shadowed > 200, "the shadow covers {shadowed} pixels");
    let share = agree as f32 / total as f32;
    assert!(share >= 0.995, "{agree} of {total} pixels agree ({share})");
}

/// A ball rolling over the grass: its shadow (the on/off difference) moves with it, as far
/// as the CPU's shadow of the ball moves on the ground between the two frames.
#[test]
fn a_balls_shadow_moves_with_it() {
    let size = (160, 100);
    let base = |shadows: bool, frames_at: f32| {
        let mut s = common::still_scene();
        s.render.msaa = 1;
        s.terrain.height = HeightSource::Flat;
        s.terrain.size = 16.0;
        s.field.tile_size = 0.0;
        s.render.sun_direction = (0.3, 0.85, 0.2);
        s.light.shadows.enabled = shadows;
        // The ball's shadow alone: the blades cast none (from its first frame they would).
        s.light.shadows.grass_radius = 0.0;
        s.colliders = vec![Sphere {
            center: (-2.0 + frames_at, 1.2, 0.0),
            radius: 0.5,
            motion: Motion::Static,
        }];
        s.camera.eye = (0.0, 6.0, 6.0);
        s.camera.target = (0.0, 0.0, 0.0);
        s
    };
    let centroid = |at: f32| {
        let (on, _, _) = render(base(true, at), size, 1);
        let (off, _, _) = render(base(false, at), size, 1);
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
        for (x, y, p) in on.enumerate_pixels() {
            let q = off.get_pixel(x, y);
            let l = |c: &image::Rgba<u8>| c.0[0] as f32 + c.0[1] as f32 + c.0[2] as f32;
            if l(p) < 0.8 * l(q) {
                sx += x as f32;
                sy += y as f32;
                n += 1.0;
            }
        }
        assert!(n > 30.0, "a shadow at {at}: {n} pixels");
        (sx / n, sy / n)
    };
    let a = centroid(0.0);
    let b = centroid(3.0);
    // The ground's shadow centre: the ball's centre projected along the sun onto y = 0.
    let sun = Vec3::new(0.3, 0.85, 0.2).normalize();
    let on_ground = |x: f32| Vec3::new(x, 1.2, 0.0) - sun * (1.2 / sun.y);
    let camera = CameraView::from_scene(&base(true, 0.0).camera);
    let vp = camera.view_proj(size.0 as f32 / size.1 as f32);
    let screen = |p: Vec3| {
        let c = vp.project_point3(p);
        (
            (c.x * 0.5 + 0.5) * size.0 as f32,
            (0.5 - c.y * 0.5) * size.1 as f32,
        )
    };
    let (pa, pb) = (screen(on_ground(-2.0)), screen(on_ground(1.0)));
    let moved = (b.0 - a.0, b.1 - a.1);
    let want = (pb.0 - pa.0, pb.1 - pa.1);
    let err = ((moved.0 - want.0).powi(2) + (moved.1 - want.1).powi(2)).sqrt();
    let len = (want.0.powi(2) + want.1.powi(2)).sqrt();
    // The grass stands in the shadow at varying heights: within a fifth of the move.
    assert!(err < 0.2 * len, "moved {moved:?}, CPU {want:?}");
}

/// Each blade shading term, switched off, changes the picture of a windy meadow seen close
/// up (mean absolute difference per channel over 0.3 of 255): none does nothing.
#[test]
fn every_shading_term_changes_the_picture() {
    let size = (128, 80);
    let scene = || {
        let mut s = Scene::default();
        s.render.msaa = 1;
        s.field.tile_size = 0.0;
        s.terrain.size = 12.0;
        s.culling.max_distance = 14.0;
        // A low sun behind the camera's left: the blades' sheen faces the camera, and the
        // backs of half the blades face the sun (translucency).
        s.render.sun_direction = (-0.6, 0.4, 0.5);
        s.camera.eye = (-3.0, 1.4, 3.0);
        s.camera.target = (1.0, 0.2, -1.0);
        s
    };
    let (all, _, _) = render(scene(), size, 8);
    // Translucency shows against a sun ahead of the camera.
    let mut ahead = scene();
    ahead.render.sun_direction = (0.5, 0.45, -0.6);
    let (all_ahead, _, _) = render(ahead.clone(), size, 8);
    for name in Shading::NAMES {
        let (mut s, all) = if name == "translucency" {
            (ahead.clone(), &all_ahead)
        } else {
            (scene(), &all)
        };
        *s.light.shading.term_mut(name).expect("term") = 0.0;
        let (without, _, _) = render(s, size, 8);
        let diff = sward::compare::compare(all, &without).expect("same size");
        assert!(
            diff.mean > 0.3,
            "{name} off changes the picture by only {:.3}",
            diff.mean
        );
    }
}

/// The bunny at its reference view (`assets/scenes/bunny_meadow.ron`), the sun to its right
/// and ahead of the camera:
/// its shadow lies on the grass where the CPU says. The CPU casts every vertex of the mesh
/// along the sun onto the terrain, lifted by 0 to 0.6 m (the blades' heights, whose points
/// take the shadow), and projects the hits to the screen: the footprint. Shadows on against
/// off (the grass casting none, so only the bunny and the ground cast), the pixels darkened
/// by over 8 % away from the bunny itself lie in that footprint, and the footprint at half the grass's
/// height is darkened wherever a blade there faced the sun.
#[test]
fn the_bunnys_shadow_lies_on_the_grass() {
    let size = (240u32, 135u32);
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/bunny_meadow.ron");
    let scene = |shadows: bool| {
        let mut s = sward::scene::load_scene(&path).expect("bunny_meadow.ron");
        s.render.msaa = 1;
        s.light.time_of_day = None;
        s.render.sun_direction = (0.8, 0.7, -0.6);
        s.light.shadows.enabled = shadows;
        s.light.shadows.grass_radius = 0.0;
        s
    };
    let gpu = common::gpu();
    let (on, _, camera) = render_on(&gpu, scene(true), size, 2);
    let (off, _, _) = render_on(&gpu, scene(false), size, 2);

    let session = Session::new(scene(true), None, None).expect("session");
    let model = session.scene.objects[0].transform();
    let sun = Vec3::from(session.scene.render.sun_direction).normalize();
    let vp = camera.view_proj(size.0 as f32 / size.1 as f32);
    let (w, h) = (size.0 as i32, size.1 as i32);
    let pixel = |p: Vec3| {
        let c = vp.project_point3(p);
        (
            ((c.x * 0.5 + 0.5) * size.0 as f32) as i32,
            ((0.5 - c.y * 0.5) * size.1 as f32) as i32,
        )
    };
    // Marks the pixels within `r` of the projected points.
    let splat = |mask: &mut Vec<bool>, points: &[Vec3], r: i32| {
        for &p in points {
            let (x, y) = pixel(p);
            for dy in -r..=r {
                for dx in -r..=r {
                    let (px, py) = (x + dx, y + dy);
                    if px >= 0 && py >= 0 && px < w && py < h {
                        mask[(py * w + px) as usize] = true;
                    }
                }
            }
        }
    };
    let vertices: Vec<Vec3> = session.meshes[0]
        .positions
        .iter()
        .map(|p| model.transform_point3(Vec3::from(*p)))
        .collect();
    // Where the sun ray back from `p` meets the terrain lifted by `lift` (fixed-point
    // iteration on the smooth height field).
    let cast = |p: Vec3, lift: f32| {
        let mut t = 0.0;
        for _ in 0..12 {
            let q = p - sun * t;
            t = (p.y - session.terrain.height(q.x, q.z) - lift).max(0.0) / sun.y;
        }
        p - sun * t
    };
    let footprint = |lifts: &[f32], r: i32| {
        let mut mask = vec![false; (w * h) as usize];
        for &lift in lifts {
            let hits: Vec<Vec3> = vertices.iter().map(|&p| cast(p, lift)).collect();
            splat(&mut mask, &hits, r);
        }
        mask
    };
    let mut bunny = vec![false; (w * h) as usize];
    splat(&mut bunny, &vertices, 3);
    let anywhere = footprint(&[0.0, 0.15, 0.3, 0.45, 0.6], 3);
    let middle = footprint(&[0.3], 0);

    let luma = |c: &image::Rgba<u8>| c.0[0] as f32 + c.0[1] as f32 + c.0[2] as f32;
    let (mut dark, mut dark_inside, mut mid, mut mid_dark) = (0, 0, 0, 0);
    for (x, y, p) in on.enumerate_pixels() {
        let i = (y as i32 * w + x as i32) as usize;
        if bunny[i] {
            continue;
        }
        let darkened = luma(p) < 0.92 * luma(off.get_pixel(x, y));
        if darkened {
            dark += 1;
            dark_inside += anywhere[i] as u32;
        }
        if middle[i] {
            mid += 1;
            mid_dark += darkened as u32;
        }
    }
    println!(
        "bunny shadow: {dark} darkened pixels, {dark_inside} in the CPU's footprint; \
         {mid_dark} of {mid} footprint pixels at half height darkened"
    );
    assert!(dark > 80, "the bunny casts a shadow of {dark} pixels");
    let inside = dark_inside as f32 / dark as f32;
    assert!(
        inside >= 0.9,
        "{dark_inside} of {dark} darkened pixels in the footprint"
    );
    assert!(mid > 60, "the footprint covers {mid} pixels");
    // Measured 44 %: a blade whose side towards the camera faces away from the sun takes no
    // direct sun even in the light, so the shadow cannot darken it.
    let covered = mid_dark as f32 / mid as f32;
    assert!(
        covered >= 0.3,
        "{mid_dark} of {mid} footprint pixels darkened"
    );
}

/// The sun along the drawn blades (`blade_sun_points` in `grass_vis.wgsl`, which the
/// deferred shading interpolates per pixel with `light.shadows.blade_lookup: PerRow`) against a CPU ray cast: still
/// grass under a sphere, the grass casting no shadow of its own. Each drawn blade is
/// looked up at as many points along its curve as its level's mesh has rows (at most
/// `SUN_POINTS`), and its `SUN_POINTS` packed values are those points' visibilities
/// between them. The CPU does the same with the ray's answer (1 lit, 0 shadowed): every
/// packed value must be on the same side of one half (values whose two points lie within
/// 6 cm of the shadow's edge, the filter's soft band, left out), and the CPU twin of the
/// shading's lookup (`deferred::sun_at`) must read the packed values back at their heights
/// and halfway between them. A pass that wrote nothing (all zero: shadowed) or the wrong
/// blades fails the ray test; one that packed the points tip first fails it along the
/// blades' length.
#[test]
fn the_sun_along_the_drawn_blades_matches_a_ray_cast() {
    use sward::render::deferred::{sun_at, SUN_POINTS};
    let gpu = common::gpu();
    // The sphere over the plane, now with still blades, none culled by distance.
    let mut s = sphere_over_plane(true);
    s.render.taa = false;
    s.field.density = 30.0;
    s.culling.distance = false;
    s.light.shadows.grass_radius = 0.0;
    s.light.shadows.blade_lookup = BladeShadowLookup::PerRow;
    s.physics.gravity_acceleration = 0.0;
    s.physics.gravity_center_acceleration = 0.0;
    let segments = sward::render::mesh::lod_segments(s.field.segments);
    let session = Session::new(s, None, Some(&gpu)).expect("field");
    let (r, _) = common::draw_frames(&gpu, &session, (160, 120), 2, false, |_| {});
    assert!(
        r.grass_deferred(),
        "one sample per pixel takes the deferred path"
    );
    let (blades, _) = r.buffers.read(&gpu).expect("blades");
    let words = r.buffers.read_sun(&gpu).expect("sun");
    let levels = r
        .cull
        .read_visible_levels(&gpu, &r.buffers)
        .expect("visible");
    let sun = Vec3::new(0.35, 0.8, 0.25).normalize();
    let last = (SUN_POINTS - 1) as f32;
    let (mut agree, mut total, mut shadowed, mut drawn) = (0u32, 0u32, 0u32, 0usize);
    for (level, list) in levels.iter().enumerate() {
        let points = (segments[level] + 1).min(SUN_POINTS);
        let steps = (points - 1) as f32;
        drawn += list.len();
        for &i in list {
            let b = blades[i as usize];
            let w = words[i as usize];
            let (v0, v1, v2) = (
                Vec3::from_slice(&b.v0_dir[..3]),
                Vec3::from_slice(&b.v1_height[..3]),
                Vec3::from_slice(&b.v2_width[..3]),
            );
            // The ray's margin at each looked-up point of Jahrmann's quadratic (Eq. 21).
            let margins: Vec<f32> = (0..points)
                .map(|k| {
                    let v = k as f32 / steps;
                    shadow_margin(v0.lerp(v1, v).lerp(v1.lerp(v2, v), v), sun)
                })
                .collect();
            let byte = |j: u32| ((w[(j / 4) as usize] >> (8 * (j % 4))) & 0xff) as f32 / 255.0;
            for j in 0..SUN_POINTS {
                assert_eq!(sun_at(w, j as f32 / last), byte(j), "blade {i} value {j}");
                if j + 1 < SUN_POINTS {
                    let mid = 0.5 * (byte(j) + byte(j + 1));
                    let at = sun_at(w, (j as f32 + 0.5) / last);
                    assert!((at - mid).abs() < 1e-6, "blade {i} after value {j}");
                }
                let x = j as f32 * steps / last;
                let k = (x as usize).min(points as usize - 2);
                let (a, c) = (margins[k], margins[k + 1]);
                if a.abs() < 0.06 || c.abs() < 0.06 {
                    continue;
                }
                let lit = |m: f32| if m < 0.0 { 0.0 } else { 1.0 };
                let cpu = lit(a) + (lit(c) - lit(a)) * (x - k as f32);
                if (cpu - 0.5).abs() < 0.05 {
                    continue;
                }
                total += 1;
                shadowed += (cpu < 0.5) as u32;
                agree += ((cpu < 0.5) == (byte(j) < 0.5)) as u32;
            }
        }
    }
    assert!(drawn > 500, "{drawn} blades drawn");
    // Measured on lavapipe: all 25,285 values agree, 309 of them shadowed; with the points
    // looked up tip first, 45 disagree.
    assert!(
        shadowed > 200,
        "{shadowed} packed values of drawn blades in the shadow"
    );
    assert!(
        total - agree <= total / 4000,
        "{agree} of {total} packed values agree"
    );
}

/// The blades cast their shadows from their first frame, in a whole field and in streamed
/// tiles: the grass casters are the cull's early lists, drawn before the late occlusion
/// test, and new blades start as seen (`SEEN_YES`), so they are drawn early. Before, every
/// blade of a first frame waited for the late test and cast nothing: the frame was the
/// same to the byte with the grass casting no shadow (`grass_radius` 0).
#[test]
fn the_blades_cast_shadows_from_their_first_frame() {
    let gpu = common::gpu();
    for tile_size in [0.0, 8.0] {
        let frame = |grass_radius: f32| {
            let mut s = Scene::default();
            s.render.msaa = 1;
            s.field.tile_size = tile_size;
            s.light.shadows.grass_radius = grass_radius;
            render_on(&gpu, s, (160, 90), 1).0
        };
        let (casting, none) = (frame(25.0), frame(0.0));
        let sum: u64 = casting
            .pixels()
            .zip(none.pixels())
            .map(|(a, b)| (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>())
            .sum();
        let mean = sum as f64 / (3 * 160 * 90) as f64;
        println!("tiles of {tile_size} m: the grass's shadows change the first frame by {mean:.2} levels");
        // Measured on lavapipe: 2.05 (whole field) and 2.04 (tiles); 0.00 for both before.
        assert!(mean > 0.5, "tiles of {tile_size} m: {mean:.2} levels");
    }
}

/// The far light's canopy table (`light::canopy`) is summed once for the field, not once
/// per frame: after six frames the light pass summed it once, and the uniforms it drew
/// the frame with hold the table `light::uniforms` sums for the same scene.
#[test]
fn the_canopy_table_is_summed_once_for_the_field() {
    let mut scene = Scene::default();
    scene.render.msaa = 1;
    let sun = sward::render::light::sun::scene_sun(&scene);
    let expected = sward::render::light::uniforms(&scene, sun).canopy;
    let (_, r, _) = render(scene, (32, 18), 6);
    assert_eq!(r.light().canopy_sums(), 1);
    assert_eq!(r.light().uniforms().canopy, expected);
}
